#include "gridshell/voronoi/engine.h"

// The CVT optimisation: L-BFGS on the CVT energy (Liu et al. 2009) with the seeds kept on the
// surface, or over-relaxed Lloyd steps; the optional coarse-then-fine levels.
// docs/voronoi.md "Method", CVT optimisation.

#include <algorithm>
#include <cmath>
#include <limits>

#include <LBFGS.h>
#include <spdlog/spdlog.h>

namespace gridshell::voronoi {

namespace {

/// Minimises the CVT energy of the interior seeds by L-BFGS (Liu et al. 2009), the seeds kept
/// on the surface: E = Σ_i ∫_{V_i} |x − s_i|² dA, ∂E/∂s_i = 2 m_i (s_i − c_i). Every point the
/// solver asks for is first put back on the surface (each seed to the closest point of the
/// triangles its region met at the previous evaluation, written back into the iterate), and the
/// gradient is projected on the tangent plane there. Stops when the RMS tangential Lloyd move
/// |P_T(c_i − s_i)| is below `tol` (m) — the measure of the Lloyd iteration, whose move is
/// projected on the surface too — after `max_evals` diagrams, or when the line search can make
/// no progress; the seeds are left at the evaluated point of lowest energy (labels and
/// integrals are then not current). Returns the number of diagrams computed.
///
/// How the run stops: LBFGS++ has no callback and counts iterations, not evaluations, so the
/// objective itself ends the run through the solver's own convergence test. At the stopping
/// evaluation it returns a zero gradient and the value −∞: the line search accepts that point at
/// once (Armijo holds for −∞; the Wolfe test of a zero gradient passes), and minimize() returns
/// on ‖g‖ ≤ epsilon = 0 — also when the first evaluation stops. LBFGS++ (0.1.0, Debian
/// liblbfgspp-dev) evaluates nothing after that test, so the diagrams computed are exactly those
/// of the former design, which threw an exception out of the objective there (the snapshot and
/// an evaluation-by-evaluation trace of L-BFGS runs are bit-identical). The line search's own
/// failures still arrive as exceptions from LBFGS++ and end the run the same way.
int minimize_energy(Engine& E, double tol, int max_evals, int history, bool* converged) {
  std::vector<int> free;
  for (std::size_t i = 0; i < E.seeds.size(); ++i)
    if (E.seeds[i].kind == kInterior) free.push_back(static_cast<int>(i));
  const int n = static_cast<int>(free.size());
  if (n == 0 || max_evals <= 0) return 0;
  // Scaled variables (positions / R about the box centre, energy / R⁴) keep the numbers O(1).
  const Vec3 o = 0.5 * (E.lo + E.hi);
  const double R3 = E.R * E.R * E.R, R4 = R3 * E.R;
  const auto& F = E.S.deformed.F;
  Eigen::VectorXd x(3 * n);
  for (int k = 0; k < n; ++k) x.segment<3>(3 * k) = (E.seeds[free[k]].pos - o) / E.R;
  std::vector<Seed> best_seeds;
  double best_f = std::numeric_limits<double>::infinity();
  int evals = 0;
  auto f = [&](Eigen::VectorXd& y, Eigen::VectorXd& grad) -> double {
    if (evals > 0)
      for (int k = 0; k < n; ++k) {
        const int i = free[k];
        const Vec3 p = o + E.R * y.segment<3>(3 * k);
        if (E.cell_start[i + 1] > E.cell_start[i]) place_on_region(E, i, p);
        y.segment<3>(3 * k) = (E.seeds[i].pos - o) / E.R;
      }
    compute_labels(E, 0, evals > 0 ? static_cast<int>(E.label.size()) : 0);
    integrate(E);
    ++evals;
    grad.resize(3 * n);
    double sum = 0;
    for (int k = 0; k < n; ++k) {
      const int i = free[k];
      const int t = E.seeds[i].tri;
      const Vec3 a = E.S.deformed.vertex(F(t, 0));
      const Vec3 nrm =
          (E.S.deformed.vertex(F(t, 1)) - a).cross(E.S.deformed.vertex(F(t, 2)) - a).normalized();
      Vec3 g = E.area[i] * E.seeds[i].pos - E.moment[i];
      if (nrm.allFinite()) g -= g.dot(nrm) * nrm;
      grad.segment<3>(3 * k) = 2.0 * g / R3;
      if (E.area[i] > 0) sum += g.squaredNorm() / (E.area[i] * E.area[i]);
    }
    const double fx = E.energy / R4;
    const double move = std::sqrt(sum / n);
    if (fx < best_f || move < tol) {
      best_f = move < tol ? -std::numeric_limits<double>::infinity() : fx;
      best_seeds = E.seeds;
      if (move < tol && converged) *converged = true;
    }
    spdlog::debug("cvt energy {} {:.9e} rms move/R {:.3e}", evals, fx, move / E.R);
    if (move < tol || evals >= max_evals) {  // stop: see above
      grad.setZero();
      return -std::numeric_limits<double>::infinity();
    }
    return fx;
  };
  LBFGSpp::LBFGSParam<double> param;
  param.m = history;
  param.epsilon = 0;
  param.epsilon_rel = 0;
  param.max_iterations = 0;
  param.max_linesearch = 20;
  param.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_WOLFE;
  LBFGSpp::LBFGSSolver<double> solver(param);
  double fx = 0;
  try {
    solver.minimize(f, x, fx);
  } catch (const std::exception& e) {  // the line search could make no progress
    spdlog::debug("cvt energy: L-BFGS stopped ({})", e.what());
  }
  if (!best_seeds.empty()) E.seeds = std::move(best_seeds);
  return evals;
}

}  // namespace

/// One Lloyd step (labels must be current), the move over-relaxed by `omega`. Returns the
/// root-mean-square move of the interior seeds divided by omega.
double lloyd_step(Engine& E, double omega) {
  integrate(E);
  double sum_move2 = 0;
  int moved = 0;
  for (std::size_t i = 0; i < E.seeds.size(); ++i) {
    if (E.seeds[i].kind != kInterior || E.area[i] <= 0) continue;
    const Vec3 g = E.moment[i] / E.area[i];
    sum_move2 +=
        place_on_region(E, static_cast<int>(i), E.seeds[i].pos + omega * (g - E.seeds[i].pos)) /
        (omega * omega);
    ++moved;
  }
  return moved ? std::sqrt(sum_move2 / moved) : 0.0;
}

CvtResult optimize_cvt(Engine& E, const TessellationOptions& o) {
  const double R = E.R;
  const bool two_level = o.coarse_edge > o.support_edge;
  const double tol = o.tolerance * R;
  CvtResult result;
  int& it = result.iterations;
  // Level 1: the CVT on the (coarse) support mesh. The diagram is clipped exactly on the planar
  // triangles, so a coarse support mesh gives the same cells wherever every cell meeting a triangle
  // labels one of its corners or its neighbours' opposite corners.
  const double level1_tol = two_level ? o.coarse_tolerance * R : tol;
  // Lloyd steps until the seeds move less than `tolerance` (true) or `it` reaches `end`.
  const auto lloyd_until = [&](int end, double tolerance, const char* tag) {
    for (; it < end; ++it) {
      compute_labels(E, 0, static_cast<int>(E.label.size()));
      const double move = lloyd_step(E, o.over_relaxation);
      spdlog::debug("{} {} move/R {:.3e}", tag, it, move / R);
      if (move < tolerance) {
        ++it;
        return true;
      }
    }
    return false;
  };
  if (o.quasi_newton) {
    it += minimize_energy(E, level1_tol, o.max_iterations, o.lbfgs_history, &result.converged);
    spdlog::debug("cvt: {} diagrams", it);
  } else {
    result.converged = lloyd_until(o.max_iterations, level1_tol, "lloyd");
  }
  // Level 2: a finer support mesh and a few (over-relaxed) Lloyd steps to `tolerance`.
  if (two_level && o.fine_iterations > 0) {
    std::vector<int> source;
    const int old_faces = E.S.deformed.num_faces();
    refine_to_length(E.S, o.support_edge * R, &source);
    E.adj = build_triangle_adjacency(E.S.deformed.F, E.S.deformed.num_vertices());
    E.corner_vertex.resize(E.S.deformed.num_vertices(), 0);
    relocate_seeds(E, source, old_faces);
    result.converged =
        lloyd_until(std::min(o.max_iterations, it + o.fine_iterations), tol, "fine lloyd");
  }
  return result;
}

}  // namespace gridshell::voronoi
