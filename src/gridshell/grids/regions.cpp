#include "gridshell/grids/regions.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "gridshell/core/error.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

namespace {

struct Labelling {
  std::vector<int> region;  // per face
  int count = 0;
};

/// Connected components of equally-labelled faces.
Labelling components(const Topology& t, const std::vector<int>& label, int nf) {
  DisjointSets sets(nf);
  for (const auto& ef : t.edge_faces)
    if (ef.size() == 2 && label[ef[0]] == label[ef[1]]) sets.unite(ef[0], ef[1]);
  Labelling l;
  l.region.assign(nf, -1);
  std::map<int, int> ids;
  for (int f = 0; f < nf; ++f) {
    auto [it, inserted] = ids.emplace(sets.find(f), l.count);
    if (inserted) ++l.count;
    l.region[f] = it->second;
  }
  return l;
}

/// Border length between each pair of neighbouring regions.
std::vector<std::map<int, double>> region_borders(const TriMesh& mesh, const Topology& t,
                                                  const Labelling& l) {
  std::vector<std::map<int, double>> border(l.count);
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    const auto& ef = t.edge_faces[e];
    if (ef.size() != 2) continue;
    const int ra = l.region[ef[0]], rb = l.region[ef[1]];
    if (ra == rb) continue;
    const double len = (mesh.vertex(t.edges[e][0]) - mesh.vertex(t.edges[e][1])).norm();
    border[ra][rb] += len;
    border[rb][ra] += len;
  }
  return border;
}

/// Junctions: vertices where three regions meet, or two on the mesh boundary, and corners.
std::vector<char> junctions(const Topology& t, const Labelling& l, const std::vector<char>& corner) {
  const int nv = static_cast<int>(t.vertex_faces.size());
  std::vector<char> junction(nv, 0);
  for (int v = 0; v < nv; ++v) {
    std::set<int> rs;
    for (int f : t.vertex_faces[v]) rs.insert(l.region[f]);
    junction[v] = rs.size() >= 3 || (t.on_boundary[v] && rs.size() >= 2) || corner[v];
  }
  return junction;
}

/// Each region's polygon: the junctions along its boundary loop. bad[r] when the region is not
/// a disk (pinched, or more than one loop) or has fewer than 3 junctions.
struct RegionPolygons {
  std::vector<std::vector<int>> polygon;
  std::vector<char> bad;
};

RegionPolygons region_polygons(const TriMesh& mesh, const Topology& t, const Labelling& l,
                               const std::vector<char>& junction) {
  // Boundary half-edges of each region.
  std::vector<std::multimap<int, int>> next(l.count);
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      const int e = t.find_edge(a, b);
      const auto& ef = t.edge_faces[e];
      const int g = ef.size() == 2 ? (ef[0] == f ? ef[1] : ef[0]) : -1;
      if (g < 0 || l.region[g] != l.region[f]) next[l.region[f]].emplace(a, b);
    }
  RegionPolygons rp;
  rp.polygon.resize(l.count);
  rp.bad.assign(l.count, 0);
  for (int r = 0; r < l.count; ++r) {
    auto& nx = next[r];
    for (const auto& [a, b] : nx)
      if (nx.count(a) > 1) rp.bad[r] = 1;  // pinched
    if (rp.bad[r] || nx.empty()) {
      rp.bad[r] = 1;
      continue;
    }
    // Walk one loop; the region is a disk only if it uses every boundary half-edge.
    std::vector<int> loop;
    int cur = nx.begin()->first;
    const int first = cur;
    do {
      loop.push_back(cur);
      auto it = nx.find(cur);
      if (it == nx.end()) break;
      cur = it->second;
    } while (cur != first && loop.size() <= nx.size());
    if (loop.size() != nx.size() || cur != first) {
      rp.bad[r] = 1;
      continue;
    }
    for (int v : loop)
      if (junction[v]) rp.polygon[r].push_back(v);
    if (rp.polygon[r].size() < 3) rp.bad[r] = 1;
  }
  return rp;
}

/// The polygon mesh of the regions, its vertices the junctions (numbered in order of first use).
RegionMesh region_mesh(const TriMesh& mesh, const Labelling& l,
                       const std::vector<std::vector<int>>& polygon,
                       const std::vector<int>& label) {
  RegionMesh out;
  std::vector<int> new_id(mesh.num_vertices(), -1);
  std::vector<int> first_face(l.count, -1);
  for (int f = mesh.num_faces() - 1; f >= 0; --f) first_face[l.region[f]] = f;
  for (int r = 0; r < l.count; ++r) {
    std::vector<int> face;
    for (int v : polygon[r]) {
      if (new_id[v] < 0) {
        new_id[v] = static_cast<int>(out.source_vertex.size());
        out.source_vertex.push_back(v);
      }
      face.push_back(new_id[v]);
    }
    out.mesh.faces.push_back(std::move(face));
    out.face_label.push_back(label[first_face[r]]);
  }
  out.mesh.V.resize(static_cast<int>(out.source_vertex.size()), 3);
  for (std::size_t i = 0; i < out.source_vertex.size(); ++i)
    out.mesh.V.row(static_cast<int>(i)) = mesh.V.row(out.source_vertex[i]);
  return out;
}

/// Relabels the faces of the victims (sorted: non-disks first, then by area) with the label of
/// the neighbour each shares most border with; a region that takes part in a merge this round
/// is not merged again.
void merge_regions(const Labelling& l, const std::vector<int>& victims,
                   const std::vector<std::map<int, double>>& border, std::vector<int>& label) {
  const int nf = static_cast<int>(label.size());
  std::vector<int> region_label(l.count, -1);
  for (int f = 0; f < nf; ++f) region_label[l.region[f]] = label[f];
  std::vector<int> new_label = region_label;
  std::vector<char> touched(l.count, 0);
  for (int victim : victims) {
    if (touched[victim]) continue;
    if (border[victim].empty())
      throw Error("regions", "a region is not a disk and has no neighbour to merge with");
    const int target =
        std::max_element(border[victim].begin(), border[victim].end(), [](auto& a, auto& b) {
          return a.second < b.second;
        })->first;
    if (touched[target]) continue;
    new_label[victim] = region_label[target];
    touched[victim] = touched[target] = 1;
  }
  for (int f = 0; f < nf; ++f) label[f] = new_label[l.region[f]];
}

}  // namespace

RegionMesh extract_regions(const TriMesh& mesh, std::vector<int> label, const RegionOptions& o) {
  const int nf = mesh.num_faces();
  const Topology t = build_topology(mesh);
  const std::vector<char> corner = boundary_corners(mesh.V, t.boundary_loops, o.corner_angle_deg);
  std::vector<double> face_area(nf);
  for (int f = 0; f < nf; ++f) {
    const auto& F = mesh.F;
    face_area[f] = triangle_area(mesh.vertex(F(f, 0)), mesh.vertex(F(f, 1)), mesh.vertex(F(f, 2)));
  }

  for (int round = 0; round < 1000; ++round) {
    const Labelling l = components(t, label, nf);
    std::vector<double> area(l.count, 0);
    for (int f = 0; f < nf; ++f) area[l.region[f]] += face_area[f];
    const std::vector<std::map<int, double>> border = region_borders(mesh, t, l);
    const RegionPolygons rp = region_polygons(mesh, t, l, junctions(t, l, corner));
    const std::vector<char>& bad = rp.bad;
    // Merge offenders: non-disk or too-few-corner regions, and regions under the area threshold,
    // each into the neighbour it shares most border with.
    std::vector<int> victims;
    for (int r = 0; r < l.count; ++r)
      if (bad[r] || (area[r] < o.min_area && !border[r].empty())) victims.push_back(r);
    if (victims.empty()) return region_mesh(mesh, l, rp.polygon, label);
    std::sort(victims.begin(), victims.end(),
              [&](int a, int b) { return bad[a] != bad[b] ? bad[a] > bad[b] : area[a] < area[b]; });
    merge_regions(l, victims, border, label);
  }
  throw Error("regions", "could not make every region a disk");
}

}  // namespace gridshell
