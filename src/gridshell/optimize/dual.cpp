#include "gridshell/optimize/dual.h"

#include <map>
#include <utility>

#include "gridshell/core/error.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

DualMesh dual_polygon_mesh(const TriMesh& m, double corner_angle_deg) {
  const int nv = m.num_vertices(), nf = m.num_faces();
  // Directed edge (a, b) → face that walks it.
  std::map<std::pair<int, int>, int> dir;
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const auto key = std::make_pair(m.F(f, k), m.F(f, (k + 1) % 3));
      if (!dir.emplace(key, f).second)
        throw Error("surface", "non-manifold or inconsistently oriented mesh");
    }
  auto face_of = [&](int a, int b) {
    auto it = dir.find({a, b});
    return it == dir.end() ? -1 : it->second;
  };
  auto corner_index = [&](int f, int v) {
    for (int k = 0; k < 3; ++k)
      if (m.F(f, k) == v) return k;
    return -1;
  };
  std::vector<std::vector<int>> vf(nv);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) vf[m.F(f, k)].push_back(f);

  const Topology topo = build_topology(m);
  const std::vector<char> is_corner = boundary_corners(m.V, topo.boundary_loops, corner_angle_deg);

  DualMesh d;
  std::vector<Vec3> pts;
  for (int f = 0; f < nf; ++f)
    pts.push_back((m.vertex(m.F(f, 0)) + m.vertex(m.F(f, 1)) + m.vertex(m.F(f, 2))) / 3.0);
  d.on_boundary.assign(nf, 0);
  d.corner.assign(nf, 0);
  std::map<std::pair<int, int>, int> midpoint;  // undirected boundary edge → polygon vertex
  auto mid = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    auto it = midpoint.find(key);
    if (it != midpoint.end()) return it->second;
    const int id = static_cast<int>(pts.size());
    pts.push_back(0.5 * (m.vertex(a) + m.vertex(b)));
    d.on_boundary.push_back(1);
    d.corner.push_back(0);
    midpoint.emplace(key, id);
    return id;
  };
  std::vector<int> corner_id(nv, -1);
  for (int v = 0; v < nv; ++v) {
    if (vf[v].empty()) continue;
    // Start face: for an interior vertex any; for a boundary vertex the face f = (v, a, b)
    // whose edge v→a has no twin (walking counter-clockwise around v ends at the other side).
    int start = vf[v][0];
    bool boundary = false;
    for (int f : vf[v]) {
      const int a = m.F(f, (corner_index(f, v) + 1) % 3);
      if (face_of(a, v) < 0) {
        start = f;
        boundary = true;
        break;
      }
    }
    std::vector<int> poly;
    if (boundary) {
      if (is_corner[v]) {
        corner_id[v] = static_cast<int>(pts.size());
        pts.push_back(m.vertex(v));
        d.on_boundary.push_back(1);
        d.corner.push_back(1);
        poly.push_back(corner_id[v]);
      }
      poly.push_back(mid(v, m.F(start, (corner_index(start, v) + 1) % 3)));
    }
    int f = start;
    for (std::size_t guard = 0; guard <= vf[v].size(); ++guard) {
      poly.push_back(f);
      const int b = m.F(f, (corner_index(f, v) + 2) % 3);
      const int next = face_of(v, b);
      if (next < 0) {
        if (!boundary) throw Error("surface", "non-manifold vertex");
        poly.push_back(mid(v, b));
        break;
      }
      if (next == start) break;
      f = next;
    }
    if (poly.size() >= 3) d.mesh.faces.push_back(std::move(poly));
  }
  d.mesh.V = to_points(pts);
  return d;
}

}  // namespace gridshell
