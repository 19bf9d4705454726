#include "gridshell/surfaces/force_density.h"

#include <Eigen/Sparse>

#include "gridshell/core/sparse_cholesky.h"
#include "gridshell/core/error.h"

namespace gridshell {

ForceDensityResult solve_force_density(const ForceDensityProblem& pb) {
  const int n = static_cast<int>(pb.X.rows());
  std::vector<int> free_index(n, -1);
  int nfree = 0;
  for (int i = 0; i < n; ++i)
    if (!pb.fixed[i]) free_index[i] = nfree++;
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(nfree, 3);
  for (int i = 0; i < n; ++i)
    if (free_index[i] >= 0) rhs.row(free_index[i]) = pb.loads.row(i);
  for (std::size_t e = 0; e < pb.edges.size(); ++e) {
    const auto [a, b] = pb.edges[e];
    const double q = pb.q[e];
    const int fa = free_index[a], fb = free_index[b];
    if (fa >= 0) trip.emplace_back(fa, fa, q);
    if (fb >= 0) trip.emplace_back(fb, fb, q);
    if (fa >= 0 && fb >= 0) {
      trip.emplace_back(fa, fb, -q);
      trip.emplace_back(fb, fa, -q);
    } else if (fa >= 0) {
      rhs.row(fa) += q * pb.X.row(b);
    } else if (fb >= 0) {
      rhs.row(fb) += q * pb.X.row(a);
    }
  }
  Eigen::SparseMatrix<double> D(nfree, nfree);
  D.setFromTriplets(trip.begin(), trip.end());
  SparseCholesky solver;
  if (!solver.compute(D).ok)
    throw Error("force density", "network has free nodes not connected to an anchor");
  const Eigen::MatrixX3d xf = solver.solve(rhs);
  ForceDensityResult r;
  r.X = pb.X;
  for (int i = 0; i < n; ++i)
    if (free_index[i] >= 0) r.X.row(i) = xf.row(free_index[i]);
  r.residual = force_density_residual(pb, r.X);
  return r;
}

double force_density_residual(const ForceDensityProblem& pb, const Points& X) {
  Points res = pb.loads;
  for (std::size_t e = 0; e < pb.edges.size(); ++e) {
    const auto [a, b] = pb.edges[e];
    Eigen::RowVector3d f = pb.q[e] * (X.row(b) - X.row(a));
    res.row(a) += f;
    res.row(b) -= f;
  }
  double worst = 0, scale = 0;
  for (int i = 0; i < X.rows(); ++i) {
    scale = std::max(scale, pb.loads.row(i).norm());
    if (!pb.fixed[i]) worst = std::max(worst, res.row(i).norm());
  }
  return scale > 0 ? worst / scale : worst;
}

}  // namespace gridshell
