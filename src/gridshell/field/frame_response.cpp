#include "gridshell/field/frame_response.h"

#include <cmath>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/core/error.h"
#include "gridshell/field/field_io.h"
#include "gridshell/mesh/nearest.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

StressField frame_response_field(const TriMesh& surface, const PolyMesh& gridshell,
                                 const std::vector<double>& member_value) {
  const Topology topo = build_topology(gridshell);
  if (static_cast<int>(member_value.size()) != topo.num_edges())
    throw Error("frame response", fmt::format("{} member values for {} beams",
                                              member_value.size(), topo.num_edges()));
  const int nj = gridshell.num_vertices();
  std::vector<Eigen::Matrix3d> joint(nj, Eigen::Matrix3d::Zero());
  for (int e = 0; e < topo.num_edges(); ++e) {
    const double w = member_value[e];
    if (!(w >= 0) || !std::isfinite(w))
      throw Error("frame response", fmt::format("member {} has value {}", e, w));
    const auto [a, b] = topo.edges[e];
    const Vec3 d = gridshell.vertex(b) - gridshell.vertex(a);
    if (!(d.norm() > 0)) continue;
    const Vec3 t = d.normalized();
    const Eigen::Matrix3d tt = 0.5 * w * t * t.transpose();
    joint[a] += tt;
    joint[b] += tt;
  }
  const std::vector<double> area = analysis::tributary_areas(gridshell);
  for (int v = 0; v < nj; ++v)
    joint[v] = area[v] > 0 ? Eigen::Matrix3d(joint[v] / area[v]) : Eigen::Matrix3d::Zero();
  const auto nearest = nearest_points(gridshell.V, surface.V, 3);
  std::vector<Eigen::Matrix3d> vertex(surface.num_vertices(), Eigen::Matrix3d::Zero());
  tbb::parallel_for(0, surface.num_vertices(), [&](int v) {  // each vertex on its own
    for (int j : nearest[v]) vertex[v] += joint[j];
    vertex[v] /= static_cast<double>(nearest[v].size());
  });
  return principal_stress_from_vertex_tensors(surface, vertex);
}

}  // namespace gridshell
