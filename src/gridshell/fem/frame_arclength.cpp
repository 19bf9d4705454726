#include "gridshell/fem/frame_arclength.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <tuple>

#include <boost/math/tools/toms748_solve.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

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

/// How one arc-length step ended.
enum class StepOutcome {
  converged,  ///< the corrector met the tolerance: the step's point is the path's next
  /// Diverged, no convergence in max_iterations, or a singular or non-finite solve: a shorter
  /// step may converge.
  failed,
  /// The iterate went past a critical point of a stable path and the last stable tangent no
  /// longer contracts the residual: the radius reaches beyond the critical point.
  crossed,
};

/// What ArcStepper::step returns: how it ended and, when converged, the new point (without its
/// tangent factorised) and the corrector's iterations.
struct StepResult {
  StepOutcome outcome = StepOutcome::failed;
  int iterations = 0;
  Converged point;
};

/// One arc-length step's corrector state: the iterate, its increment from the step's start, the
/// tangent in use and its load tangent ut = K⁻¹f, and what the refresh policy remembers.
struct Corrector {
  FrameState st;
  Eigen::VectorXd du, ut;
  double lam = 0, dlam = 0;  ///< the iterate's λ; the predictor's Δλ
  const TangentSolver* solver = nullptr;
  double rprev = 0;  ///< the previous iteration's residual norm
  int last_refresh = 0, growing = 0, refreshes = 0;
  /// The predicted point (iteration 1), kept for a refresh at iteration 2 (see ArcStepper::step).
  struct Iterate {
    FrameState state;
    Eigen::VectorXd du, r;
    double lambda = 0, rn = 0;
  } predicted;
  bool fresh = false;        ///< the tangent in use is that of the previous iterate
  bool stable_only = false;  ///< a refreshed tangent was indefinite
};

/// The arc-length steps of one path: what stays fixed along it (model, assembler, the norm's
/// weights W, options, whether the start was already indefinite) and the path's count of
/// factorisations, which every refreshed tangent adds to.
class ArcStepper {
 public:
  ArcStepper(const FrameMesh& mesh, const FrameAssembler& asmb, const Eigen::VectorXd& W,
             const ArcLengthOptions& opt, bool indefinite_start, int& factorizations)
      : mesh_(mesh),
        asmb_(asmb),
        W_(W),
        opt_(opt),
        indefinite_start_(indefinite_start),
        factorizations_(factorizations),
        node_elements_(opt.relaxation ? node_elements(mesh) : std::vector<std::vector<int>>{}) {}

  /// One arc-length step from `from` with radius ds. `start` holds the factorised tangent at the
  /// start point and ut0 = K⁻¹f; neither is modified, so a failed or refined step needs no
  /// refactorisation. Refreshed tangents go into `work`.
  StepResult step(const TangentSolver& start, const Eigen::VectorXd& ut0, TangentSolver& work,
                  const Converged& from, double ds, bool first) const;
  /// Local relaxations done so far.
  int relaxations() const { return relaxations_; }

 private:
  bool predict(const Converged& from, double ds, bool first, Corrector& c) const;
  std::optional<StepOutcome> watch(Corrector& c, int it, double rho, double tol, double scale,
                                   Eigen::VectorXd& r, double& rn, TangentSolver& work) const;
  bool correct(Corrector& c, const Eigen::VectorXd& r, double ds) const;
  bool relax(Corrector& c, Eigen::VectorXd& r, double rn, Eigen::VectorXd& fint,
             std::vector<Vec12>& forces) const;

  const FrameMesh& mesh_;
  const FrameAssembler& asmb_;
  const Eigen::VectorXd& W_;
  const ArcLengthOptions& opt_;
  bool indefinite_start_;
  int& factorizations_;
  std::vector<std::vector<int>> node_elements_;  ///< for the local relaxation
  mutable int relaxations_ = 0;
};

/// The predictor: along the load tangent c.ut, with the sign that keeps the path's direction
/// (λ increasing on the first step), to arc length ds. False when the load tangent is zero.
bool ArcStepper::predict(const Converged& from, double ds, bool first, Corrector& c) const {
  const Eigen::VectorXd& ut = c.ut;
  const double nt = std::sqrt(ut.dot(W_.cwiseProduct(ut)));
  if (!(nt > 0)) return false;
  double sign = 1;
  if (!first) sign = from.du.dot(W_.cwiseProduct(ut)) >= 0 ? 1 : -1;
  c.dlam = sign * ds / nt;
  c.du = c.dlam * ut;
  c.st = from.state;
  apply_increment(mesh_, c.du, c.st);
  c.lam = from.lambda + c.dlam;
  return true;
}

/// From iteration 2 on: whether the step is to stop (diverging, or crossing a critical point),
/// and the tangent's refresh when the residual contracts too slowly (see step). A refresh at
/// iteration 2 first goes back to the predicted point (the iterate, r and rn with it).
std::optional<StepOutcome> ArcStepper::watch(Corrector& c, int it, double rho, double tol,
                                             double scale, Eigen::VectorXd& r, double& rn,
                                             TangentSolver& work) const {
  c.growing = rho >= 1 ? c.growing + 1 : 0;
  // Past a critical point with the last stable tangent and no contraction: the step
  // crosses the critical point and would only iterate to max_iterations; a shorter one is
  // cheaper (StepOutcome::crossed tells the caller).
  if (c.stable_only && rho >= 1) {
    spdlog::debug("  crossing a critical point at iteration {}", it);
    return StepOutcome::crossed;
  }
  // Diverging: the residual keeps growing, or grows with a fresh tangent after the
  // refreshes an attempt may spend (the step is too long: a shorter one is cheaper).
  if (c.growing >= 4 || (c.refreshes >= kMaxRefreshes && rho >= 1)) {
    spdlog::debug("  diverging at iteration {}", it);
    return StepOutcome::failed;
  }
  const bool slow = rho >= 1 || std::log(tol / rn) / std::log(rho) > kRefreshIterations;
  if (!(slow && it - c.last_refresh >= 2 && !c.stable_only && c.refreshes < kMaxRefreshes))
    return std::nullopt;
  c.last_refresh = it;
  ++c.refreshes;
  if (it == 2) {
    const Corrector::Iterate& p = c.predicted;
    std::tie(c.st, c.du, r, c.lam, rn) = std::tie(p.state, p.du, p.r, p.lambda, p.rn);
    spdlog::debug("  back to the predicted point");
  }
  if (!factorize_tangent(asmb_, c.st, work, factorizations_)) return StepOutcome::failed;
  spdlog::debug("  refresh at iteration {}: residual {:.3g}, contraction {:.3g}, {}", it,
                rn / scale, rho, work.positive_definite() ? "positive definite" : "indefinite");
  // An indefinite tangent (the iterate is past a critical point of a path that started
  // stable) is not used: its solves would amplify the critical mode and can throw the
  // iterate onto another branch; the last stable tangent is kept.
  if (work.positive_definite() || indefinite_start_) {
    c.solver = &work;
    c.ut = work.solve(mesh_.load);
    if (!c.ut.allFinite()) return StepOutcome::failed;
    c.fresh = true;
  } else {
    c.stable_only = true;  // past a critical point: no further refreshes in this step
    if (rho >= 1) {
      spdlog::debug("  crossing a critical point at iteration {}", it);
      return StepOutcome::crossed;
    }
  }
  return std::nullopt;
}

/// One corrector iteration: the residual's solve with the tangent in use and the λ-correction
/// that keeps the increment on the sphere of radius ds (the root nearer the previous increment).
/// False when the solve or the constraint fails.
bool ArcStepper::correct(Corrector& c, const Eigen::VectorXd& r, double ds) const {
  const Eigen::VectorXd& ut = c.ut;
  const Eigen::VectorXd ur = c.solver->solve(r);
  const Eigen::VectorXd base = c.du + ur;
  const double a = ut.dot(W_.cwiseProduct(ut));
  const double b = 2 * ut.dot(W_.cwiseProduct(base));
  const double cc = base.dot(W_.cwiseProduct(base)) - ds * ds;
  if (!(a > 0)) return false;
  // No real root (the stale tangent near a limit point): take the λ-correction that comes
  // closest to the constraint; the following iterations restore it.
  const double disc = std::max(b * b - 4 * a * cc, 0.0);
  const double sq = std::sqrt(disc);
  const double q = -0.5 * (b + (b >= 0 ? sq : -sq));
  double r1 = q / a, r2 = q != 0 ? cc / q : r1;
  const Eigen::VectorXd d1 = base + r1 * ut, d2 = base + r2 * ut;
  const double c1 = d1.dot(W_.cwiseProduct(c.du)), c2 = d2.dot(W_.cwiseProduct(c.du));
  const double dl = c1 >= c2 ? r1 : r2;
  const Eigen::VectorXd corr = ur + dl * ut;
  if (!corr.allFinite()) return false;
  c.du += corr;
  c.lam += dl;
  apply_increment(mesh_, corr, c.st);
  return true;
}

/// The local relaxation of the iterate where its residual r is concentrated (the increment
/// c.du takes the region's displacement, so the next correction keeps the arc-length
/// constraint); kept only when the whole residual falls (a region balanced against held
/// neighbours can push more onto them than it took off), and then r and fint are those of the
/// relaxed iterate. False when nothing changed.
bool ArcStepper::relax(Corrector& c, Eigen::VectorXd& r, double rn, Eigen::VectorXd& fint,
                       std::vector<Vec12>& forces) const {
  FrameState st = c.st;
  Eigen::VectorXd du = c.du;
  std::vector<Vec12> relaxed_forces = forces;
  const LocalRelaxResult lr =
      relax_locally(mesh_, node_elements_, c.lam, r, st, du, *opt_.relaxation, &relaxed_forces);
  if (!lr.relaxed) return false;
  // Only the region's elements changed: the sum of the forces is internal_force(st), bit for bit.
  Eigen::VectorXd f = sum_element_forces(mesh_, relaxed_forces);
  Eigen::VectorXd rr = c.lam * mesh_.load - asmb_.reduce(f);
  const double after = rr.norm();
  spdlog::debug("  relaxed {} nodes ({} iterations): residual {:.3g} -> {:.3g}{}", lr.nodes,
                lr.iterations, rn / mesh_.load.norm(), after / mesh_.load.norm(),
                after < rn ? "" : ", not kept");
  if (!(after < rn)) return false;
  ++relaxations_;
  c.st = std::move(st);
  c.du = std::move(du);
  fint = std::move(f);
  forces = std::move(relaxed_forces);
  r = std::move(rr);
  return true;
}

// Modified Newton: the start tangent is kept while the residual contracts fast enough
// (linear convergence, each iteration one residual and one solve); it is refreshed at the
// current iterate when the contraction rate predicts more than kRefreshIterations iterations,
// except at iteration 2: there the tangent is refreshed at the predicted point, not at the
// iterate. On a softening path the start tangent's first correction throws the iterate along
// the soft mode, away from the path (its residual grows ×1.5–2.5 on the Aquadom designs), and a
// tangent taken there contracts only ×0.3–0.4 per iteration, where the one at the predicted
// point gives a nearly quadratic first iteration (×1e-3): the steps can then be 2–4× longer.
StepResult ArcStepper::step(const TangentSolver& start, const Eigen::VectorXd& ut0,
                            TangentSolver& work, const Converged& from, double ds,
                            bool first) const {
  const Eigen::VectorXd& f = mesh_.load;
  Corrector c;
  c.solver = &start;
  c.ut = ut0;  // K⁻¹f of the tangent in use
  if (!predict(from, ds, first, c)) return {};
  const double fnorm = f.norm();
  Eigen::VectorXd fint;
  std::vector<Vec12> forces;  // per element, for the local relaxation
  for (int it = 1; it <= opt_.max_iterations; ++it) {
    fint = asmb_.internal_force(c.st, nullptr, opt_.relaxation ? &forces : nullptr);
    Eigen::VectorXd r = c.lam * f - asmb_.reduce(fint);
    if (!r.allFinite()) return {};
    const double scale = fnorm * std::max(std::abs(c.lam), 1e-3 * std::abs(c.dlam));
    double rn = r.norm();
    // A residual concentrated on a few nodes is relaxed there first (fem/frame_relax.h), except
    // at iteration 2, where the corrector may go back to the predicted point and refresh its
    // tangent there (watch): a relaxed iterate would hide the overshoot that refresh is for
    // (relaxed at iteration 2 too, locate_crossing's shorter steps on the perfect Aquadom path
    // crossed the critical point and did not converge).
    if (opt_.relaxation && it != 2 && relax(c, r, rn, fint, forces)) rn = r.norm();
    // A stale tangent converges linearly and stops just below the tolerance, where Newton's
    // quadratic convergence would overshoot it by far: the modified corrector iterates on to
    // kPolish × tolerance (each iteration is cheap) and accepts the plain tolerance only when
    // the contraction stalls. The residual left in a near-critical mode acts as an imperfection,
    // so this keeps perfect structures on their fundamental path up to a bifurcation.
    const double tol = opt_.tolerance * scale * kPolish;
    const double rho = it >= 2 ? rn / c.rprev : 0;
    const bool floor = (rn <= opt_.tolerance * scale && rho >= 0.5) ||
                       (c.fresh && it >= 3 && rn <= 1e-5 * scale && rho >= 0.5);
    if (rn <= tol || floor) {
      StepResult done{StepOutcome::converged, it, {}};
      done.point.state = std::move(c.st);
      done.point.lambda = c.lam;
      done.point.du = c.du;
      done.point.dlambda = c.lam - from.lambda;
      return done;
    }
    c.fresh = false;
    if (it == 1) c.predicted = {c.st, c.du, r, c.lam, rn};
    if (it >= 2)
      if (const auto stop = watch(c, it, rho, tol, scale, r, rn, work)) return {*stop, 0, {}};
    c.rprev = rn;
    if (!correct(c, r, ds)) return {};
  }
  spdlog::debug("  no convergence in {} iterations", opt_.max_iterations);
  return {};
}

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
                TangentSolver& solver, Converged& cur, Eigen::VectorXd& ut, ArcLengthResult& res) {
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

// A path's last three points at an event: (−r_prev, λ_prev), (0, λ_cur), (r, λ_next) in arc length.
struct LimitBracket {
  double r_prev = 0, lam_prev = 0, lam_cur = 0, r = 0, lam_next = 0;
};

// The top of the parabola λ(s) through a limit point's bracket. Near a limit point λ(s) is
// smooth with its maximum among the points: their own largest λ is O(r²) below it wherever the
// bracket falls (a step straddling the top stops on both sides of it, equally low), the vertex
// O(r³). −∞ where the parabola opens upwards or its vertex lies outside the points (no earlier
// point: the first step).
double limit_lambda(const LimitBracket& b) {
  const double a = b.r_prev, r = b.r;
  if (!(a > 0 && r > 0)) return -HUGE_VAL;
  const double up = (b.lam_next - b.lam_cur) / r, down = (b.lam_prev - b.lam_cur) / a;
  const double q = (up + down) / (a + r), p = up - q * r;  // λ = λ_cur + p s + q s²
  if (!(q < 0)) return -HUGE_VAL;
  const double s = -p / (2 * q);
  return s >= -a && s <= r ? b.lam_cur - p * p / (4 * q) : -HUGE_VAL;
}

// A bracketed event, classified with the tangent at the last stable point `cur` and its softest
// mode φ. At a new negative pivot: near a limit point the load tangent v = K⁻¹f is dominated by φ
// (φᵀf ≠ 0); at a bifurcation φ ⟂ f and v has no large component along φ. At a fall of λ
// without a new pivot the corrector may already have slipped onto a buckled branch through a
// bifurcation whose pivot change it never saw (a perfect portal frame's sway; φ is no longer
// ⟂ f there): it is a limit point only if the path's displacement so far lies mostly along φ
// (a limit point's softening mode grows with the load: Lee's frame 0.76, the deep arch 0.75,
// the star dome 1.0; the portal frame 0.31). Sets res's alignment and limit type; returns the
// critical load factor: the bracket's middle at a pivot bifurcation, the top of λ(s) at a limit
// point (limit_lambda), else the largest λ.
double classify_critical(const FrameMesh& mesh, const TangentSolver& solver,
                         const Eigen::VectorXd& ut, const Converged& cur, const Converged& next,
                         double lam_max, int base_negative, const LimitBracket& bracket,
                         ArcLengthResult& res) {
  Eigen::VectorXd phi;
  const double along = critical_mode_alignment(solver, ut, mesh.num_dofs, phi);
  res.critical_mode_alignment = along;
  const bool pivot = next.negative > base_negative;
  const bool bifurcation =
      pivot ? along < 0.5 : along < 0.5 || path_alignment(mesh, cur.state, phi) < 0.5;
  res.limit_type = bifurcation ? LimitType::bifurcation : LimitType::limit_point;
  if (bifurcation && pivot) return 0.5 * (cur.lambda + next.lambda);
  const double top = std::max({cur.lambda, next.lambda, lam_max});
  return bifurcation ? top : std::max(top, limit_lambda(bracket));
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

/// One arc-length path being traced: the current (last converged) point with its factorised
/// tangent, the radius and its bounds, what has been found so far, and the result being filled.
/// arc_length runs attempt() until it says stop, then finish().
class PathWalker {
 public:
  PathWalker(const FrameMesh& mesh, const FrameAssembler& asmb, const ArcLengthOptions& opt,
             const FrameState& start, ArcLengthResult& res)
      : mesh_(mesh), asmb_(asmb), opt_(opt), res_(res), W_(arc_weights(mesh)) {
    cur_.state = start;
    stable_state_ = start;
  }

  /// The path's first point and tangent (start_path), the initial radius and the stepper. False
  /// when the initial tangent is singular (res says so).
  bool begin(const FrameState& start);
  /// One attempted step: cut back, refined, bracketed or accepted. False when the path ends.
  bool attempt();
  /// The critical load factor, the stop reason (when none was set) and the states.
  void finish();
  /// λ of the last converged point.
  double lambda() const { return cur_.lambda; }

 private:
  bool cut_back();
  bool retry_shorter(StepOutcome outcome);
  void bracketed(Converged& next);
  bool accept(Converged& next, int its);
  std::vector<double> crossing_values(const FrameState& state, double lambda) const;
  void record_crossings(const Converged& next);

  const FrameMesh& mesh_;
  const FrameAssembler& asmb_;
  const ArcLengthOptions& opt_;
  ArcLengthResult& res_;
  const Eigen::VectorXd W_;
  // solver_cur_: the factorised tangent at the current point, with its load tangent
  // ut_cur_ = K⁻¹f; solver_work_: refreshed and candidate tangents.
  std::unique_ptr<TangentSolver> solver_cur_ =
      std::make_unique<TangentSolver>(Refactorisation::repeated);
  std::unique_ptr<TangentSolver> solver_work_ =
      std::make_unique<TangentSolver>(Refactorisation::repeated);
  Converged cur_;
  Eigen::VectorXd ut_cur_;
  std::vector<double> crossing_cur_;  // the crossings' quantities at cur_
  std::optional<ArcStepper> stepper_;
  double ds_ = 0, ds_min_ = 0, ds_max_ = 0;
  double lam_max_ = 0;
  double prev_lambda_ = 0, prev_radius_ = 0;  // the point before cur_ and the radius from it
  bool first_ = true;
  bool critical_ = false;  // an event has been bracketed
  double lam_crit_ = 0;
  int base_negative_ = 0;
  FrameState stable_state_;
  bool bracketing_ = false;
  double ceiling_ = 0;  // lowered after a step that crossed into the unstable region
  bool cut_since_accept_ = false;  // a cut-back since the last accepted step
  int stalled_ = 0;                // accepted steps in a row that barely raised λ after a cut-back
  int pinned_ = 0;                 // of those, the ones in a row that raised it by next to nothing
};

bool PathWalker::begin(const FrameState& start) {
  for (TangentSolver* s : {solver_cur_.get(), solver_work_.get()})
    s->analyze_like(opt_.analysis.get(), asmb_.pattern());
  if (!start_path(mesh_, asmb_, start, *solver_cur_, cur_, ut_cur_, res_)) return false;
  if (opt_.on_point) opt_.on_point(start, 0.0);
  crossing_cur_ = crossing_values(start, 0.0);
  res_.crossing_steps.assign(opt_.crossings.size(), std::nullopt);
  const double ds0 = opt_.initial_lambda * std::sqrt(ut_cur_.dot(W_.cwiseProduct(ut_cur_)));
  ds_ = ds0;
  ds_min_ = 1e-7 * ds0;
  ds_max_ = 50 * ds0;
  base_negative_ = cur_.negative;
  ceiling_ = ds_max_;
  stepper_.emplace(mesh_, asmb_, W_, opt_, base_negative_ != 0, res_.factorizations);
  return true;
}

// A failed step halves the arc length; false (with the reason set) once it is below ds_min.
bool PathWalker::cut_back() {
  ++res_.cutbacks;
  cut_since_accept_ = true;
  ds_ *= 0.5;
  if (ds_ >= ds_min_) return true;
  res_.stop_reason = "the arc-length step could not converge";
  return false;
}

// After a step that did not converge: a shorter radius, or false when it is below ds_min.
bool PathWalker::retry_shorter(StepOutcome outcome) {
  if (outcome == StepOutcome::failed) return cut_back();
  // The iterate went into the unstable region (often the predictor overshooting a stiff
  // bend, not the critical point itself): retry a little shorter and keep the radius below
  // this one for a while, instead of halving and growing back into the same failure.
  ++res_.cutbacks;
  cut_since_accept_ = true;
  ceiling_ = ds_ = 0.7 * ds_;
  if (ds_ >= ds_min_) return true;
  res_.stop_reason = "the arc-length step could not converge";
  return false;
}

// Bracketed: the event is classified with the tangent at the last stable point, and `next`
// becomes the path's last point.
void PathWalker::bracketed(Converged& next) {
  critical_ = true;
  stable_state_ = cur_.state;
  const LimitBracket bracket{prev_radius_, prev_lambda_, cur_.lambda, ds_, next.lambda};
  lam_crit_ = classify_critical(mesh_, *solver_cur_, ut_cur_, cur_, next, lam_max_, base_negative_,
                                bracket, res_);
  ++res_.steps;
  res_.path.push_back({next.lambda, max_displacement(mesh_, next.state), next.negative});
  if (opt_.on_point) opt_.on_point(next.state, next.lambda);
  cur_ = std::move(next);
}

// Accepts the step: the new point's factorised tangent becomes the current one, and the radius
// follows the iterations it took. False when a stop rule is met.
bool PathWalker::accept(Converged& next, int its) {
  record_crossings(next);
  std::swap(solver_cur_, solver_work_);
  ut_cur_ = solver_cur_->solve(mesh_.load);
  ++res_.steps;
  first_ = false;
  // λ's gain, counted only for a step accepted after a cut-back (crept, pinned: options).
  const double gain = cut_since_accept_ ? next.lambda - cur_.lambda : HUGE_VAL;
  const double at = std::abs(cur_.lambda);
  stalled_ = gain < opt_.stall_tolerance * at ? stalled_ + 1 : 0;
  pinned_ = opt_.pinned_tolerance > 0 && gain < opt_.pinned_tolerance * at ? pinned_ + 1 : 0;
  cut_since_accept_ = false;
  prev_lambda_ = cur_.lambda;
  prev_radius_ = ds_;
  cur_ = std::move(next);
  lam_max_ = std::max(lam_max_, cur_.lambda);
  const double umax = max_displacement(mesh_, cur_.state);
  res_.path.push_back({cur_.lambda, umax, cur_.negative});
  if (opt_.on_point) opt_.on_point(cur_.state, cur_.lambda);
  if (cur_.lambda >= opt_.max_lambda) {
    res_.stop_reason = "maximum load factor reached";
    return false;
  }
  if (opt_.max_displacement > 0 && umax >= opt_.max_displacement) {
    res_.stop_reason = "maximum displacement reached";
    return false;
  }
  stable_state_ = cur_.state;
  if (opt_.stall_steps > 0 && (stalled_ >= opt_.stall_steps || pinned_ >= 2)) {
    res_.stop_reason = "the path stalled below a limit it could not pass";
    spdlog::debug("arc-length step {}: lambda {:.8g}, stalled", res_.steps, cur_.lambda);
    return false;
  }
  if (!bracketing_) {
    ds_ = std::min(next_radius(ds_, its, opt_.desired_iterations, ds_max_), ceiling_);
    ceiling_ *= 1.05;
  }
  spdlog::debug("arc-length step {}: lambda {:.6g}, u {:.4g}, {} its, {} factorisations",
                res_.steps, cur_.lambda, umax, its, res_.factorizations);
  report_path_progress(opt_, res_.steps, umax, cur_.lambda);
  return true;
}

bool PathWalker::attempt() {
  StepResult step = stepper_->step(*solver_cur_, ut_cur_, *solver_work_, cur_, ds_, first_);
  res_.iterations += step.iterations;
  if (step.outcome != StepOutcome::converged) return retry_shorter(step.outcome);
  Converged& next = step.point;
  // A fall of λ is an event by itself; otherwise the tangent at the new point decides (it is
  // needed anyway: it becomes the next step's tangent).
  const bool fell = !first_ && cur_.lambda > 0 && next.lambda < cur_.lambda * (1 - 1e-6);
  const double width = std::abs(next.lambda - cur_.lambda);
  const bool refine =
      width > opt_.critical_tolerance * std::max(std::abs(cur_.lambda), 1e-300) && ds_ > ds_min_;
  if (!(fell && refine) &&
      !count_negative(asmb_, base_negative_, *solver_work_, next, res_.factorizations))
    return cut_back();
  const bool event = fell || next.negative > base_negative_;
  spdlog::debug(
      "arc-length attempt: ds {:.4g}, {} its, lambda {:.8g} -> {:.8g}, fell {}, "
      "negative {}, event {}",
      ds_, step.iterations, cur_.lambda, next.lambda, fell, next.negative, event);
  if (!event) return accept(next, step.iterations);
  if (!refine) {
    bracketed(next);
    return false;
  }
  // Refine: go back to the last stable point with half the radius.
  bracketing_ = true;
  ds_ *= 0.5;
  return true;
}

std::vector<double> PathWalker::crossing_values(const FrameState& state, double lambda) const {
  std::vector<double> out;
  for (const PathCrossing& c : opt_.crossings) out.push_back(c.value(state, lambda));
  return out;
}

// Before `next` (converged from cur_ with radius ds_) is accepted: the step is recorded for each
// crossing whose quantity rises from below its level at cur_ to it or above at `next`, the first
// time any step reaches the level.
void PathWalker::record_crossings(const Converged& next) {
  if (opt_.crossings.empty()) return;
  const std::vector<double> values = crossing_values(next.state, next.lambda);
  for (std::size_t k = 0; k < values.size(); ++k) {
    const double level = opt_.crossings[k].level;
    if (res_.crossing_steps[k] || !(values[k] >= level) || !(crossing_cur_[k] < level)) continue;
    res_.crossing_steps[k] = CrossingStep{cur_.state, cur_.lambda,     next.lambda,
                                          cur_.du,    ds_,             crossing_cur_[k],
                                          values[k],  base_negative_ != 0};
  }
  crossing_cur_ = values;
}

void PathWalker::finish() {
  report_progress(opt_.progress, "non-linear path", 1.0,
                  fmt::format("{} steps, λ = {:.4g}", res_.steps, cur_.lambda));
  if (critical_) {
    res_.lambda_critical = lam_crit_;
    if (res_.stop_reason.empty()) res_.stop_reason = "critical point found";
  } else {
    res_.lambda_critical = lam_max_;
    if (res_.stop_reason.empty()) res_.stop_reason = "maximum number of steps";
  }
  res_.critical_state = stable_state_;
  res_.final_state = cur_.state;
  if (stepper_) res_.relaxations = stepper_->relaxations();
}

}  // namespace

struct ArcLengthPath::State {
  State(const FrameMesh& mesh, const FrameAssembler& asmb, const ArcLengthOptions& opt,
        const FrameState& start)
      : opt(opt), start(start), walker(mesh, asmb, opt, start, res) {}
  const ArcLengthOptions& opt;
  FrameState start;
  ArcLengthResult res;
  PathWalker walker;
  bool begun = false, walked = false;  // begin() called; begin() succeeded
};

ArcLengthPath::ArcLengthPath(const FrameMesh& mesh, const FrameAssembler& asmb,
                             const ArcLengthOptions& opt, const FrameState& start)
    : state_(std::make_unique<State>(mesh, asmb, opt, start)) {}

ArcLengthPath::~ArcLengthPath() = default;

bool ArcLengthPath::advance() {
  if (ended_) return false;
  State& s = *state_;
  if (!s.begun) {
    s.begun = true;
    s.walked = s.walker.begin(s.start);
    s.start = FrameState();  // begin() has copied what it needs
    if (!s.walked) ended_ = true;
    return !ended_;
  }
  if (s.res.steps >= s.opt.max_steps || !s.walker.attempt()) ended_ = true;
  return !ended_;
}

double ArcLengthPath::lambda() const { return state_->walker.lambda(); }

ArcLengthResult ArcLengthPath::finish(const std::string& reason) {
  State& s = *state_;
  if (!ended_ && s.res.stop_reason.empty()) s.res.stop_reason = reason;
  ended_ = true;
  if (s.walked) s.walker.finish();
  return std::move(s.res);
}

ArcLengthResult arc_length(const FrameMesh& mesh, const FrameAssembler& asmb,
                           const ArcLengthOptions& opt, const FrameState& start) {
  ArcLengthPath path(mesh, asmb, opt, start);
  while (path.advance()) {
  }
  return path.finish("");
}

namespace {
/// A point found on a crossing's step: its quantity minus the level, and its λ.
struct CrossingSample {
  double g = 0, lambda = 0;
};

/// λ at the level from the samples nearest to it on either side (linear in the quantity).
double interpolate_level(const std::map<double, CrossingSample>& seen) {
  const CrossingSample *below = nullptr, *above = nullptr;
  for (const auto& [s, sample] : seen) {  // in the order of the radius
    if (sample.g < 0) below = &sample;
    if (sample.g >= 0 && !above) above = &sample;
  }
  if (!below || !above || above->g == below->g) return above ? above->lambda : below->lambda;
  const double t = -below->g / (above->g - below->g);
  return below->lambda + t * (above->lambda - below->lambda);
}
}  // namespace

std::optional<double> locate_crossing(const FrameMesh& mesh, const FrameAssembler& asmb,
                                      const ArcLengthOptions& opt, const PathCrossing& crossing,
                                      const CrossingStep& step, int& factorizations,
                                      double tolerance) {
  TangentSolver start(Refactorisation::repeated), work(Refactorisation::repeated);
  for (TangentSolver* s : {&start, &work}) s->analyze_like(opt.analysis.get(), asmb.pattern());
  if (!factorize_tangent(asmb, step.from, start, factorizations)) return std::nullopt;
  const Eigen::VectorXd ut = start.solve(mesh.load);
  if (!ut.allFinite()) return std::nullopt;
  const Eigen::VectorXd W = arc_weights(mesh);
  const ArcStepper stepper(mesh, asmb, W, opt, step.indefinite_start, factorizations);
  Converged from;
  from.state = step.from;
  from.lambda = step.lambda_from;
  from.du = step.du_from;
  const bool first = step.du_from.size() == 0;
  const double level = crossing.level;
  std::map<double, CrossingSample> seen{{0.0, {step.value_from - level, step.lambda_from}},
                                        {step.radius, {step.value_to - level, step.lambda_to}}};
  struct NotFollowed {};
  struct OnLevel {};
  const auto g = [&](double s) {
    const StepResult r = stepper.step(start, ut, work, from, s, first);
    if (r.outcome != StepOutcome::converged) throw NotFollowed{};
    const double v = crossing.value(r.point.state, r.point.lambda) - level;
    if (!std::isfinite(v)) throw NotFollowed{};
    spdlog::debug("crossing: radius {:.6g} of {:.6g}: lambda {:.10g}, quantity - level {:.3g}", s,
                  step.radius, r.point.lambda, v);
    seen[s] = {v, r.point.lambda};
    // Within `tolerance` of the level, the linear reading between this point and the nearest on
    // the other side is off by far less than the quantity's distance to the level.
    if (std::abs(v) <= tolerance * std::abs(level)) throw OnLevel{};
    return v;
  };
  const double width = 1e-7 * step.radius;
  const auto close = [width](double a, double b) { return std::abs(b - a) <= width; };
  std::uintmax_t runs = 40;
  try {
    boost::math::tools::toms748_solve(g, 0.0, step.radius, seen[0.0].g, seen[step.radius].g, close,
                                      runs);
  } catch (const OnLevel&) {
  } catch (const NotFollowed&) {
    spdlog::debug("crossing not located: a shorter step did not converge");
    return std::nullopt;
  }
  return interpolate_level(seen);
}

}  // namespace gridshell::fem
