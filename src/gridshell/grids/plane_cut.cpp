#include "gridshell/grids/plane_cut.h"

#include <map>

namespace gridshell {

CutMesh make_cut_mesh(const Surface& surface) {
  CutMesh m;
  m.mesh = surface.mesh;
  m.support.assign(surface.mesh.num_vertices(), 0);
  for (int v : surface.supports) m.support[v] = 1;
  m.parent_face.resize(surface.mesh.num_faces());
  for (int f = 0; f < surface.mesh.num_faces(); ++f) m.parent_face[f] = f;
  return m;
}

void cut_along_plane(CutMesh& m, const Plane& plane, double snap) {
  const int nv = m.mesh.num_vertices();
  std::vector<double> s(nv);
  for (int v = 0; v < nv; ++v) {
    s[v] = plane.signed_distance(m.mesh.vertex(v));
    if (std::abs(s[v]) <= snap) {
      m.mesh.V.row(v) -= s[v] * plane.normal.transpose();
      s[v] = 0;
    }
  }
  std::vector<Vec3> new_points;
  std::vector<char> new_support;
  std::map<std::pair<int, int>, int> edge_vertex;
  auto crossing = [&](int a, int b) {
    auto key = std::minmax(a, b);
    auto it = edge_vertex.find(key);
    if (it != edge_vertex.end()) return it->second;
    const double t = s[a] / (s[a] - s[b]);
    Vec3 p = (1 - t) * m.mesh.vertex(a) + t * m.mesh.vertex(b);
    p -= plane.signed_distance(p) * plane.normal;  // exactly on the plane
    const int id = nv + static_cast<int>(new_points.size());
    new_points.push_back(p);
    new_support.push_back(m.support[a] && m.support[b]);
    edge_vertex.emplace(key, id);
    return id;
  };
  std::vector<std::array<int, 3>> faces;
  std::vector<int> parents;
  auto emit = [&](int a, int b, int c, int parent) {
    faces.push_back({a, b, c});
    parents.push_back(parent);
  };
  for (int f = 0; f < m.mesh.num_faces(); ++f) {
    int v[3] = {m.mesh.F(f, 0), m.mesh.F(f, 1), m.mesh.F(f, 2)};
    const int parent = m.parent_face[f];
    int pos = 0, neg = 0;
    for (int k = 0; k < 3; ++k) pos += s[v[k]] > 0, neg += s[v[k]] < 0;
    if (pos == 0 || neg == 0) {
      emit(v[0], v[1], v[2], parent);
      continue;
    }
    // Rotate so that v[0] is the vertex alone on its side (or the one on the plane).
    int lone = -1;
    for (int k = 0; k < 3; ++k) {
      const int sk = (s[v[k]] > 0) - (s[v[k]] < 0);
      const int s1 = (s[v[(k + 1) % 3]] > 0) - (s[v[(k + 1) % 3]] < 0);
      const int s2 = (s[v[(k + 2) % 3]] > 0) - (s[v[(k + 2) % 3]] < 0);
      if (sk == 0 && s1 * s2 < 0) lone = k;             // one vertex on the plane
      if (sk != 0 && s1 == -sk && s2 == -sk) lone = k;  // one against two
    }
    const int a = v[lone], b = v[(lone + 1) % 3], c = v[(lone + 2) % 3];
    if (s[a] == 0) {  // the plane runs through a and crosses bc
      const int p = crossing(b, c);
      emit(a, b, p, parent);
      emit(a, p, c, parent);
    } else {  // a alone on one side: ab and ac cross
      const int p = crossing(a, b), q = crossing(a, c);
      emit(a, p, q, parent);
      emit(p, b, c, parent);
      emit(p, c, q, parent);
    }
  }
  const int total = nv + static_cast<int>(new_points.size());
  m.mesh.V.conservativeResize(total, 3);
  for (std::size_t i = 0; i < new_points.size(); ++i) {
    m.mesh.V.row(nv + static_cast<int>(i)) = new_points[i].transpose();
    m.support.push_back(new_support[i]);
  }
  m.mesh.F.resize(static_cast<int>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    m.mesh.F.row(static_cast<int>(f)) << faces[f][0], faces[f][1], faces[f][2];
  m.parent_face = std::move(parents);
}

std::vector<int> keep_side(CutMesh& m, const Plane& plane) {
  const int nv = m.mesh.num_vertices();
  std::vector<int> new_id(nv, -1), old_id;
  std::vector<std::array<int, 3>> faces;
  std::vector<int> parents;
  for (int f = 0; f < m.mesh.num_faces(); ++f) {
    Vec3 centroid = Vec3::Zero();
    for (int k = 0; k < 3; ++k) centroid += m.mesh.vertex(m.mesh.F(f, k)) / 3;
    if (plane.signed_distance(centroid) < 0) continue;
    std::array<int, 3> t;
    for (int k = 0; k < 3; ++k) {
      int& id = new_id[m.mesh.F(f, k)];
      if (id < 0) {
        id = static_cast<int>(old_id.size());
        old_id.push_back(m.mesh.F(f, k));
      }
      t[k] = id;
    }
    faces.push_back(t);
    parents.push_back(m.parent_face[f]);
  }
  CutMesh out;
  out.mesh.V.resize(static_cast<int>(old_id.size()), 3);
  out.support.resize(old_id.size());
  for (std::size_t i = 0; i < old_id.size(); ++i) {
    out.mesh.V.row(static_cast<int>(i)) = m.mesh.V.row(old_id[i]);
    out.support[i] = m.support[old_id[i]];
  }
  out.mesh.F.resize(static_cast<int>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    out.mesh.F.row(static_cast<int>(f)) << faces[f][0], faces[f][1], faces[f][2];
  out.parent_face = std::move(parents);
  m = std::move(out);
  return old_id;
}

}  // namespace gridshell
