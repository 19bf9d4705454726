// The acceptance figures of a quad grid (quad_aniso.h: QuadMeshStats).
#include "gridshell/grids/quad_aniso.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/nearest.h"
#include "gridshell/mesh/overlaps.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

namespace {

double median_of(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

QuadMeshStats quad_mesh_stats(const PolyMesh& grid, const TriMesh& surface, const Field& field,
                              const QuadMeshStatsOptions& o) {
  QuadMeshStats s;
  const Topology topo = build_topology(grid);
  Points centroids(surface.num_faces(), 3);
  for (int f = 0; f < surface.num_faces(); ++f)
    centroids.row(f) = (surface.V.row(surface.F(f, 0)) + surface.V.row(surface.F(f, 1)) +
                        surface.V.row(surface.F(f, 2))) /
                       3;
  auto face_at = [&](const Points& queries) {
    std::vector<int> out;
    for (const auto& nn : nearest_points(centroids, queries)) out.push_back(nn[0]);
    return out;
  };
  int valence4 = 0;
  for (int v = 0; v < grid.num_vertices(); ++v) {
    if (topo.on_boundary[v] || topo.vertex_faces[v].empty()) continue;
    ++s.interior_joints;
    if (topo.vertex_neighbors[v].size() == 4) ++valence4;
  }
  s.valence4_share = s.interior_joints ? static_cast<double>(valence4) / s.interior_joints : 0;
  s.overlaps = find_overlaps(grid, topo).count();
  std::vector<double> lengths;
  for (const auto& e : topo.edges)
    lengths.push_back((grid.vertex(e[0]) - grid.vertex(e[1])).norm());
  const double median = median_of(lengths);
  s.min_edge_ratio = lengths.empty() || median <= 0
                         ? 0
                         : *std::min_element(lengths.begin(), lengths.end()) / median;
  std::vector<double> areas;
  for (int f = 0; f < grid.num_faces(); ++f) areas.push_back(polygon_area(grid, f));
  const double median_area = median_of(areas);
  s.min_area_ratio = areas.empty() || median_area <= 0
                         ? 0
                         : *std::min_element(areas.begin(), areas.end()) / median_area;
  // Beams: alignment where the field is strongly anisotropic.
  Points mids(topo.num_edges(), 3);
  for (int e = 0; e < topo.num_edges(); ++e)
    mids.row(e) = 0.5 * (grid.V.row(topo.edges[e][0]) + grid.V.row(topo.edges[e][1]));
  const std::vector<int> edge_face = topo.num_edges() ? face_at(mids) : std::vector<int>{};
  const double cos_limit = std::cos(o.angle_deg * std::numbers::pi / 180);
  int aligned = 0;
  for (int e = 0; e < topo.num_edges(); ++e) {
    const auto [a, b] = topo.edges[e];
    if (topo.on_boundary[a] || topo.on_boundary[b]) continue;
    const int f = edge_face[e];
    if (field.a[f] < o.strong_a) continue;
    ++s.strong_beams;
    const Vec3 d = (grid.vertex(b) - grid.vertex(a)).normalized();
    const Vec3 n = (surface.vertex(surface.F(f, 1)) - surface.vertex(surface.F(f, 0)))
                       .cross(surface.vertex(surface.F(f, 2)) - surface.vertex(surface.F(f, 0)))
                       .normalized();
    const Vec3 u = field.u[f].normalized(), up = n.cross(u);
    const Vec3 dt = (d - n * n.dot(d)).normalized();
    if (std::abs(dt.dot(u)) >= cos_limit || std::abs(dt.dot(up)) >= cos_limit) ++aligned;
  }
  s.aligned_share = s.strong_beams ? static_cast<double>(aligned) / s.strong_beams : 0;
  // Faces.
  Points fc(grid.num_faces(), 3);
  for (int f = 0; f < grid.num_faces(); ++f) {
    Vec3 c = Vec3::Zero();
    for (int v : grid.faces[f]) c += grid.vertex(v);
    fc.row(f) = (c / static_cast<double>(grid.faces[f].size())).transpose();
  }
  const std::vector<int> face_face = grid.num_faces() ? face_at(fc) : std::vector<int>{};
  int quads = 0;
  std::vector<double> aspects, aspects_all;
  for (int f = 0; f < grid.num_faces(); ++f) {
    const auto& poly = grid.faces[f];
    if (!is_simple_polygon(grid, poly)) ++s.non_simple_faces;
    bool interior = true;
    for (int v : poly) interior = interior && !topo.on_boundary[v];
    if (!interior) continue;
    ++s.interior_faces;
    if (poly.size() != 4) continue;
    ++quads;
    std::array<Vec3, 4> e;
    for (int k = 0; k < 4; ++k) e[k] = grid.vertex(poly[(k + 1) % 4]) - grid.vertex(poly[k]);
    const double l02 = 0.5 * (e[0].norm() + e[2].norm()), l13 = 0.5 * (e[1].norm() + e[3].norm());
    if (std::min(l02, l13) <= 0) continue;
    aspects_all.push_back(std::max(l02, l13) / std::min(l02, l13));
    const int t = face_face[f];
    if (field.a[t] < o.aspect_a) continue;
    const Vec3 u = field.u[t].normalized();
    const double along02 = std::abs(e[0].normalized().dot(u)) + std::abs(e[2].normalized().dot(u));
    const double along13 = std::abs(e[1].normalized().dot(u)) + std::abs(e[3].normalized().dot(u));
    aspects.push_back(along02 >= along13 ? l02 / l13 : l13 / l02);
  }
  s.quad_share = s.interior_faces ? static_cast<double>(quads) / s.interior_faces : 0;
  s.aspect_quads = static_cast<int>(aspects.size());
  s.median_aspect = median_of(aspects);
  s.median_aspect_all = median_of(aspects_all);
  double covered = 0;
  for (int f = 0; f < grid.num_faces(); ++f) covered += polygon_area(grid, f);
  const double area = surface_area(surface);
  s.coverage = area > 0 ? covered / area : 0;
  return s;
}

}  // namespace gridshell
