#include "gridshell/grids/supports.h"

#include <limits>

#include "gridshell/mesh/topology.h"

namespace gridshell {

std::vector<int> transfer_supports(const Points& joints, const Surface& surface, double tol) {
  const TriMesh& m = surface.mesh;
  std::vector<char> sup(m.num_vertices(), 0);
  for (int v : surface.supports) sup[v] = 1;
  const Topology t = build_topology(m);
  std::vector<char> out(joints.rows(), 0);
  for (Eigen::Index j = 0; j < joints.rows(); ++j) {
    const Vec3 p = joints.row(j).transpose();
    for (const auto& loop : t.boundary_loops)
      for (std::size_t k = 0; k < loop.size() && !out[j]; ++k) {
        const int a = loop[k], b = loop[(k + 1) % loop.size()];
        const Vec3 pa = m.vertex(a), pb = m.vertex(b);
        const double len2 = (pb - pa).squaredNorm();
        const double s = len2 > 0 ? std::clamp((p - pa).dot(pb - pa) / len2, 0.0, 1.0) : 0.0;
        if ((pa + s * (pb - pa) - p).norm() > tol) continue;
        const bool at_a = s * std::sqrt(len2) <= tol, at_b = (1 - s) * std::sqrt(len2) <= tol;
        if ((at_a && sup[a]) || (at_b && sup[b]) || (sup[a] && sup[b])) out[j] = 1;
      }
  }
  for (int v : surface.supports) {
    if (t.on_boundary[v]) continue;
    Eigen::Index best = -1;
    double bd = std::numeric_limits<double>::max();
    for (Eigen::Index j = 0; j < joints.rows(); ++j) {
      const double d = (joints.row(j).transpose() - m.vertex(v)).norm();
      if (d < bd) bd = d, best = j;
    }
    if (best >= 0) out[best] = 1;
  }
  std::vector<int> ids;
  for (Eigen::Index j = 0; j < joints.rows(); ++j)
    if (out[j]) ids.push_back(static_cast<int>(j));
  return ids;
}

}  // namespace gridshell
