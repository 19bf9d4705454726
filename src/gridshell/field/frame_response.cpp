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

namespace {

/// Per joint of `gridshell`: the tensor T_v of the file comment.
std::vector<Eigen::Matrix3d> joint_tensors(const PolyMesh& gridshell,
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
  return joint;
}

}  // namespace

StressField frame_response_field(const TriMesh& surface, const PolyMesh& gridshell,
                                 const std::vector<double>& member_value) {
  const std::vector<Eigen::Matrix3d> joint = joint_tensors(gridshell, member_value);
  const auto nearest = nearest_points(gridshell.V, surface.V, 3);
  std::vector<Eigen::Matrix3d> vertex(surface.num_vertices(), Eigen::Matrix3d::Zero());
  tbb::parallel_for(0, surface.num_vertices(), [&](int v) {  // each vertex on its own
    for (int j : nearest[v]) vertex[v] += joint[j];
    vertex[v] /= static_cast<double>(nearest[v].size());
  });
  return principal_stress_from_vertex_tensors(surface, vertex);
}

StressField frame_response_field(const TriMesh& surface, const std::vector<int>& faces,
                                 const PolyMesh& gridshell,
                                 const std::vector<double>& member_value) {
  // The listed triangles as a mesh of their own (vertices in the order first met): each of its
  // vertices takes the same nearest joints, each of its triangles the same frame and tensor.
  TriMesh part;
  part.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  std::vector<int> index(surface.num_vertices(), -1), used;
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const int f = faces[k];
    if (f < 0 || f >= surface.num_faces())
      throw Error("frame response", fmt::format("face {} of {} triangles", f, surface.num_faces()));
    for (int c = 0; c < 3; ++c) {
      int& i = index[surface.F(f, c)];
      if (i < 0) i = static_cast<int>(used.size()), used.push_back(surface.F(f, c));
      part.F(static_cast<Eigen::Index>(k), c) = i;
    }
  }
  part.V.resize(static_cast<Eigen::Index>(used.size()), 3);
  for (std::size_t i = 0; i < used.size(); ++i)
    part.V.row(static_cast<Eigen::Index>(i)) = surface.V.row(used[i]);
  return frame_response_field(part, gridshell, member_value);
}

}  // namespace gridshell
