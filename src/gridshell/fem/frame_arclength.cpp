#include "gridshell/fem/frame_arclength.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <tuple>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <Eigen/SparseLU>

#include "gridshell/core/error.h"
#include "gridshell/core/rng.h"

namespace gridshell::fem {

namespace {

double max_displacement(const FrameMesh& mesh, const FrameState& s) {
  return (s.x - mesh.X).rowwise().norm().maxCoeff();
}

// Weights of the arc-length norm: 1 for translations, (mean element length)² for rotations.
Eigen::VectorXd arc_weights(const FrameMesh& mesh) {
  double l = 0;
  for (const auto& e : mesh.elements) l += e.beam.l0;
  l /= std::max<size_t>(1, mesh.elements.size());
  Eigen::VectorXd w(mesh.num_dofs);
  for (int v = 0; v < static_cast<int>(mesh.X.rows()); ++v)
    for (int c = 0; c < 6; ++c)
      if (mesh.dof[v][c] >= 0) w(mesh.dof[v][c]) = c < 3 ? 1.0 : l * l;
  return w;
}

struct Converged {
  FrameState state;
  double lambda = 0;
  Eigen::VectorXd du;  // last increment (free dofs)
  double dlambda = 0;
  int negative = 0;
};

// Factorises the tangent at `st` into `solver` (and counts it).
bool factorize_tangent(const FrameAssembler& asmb, const FrameState& st, TangentSolver& solver,
                       int& factorizations) {
  ++factorizations;
  return solver.factorize(asmb.tangent(st, nullptr));
}

// A factorisation (tangent + CHOLMOD) costs about as much as this many modified-Newton
// iterations (internal forces + one solve): the corrector refreshes its tangent only when the
// observed contraction predicts more iterations than that.
constexpr double kRefreshIterations = 20;
constexpr double kPolish = 1e-2;
constexpr int kMaxRefreshes = 3;  // per attempt
// arc_step's result when the iterate went past a critical point of a stable path and the last
// stable tangent no longer contracts the residual: the radius reaches beyond the critical point.
constexpr int kCrossed = -2;

// One arc-length step from `from` with radius ds. `start` holds the factorised tangent at the
// start point and ut0 = K⁻¹f; neither is modified, so a failed or refined step needs no
// refactorisation. Refreshed tangents go into `work`. On success fills `to` (without factorising
// its tangent) and returns the number of iterations, else −1 (kCrossed: the step crosses a
// critical point).
int arc_step(const FrameMesh& mesh, const FrameAssembler& asmb, const Eigen::VectorXd& W,
             const ArcLengthOptions& opt, const TangentSolver& start, const Eigen::VectorXd& ut0,
             TangentSolver& work, const Converged& from, double ds, bool first,
             bool indefinite_start, Converged& to, int& factorizations) {
  const Eigen::VectorXd& f = mesh.load;
  const TangentSolver* solver = &start;
  Eigen::VectorXd ut = ut0;  // K⁻¹f of the tangent in use
  const double nt = std::sqrt(ut.dot(W.cwiseProduct(ut)));
  if (!(nt > 0)) return -1;
  double sign = 1;
  if (!first) sign = from.du.dot(W.cwiseProduct(ut)) >= 0 ? 1 : -1;
  double dlam = sign * ds / nt;
  Eigen::VectorXd du = dlam * ut;
  FrameState st = from.state;
  apply_increment(mesh, du, st);
  double lam = from.lambda + dlam;
  const double fnorm = f.norm();
  Eigen::VectorXd fint;
  double rprev = 0;
  int last_refresh = 0, growing = 0, refreshes = 0;
  // The predicted point (iteration 1), kept for a refresh at iteration 2 (see below).
  struct Iterate {
    FrameState state;
    Eigen::VectorXd du, r;
    double lambda = 0, rn = 0;
  } predicted;
  bool fresh = false;        // the tangent in use is that of the previous iterate
  bool stable_only = false;  // a refreshed tangent was indefinite
  // Modified Newton: the start tangent is kept while the residual contracts fast enough
  // (linear convergence, each iteration one residual and one solve); it is refreshed at the
  // current iterate when the contraction rate predicts more than kRefreshIterations iterations,
  // except at iteration 2: there the tangent is refreshed at the predicted point, not at the
  // iterate. On a softening path the start tangent's first correction throws the iterate along
  // the soft mode, away from the path (its residual grows ×1.5–2.5 on the Aquadom designs), and a
  // tangent taken there contracts only ×0.3–0.4 per iteration, where the one at the predicted
  // point gives a nearly quadratic first iteration (×1e-3): the steps can then be 2–4× longer.
  for (int it = 1; it <= opt.max_iterations; ++it) {
    fint = asmb.internal_force(st);
    Eigen::VectorXd r = lam * f - asmb.reduce(fint);
    if (!r.allFinite()) return -1;
    const double scale = fnorm * std::max(std::abs(lam), 1e-3 * std::abs(dlam));
    double rn = r.norm();
    // A stale tangent converges linearly and stops just below the tolerance, where Newton's
    // quadratic convergence would overshoot it by far: the modified corrector iterates on to
    // kPolish × tolerance (each iteration is cheap) and accepts the plain tolerance only when
    // the contraction stalls. The residual left in a near-critical mode acts as an imperfection,
    // so this keeps perfect structures on their fundamental path up to a bifurcation.
    const double tol = opt.tolerance * scale * kPolish;
    const double rho = it >= 2 ? rn / rprev : 0;
    const bool floor = (rn <= opt.tolerance * scale && rho >= 0.5) ||
                       (fresh && it >= 3 && rn <= 1e-5 * scale && rho >= 0.5);
    if (rn <= tol || floor) {
      to.state = std::move(st);
      to.lambda = lam;
      to.du = du;
      to.dlambda = lam - from.lambda;
      return it;
    }
    fresh = false;
    if (it == 1) predicted = {st, du, r, lam, rn};
    if (it >= 2) {
      growing = rho >= 1 ? growing + 1 : 0;
      // Past a critical point with the last stable tangent and no contraction: the step
      // crosses the critical point and would only iterate to max_iterations; a shorter one is
      // cheaper (kCrossed tells the caller).
      if (stable_only && rho >= 1) {
        spdlog::debug("  crossing a critical point at iteration {}", it);
        return kCrossed;
      }
      // Diverging: the residual keeps growing, or grows with a fresh tangent after the
      // refreshes an attempt may spend (the step is too long: a shorter one is cheaper).
      if (growing >= 4 || (refreshes >= kMaxRefreshes && rho >= 1)) {
        spdlog::debug("  diverging at iteration {}", it);
        return -1;
      }
      const bool slow = rho >= 1 || std::log(tol / rn) / std::log(rho) > kRefreshIterations;
      if (slow && it - last_refresh >= 2 && !stable_only && refreshes < kMaxRefreshes) {
        last_refresh = it;
        ++refreshes;
        if (it == 2) {
          std::tie(st, du, r, lam, rn) =
              std::tie(predicted.state, predicted.du, predicted.r, predicted.lambda, predicted.rn);
          spdlog::debug("  back to the predicted point");
        }
        if (!factorize_tangent(asmb, st, work, factorizations)) return -1;
        spdlog::debug("  refresh at iteration {}: residual {:.3g}, contraction {:.3g}, {}", it,
                      rn / scale, rho,
                      work.positive_definite() ? "positive definite" : "indefinite");
        // An indefinite tangent (the iterate is past a critical point of a path that started
        // stable) is not used: its solves would amplify the critical mode and can throw the
        // iterate onto another branch; the last stable tangent is kept.
        if (work.positive_definite() || indefinite_start) {
          solver = &work;
          ut = work.solve(f);
          if (!ut.allFinite()) return -1;
          fresh = true;
        } else {
          stable_only = true;  // past a critical point: no further refreshes in this step
          if (rho >= 1) {
            spdlog::debug("  crossing a critical point at iteration {}", it);
            return kCrossed;
          }
        }
      }
    }
    rprev = rn;
    const Eigen::VectorXd ur = solver->solve(r);
    const Eigen::VectorXd base = du + ur;
    const double a = ut.dot(W.cwiseProduct(ut));
    const double b = 2 * ut.dot(W.cwiseProduct(base));
    const double c = base.dot(W.cwiseProduct(base)) - ds * ds;
    if (!(a > 0)) return -1;
    // No real root (the stale tangent near a limit point): take the λ-correction that comes
    // closest to the constraint; the following iterations restore it.
    const double disc = std::max(b * b - 4 * a * c, 0.0);
    const double sq = std::sqrt(disc);
    const double q = -0.5 * (b + (b >= 0 ? sq : -sq));
    double r1 = q / a, r2 = q != 0 ? c / q : r1;
    const Eigen::VectorXd d1 = base + r1 * ut, d2 = base + r2 * ut;
    const double c1 = d1.dot(W.cwiseProduct(du)), c2 = d2.dot(W.cwiseProduct(du));
    const double dl = c1 >= c2 ? r1 : r2;
    const Eigen::VectorXd corr = ur + dl * ut;
    if (!corr.allFinite()) return -1;
    du += corr;
    lam += dl;
    apply_increment(mesh, corr, st);
  }
  spdlog::debug("  no convergence in {} iterations", opt.max_iterations);
  return -1;
}

}  // namespace

namespace {
/// |φ·v| / |v| for the tangent's softest mode φ (inverse iteration from a seeded random start)
/// and the load tangent v = K⁻¹f at the last stable point. Near a limit point v is dominated by
/// φ (φᵀf ≠ 0); at a bifurcation φ ⟂ f and v has no large component along φ.
double critical_mode_alignment(const TangentSolver& stable, const Eigen::VectorXd& v, int dofs,
                               Eigen::VectorXd& phi) {
  phi.resize(dofs);
  Rng rng(12345);
  for (int i = 0; i < phi.size(); ++i) phi(i) = rng.uniform(-1, 1);
  phi.normalize();
  for (int k = 0; k < 40; ++k) {
    Eigen::VectorXd y = stable.solve(phi);
    const double nrm = y.norm();
    if (!(nrm > 0) || !std::isfinite(nrm)) break;
    y /= nrm;
    const double change = (y - phi).norm();
    phi = std::move(y);
    if (change < 1e-10) break;
  }
  return std::abs(phi.dot(v)) / std::max(v.norm(), 1e-300);
}
// The start of the path: the tangent at `start` factorised into `solver` with its negative
// pivots in cur.negative, the load tangent ut = K⁻¹f and the path's first point. False (with
// res's stop reason and states set) when the initial tangent is singular.
bool start_path(const FrameMesh& mesh, const FrameAssembler& asmb, const FrameState& start,
                TangentSolver& solver, Converged& cur, Eigen::VectorXd& ut,
                ArcLengthResult& res) {
  const auto singular = [&] {
    res.stop_reason = "the initial tangent is singular";
    res.final_state = res.critical_state = start;
    return false;
  };
  if (!factorize_tangent(asmb, start, solver, res.factorizations)) return singular();
  cur.negative = solver.negative_pivots();
  res.path.push_back({0.0, max_displacement(mesh, start), cur.negative});
  ut = solver.solve(mesh.load);
  if (!ut.allFinite()) return singular();
  return true;
}

// Factorises the tangent at next.state into `work` and sets next.negative; false when the
// factorisation fails. Only a change from positive definite matters for the first critical
// point: the LDLᵀ count is needed only when the start was already indefinite.
bool count_negative(const FrameAssembler& asmb, int base_negative, TangentSolver& work,
                    Converged& next, int& factorizations) {
  if (!factorize_tangent(asmb, next.state, work, factorizations)) return false;
  next.negative = work.positive_definite()
                      ? 0
                      : (base_negative != 0 ? work.negative_pivots() : base_negative + 1);
  return true;
}

// |φ·d| / (|φ| |d|) over the free translations: d = the displacement of `state` from the
// reference, φ's rotations left out.
double path_alignment(const FrameMesh& mesh, const FrameState& state, const Eigen::VectorXd& phi) {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(mesh.num_dofs);
  Eigen::VectorXd p = Eigen::VectorXd::Zero(mesh.num_dofs);
  for (int v = 0; v < static_cast<int>(mesh.X.rows()); ++v)
    for (int c = 0; c < 3; ++c)
      if (mesh.dof[v][c] >= 0) {
        d(mesh.dof[v][c]) = state.x(v, c) - mesh.X(v, c);
        p(mesh.dof[v][c]) = phi(mesh.dof[v][c]);
      }
  const double nd = d.norm(), np = p.norm();
  return nd > 0 && np > 0 ? std::abs(p.dot(d)) / (nd * np) : 0.0;
}

// A bracketed event, classified with the tangent at the last stable point `cur` and its softest
// mode φ. At a new negative pivot: near a limit point the load tangent v = K⁻¹f is dominated by φ
// (φᵀf ≠ 0); at a bifurcation φ ⟂ f and v has no large component along φ. At a fall of λ
// without a new pivot the corrector may already have slipped onto a buckled branch through a
// bifurcation whose pivot change it never saw (a perfect portal frame's sway; φ is no longer
// ⟂ f there): it is a limit point only if the path's displacement so far lies mostly along φ
// (a limit point's softening mode grows with the load: Lee's frame 0.76, the deep arch 0.75,
// the star dome 1.0; the portal frame 0.31). Sets res's alignment and limit type; returns the
// critical load factor (the bracket's middle at a pivot bifurcation, else the largest λ).
double classify_critical(const FrameMesh& mesh, const TangentSolver& solver,
                         const Eigen::VectorXd& ut, const Converged& cur, const Converged& next,
                         double lam_max, int base_negative, ArcLengthResult& res) {
  Eigen::VectorXd phi;
  const double along = critical_mode_alignment(solver, ut, mesh.num_dofs, phi);
  res.critical_mode_alignment = along;
  const bool pivot = next.negative > base_negative;
  const bool bifurcation =
      pivot ? along < 0.5 : along < 0.5 || path_alignment(mesh, cur.state, phi) < 0.5;
  res.limit_type = bifurcation ? LimitType::bifurcation : LimitType::limit_point;
  return bifurcation && pivot ? 0.5 * (cur.lambda + next.lambda)
                              : std::max({cur.lambda, next.lambda, lam_max});
}

// The next arc-length radius: scaled so that the corrector would take about the desired number
// of iterations (by at most ×2 or ×½), never above ds_max.
double next_radius(double ds, int its, int desired_iterations, double ds_max) {
  const double factor =
      std::clamp(std::sqrt(double(desired_iterations) / std::max(its, 1)), 0.5, 2.0);
  return std::min(ds * factor, ds_max);
}

// Tells opt.progress how far the path is: the nearest of the stop rules (a critical point
// cannot be foreseen).
void report_path_progress(const ArcLengthOptions& opt, int steps, double umax, double lambda) {
  double far = static_cast<double>(steps) / opt.max_steps;
  if (opt.max_displacement > 0) far = std::max(far, umax / opt.max_displacement);
  if (opt.max_lambda < 1e9) far = std::max(far, lambda / opt.max_lambda);
  report_progress(opt.progress, "non-linear path", std::min(far, 0.99),
                  fmt::format("step {}, λ = {:.4g}", steps, lambda));
}

}  // namespace

ArcLengthResult arc_length(const FrameMesh& mesh, const FrameAssembler& asmb,
                           const ArcLengthOptions& opt, const FrameState& start) {
  ArcLengthResult res;
  const Eigen::VectorXd W = arc_weights(mesh);
  // solver_cur: the factorised tangent at the current (last converged) point, with its load
  // tangent ut_cur = K⁻¹f; solver_work: refreshed and candidate tangents.
  auto solver_cur = std::make_unique<TangentSolver>(),
       solver_work = std::make_unique<TangentSolver>();
  Converged cur;
  cur.state = start;
  Eigen::VectorXd ut_cur;
  if (!start_path(mesh, asmb, start, *solver_cur, cur, ut_cur, res)) return res;
  if (opt.on_point) opt.on_point(start, 0.0);
  const double ds0 = opt.initial_lambda * std::sqrt(ut_cur.dot(W.cwiseProduct(ut_cur)));
  double ds = ds0;
  const double ds_min = 1e-7 * ds0, ds_max = 50 * ds0;
  double lam_max = 0;
  bool first = true;
  bool critical = false;  // an event has been bracketed
  double lam_crit = 0;
  const int base_negative = cur.negative;
  FrameState stable_state = start;
  bool bracketing = false;
  double ceiling = ds_max;  // lowered after a step that crossed into the unstable region

  // A failed step halves the arc length; false (with the reason set) once it is below ds_min.
  const auto cut_back = [&] {
    ++res.cutbacks;
    ds *= 0.5;
    if (ds >= ds_min) return true;
    res.stop_reason = "the arc-length step could not converge";
    return false;
  };
  while (res.steps < opt.max_steps) {
    Converged next;
    const int its = arc_step(mesh, asmb, W, opt, *solver_cur, ut_cur, *solver_work, cur, ds, first,
                             base_negative != 0, next, res.factorizations);
    res.iterations += std::max(its, 0);
    if (its == kCrossed) {
      // The iterate went into the unstable region (often the predictor overshooting a stiff
      // bend, not the critical point itself): retry a little shorter and keep the radius below
      // this one for a while, instead of halving and growing back into the same failure.
      ++res.cutbacks;
      ceiling = ds = 0.7 * ds;
      if (ds >= ds_min) continue;
      res.stop_reason = "the arc-length step could not converge";
      break;
    }
    if (its < 0) {
      if (!cut_back()) break;
      continue;
    }
    // A fall of λ is an event by itself; otherwise the tangent at the new point decides (it is
    // needed anyway: it becomes the next step's tangent).
    const bool fell = !first && cur.lambda > 0 && next.lambda < cur.lambda * (1 - 1e-6);
    const double width = std::abs(next.lambda - cur.lambda);
    const bool refine =
        width > opt.critical_tolerance * std::max(std::abs(cur.lambda), 1e-300) && ds > ds_min;
    if (!(fell && refine) &&
        !count_negative(asmb, base_negative, *solver_work, next, res.factorizations)) {
      if (!cut_back()) break;
      continue;
    }
    const bool event = fell || next.negative > base_negative;
    spdlog::debug(
        "arc-length attempt: ds {:.4g}, {} its, lambda {:.8g} -> {:.8g}, fell {}, "
        "negative {}, event {}",
        ds, its, cur.lambda, next.lambda, fell, next.negative, event);
    if (event) {
      if (refine) {
        // Refine: go back to the last stable point with half the radius.
        bracketing = true;
        ds *= 0.5;
        continue;
      }
      // Bracketed: classify with the tangent at the last stable point.
      critical = true;
      stable_state = cur.state;
      lam_crit = classify_critical(mesh, *solver_cur, ut_cur, cur, next, lam_max, base_negative,
                                   res);
      ++res.steps;
      res.path.push_back({next.lambda, max_displacement(mesh, next.state), next.negative});
      if (opt.on_point) opt.on_point(next.state, next.lambda);
      cur = std::move(next);
      break;
    }
    // Accept the step: the new point's factorised tangent becomes the current one.
    std::swap(solver_cur, solver_work);
    ut_cur = solver_cur->solve(mesh.load);
    ++res.steps;
    first = false;
    cur = std::move(next);
    lam_max = std::max(lam_max, cur.lambda);
    const double umax = max_displacement(mesh, cur.state);
    res.path.push_back({cur.lambda, umax, cur.negative});
    if (opt.on_point) opt.on_point(cur.state, cur.lambda);
    if (cur.lambda >= opt.max_lambda) {
      res.stop_reason = "maximum load factor reached";
      break;
    }
    if (opt.max_displacement > 0 && umax >= opt.max_displacement) {
      res.stop_reason = "maximum displacement reached";
      break;
    }
    stable_state = cur.state;
    if (!bracketing) {
      ds = std::min(next_radius(ds, its, opt.desired_iterations, ds_max), ceiling);
      ceiling *= 1.05;
    }
    spdlog::debug("arc-length step {}: lambda {:.6g}, u {:.4g}, {} its, {} factorisations",
                  res.steps, cur.lambda, umax, its, res.factorizations);
    report_path_progress(opt, res.steps, umax, cur.lambda);
  }
  report_progress(opt.progress, "non-linear path", 1.0,
                  fmt::format("{} steps, λ = {:.4g}", res.steps, cur.lambda));
  if (critical) {
    res.lambda_critical = lam_crit;
    if (res.stop_reason.empty()) res.stop_reason = "critical point found";
  } else {
    res.lambda_critical = lam_max;
    if (res.stop_reason.empty()) res.stop_reason = "maximum number of steps";
  }
  res.critical_state = stable_state;
  res.final_state = cur.state;
  return res;
}

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
