#include "gridshell/fem/frame_static.h"

#include <cmath>

#include <fmt/format.h>
#include <Eigen/SparseLU>

#include "gridshell/core/error.h"

namespace gridshell::fem {

NonlinearStaticResult nonlinear_static(const FrameMesh& mesh, const FrameAssembler& asmb,
                                       double lambda, const NonlinearStaticOptions& opt,
                                       const std::string& subject) {
  NonlinearStaticResult res;
  FrameState cur = reference_state(mesh);
  double lam = 0;
  double step = lambda / std::max(opt.initial_steps, 1);
  int cutbacks = 0;
  const Eigen::VectorXd& f = mesh.load;
  const double fnorm = f.norm();
  // Full Newton with the exact (non-symmetric) spin tangent: quadratic convergence also under
  // applied moments.
  Eigen::SparseLU<SpMat, Eigen::COLAMDOrdering<int>> lu;
  bool analyzed = false;
  Eigen::VectorXd fint;
  while (std::abs(lam - lambda) > 1e-14 * std::abs(lambda)) {
    if (std::abs(step) > std::abs(lambda - lam)) step = lambda - lam;
    const double target = lam + step;
    FrameState st = cur;
    bool converged = false;
    int its = 0;
    double rprev = 1e300;
    for (its = 1; its <= opt.max_iterations; ++its) {
      const SpMat K = asmb.tangent(st, &fint, nullptr, false);
      const Eigen::VectorXd r = target * f - asmb.reduce(fint);
      const double rn = r.norm();
      if (!std::isfinite(rn)) break;
      const double scale = fnorm * std::abs(target);
      if (rn <= opt.tolerance * scale || (its >= 4 && rn <= 1e-5 * scale && rn >= 0.5 * rprev)) {
        converged = true;
        break;
      }
      if (its > 6 && rn > rprev) break;  // diverging
      rprev = rn;
      if (!analyzed) {
        lu.analyzePattern(K);
        analyzed = true;
      }
      lu.factorize(K);
      if (lu.info() != Eigen::Success) break;
      const Eigen::VectorXd du = lu.solve(r);
      if (!du.allFinite()) break;
      apply_increment(mesh, du, st);
    }
    res.iterations += its;
    if (converged) {
      cur = std::move(st);
      lam = target;
      ++res.steps;
      if (its <= 4) step *= 1.5;
    } else {
      step *= 0.5;
      if (++cutbacks > opt.max_cutbacks)
        throw Error(subject, fmt::format("no equilibrium found beyond load factor {:.6g} (the "
                                         "requested {:.6g} may exceed the limit load)",
                                         lam, lambda));
    }
  }
  fint = asmb.internal_force(cur, &res.axial);
  res.reactions = fint - lambda * mesh.load_full;
  for (int v = 0; v < static_cast<int>(mesh.X.rows()); ++v)
    for (int c = 0; c < 6; ++c)
      if (mesh.dof[v][c] >= 0 || !mesh.active[v][c]) res.reactions(6 * v + c) = 0;
  res.state = std::move(cur);
  return res;
}

}  // namespace gridshell::fem
