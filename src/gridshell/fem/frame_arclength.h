#pragma once
/// \file frame_arclength.h
/// Geometrically non-linear analysis of a frame under a proportional load λ·f.
///
/// * `arc_length`: Crisfield's cylindrical arc-length method (constraint on the increment of
///   the translations plus rotations scaled by the mean element length; root picked by the
///   smallest angle with the previous increment; predictor direction by the sign of the previous
///   increment). Modified Newton corrector: the start tangent is kept while the residual
///   contracts and refreshed only when the contraction predicts more iterations than a
///   factorisation costs (when that is seen after the first correction, the tangent is taken at
///   the predicted point rather than at the iterate the stale tangent threw off the path); an
///   indefinite refreshed tangent on a still-stable path is not used;
///   iterations go to 1e-2 × tolerance (a stale tangent stops just below it). Where an
///   iterate's residual sits on a few nodes (a local snap of a flat or weak region near the
///   critical load), those nodes and their neighbours are first brought into equilibrium by a
///   Newton iteration of their own (`relax_locally`), so the global iteration sees a residual
///   its stale tangent can reduce. Adaptive steps
///   (Δs ∝ √(desired / used iterations), cut-backs on failure; an attempt whose iterate went
///   into the unstable region and stopped contracting fails at once, is retried at 0.7× and
///   caps the following radii, the cap rising 5 % a step). After every converged step the
///   factorised tangent is inspected: loss of positive definiteness (or, when the start was
///   already indefinite, a change of the LDLᵀ negative-pivot count), or a fall of λ, marks a
///   critical point. The step is then
///   bisected from the last stable state until the bracket on λ is within `critical_tolerance`;
///   the critical mode φ (inverse iteration on the last stable tangent) classifies it: if the
///   load tangent K⁻¹f is dominated by φ (φᵀf ≠ 0) it is a "limit point" (load maximum),
///   otherwise a "bifurcation" (φ ⟂ f, the path could continue with rising λ). The critical λ
///   of a limit point is the top of the parabola λ(s) through the path's last three points
///   (O(r³) off where the points' own largest λ is O(r²) below: a step can straddle the top);
///   of a bifurcation the bracket's middle (a new pivot) or its largest λ.
///   Crossings: quantities of the state (the largest displacement, the largest utilisation) can
///   be watched for their first rise over a level. The path records the step that carries each
///   over (its start and radius); `locate_crossing` follows that step again with shorter radii
///   until the point on the level is found, so the λ there does not depend on where the path's
///   points fall. Locating is left to the caller because it costs factorisations and usually only
///   one path's crossing is wanted.
/// * `nonlinear_static` (fem/frame_static.h): Newton–Raphson with adaptive load steps up to a
///   given factor.
///
/// Cost: per corrector iteration one internal-force evaluation (~1 µs per element) and one
/// solve; per converged step one tangent assembly (~2 µs per element) and factorisation, plus
/// the refreshes (typically one per step on a strongly non-linear path).

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gridshell/core/progress.h"
#include "gridshell/fem/frame_relax.h"
#include "gridshell/fem/frame_solver.h"
#include "gridshell/fem/frame_static.h"
#include "gridshell/fem/limit_type.h"

namespace gridshell::fem {

/// A quantity of the path's state whose first rise to `level` is wanted (ArcLengthOptions).
struct PathCrossing {
  std::function<double(const FrameState& state, double lambda)> value;
  double level = 1;
};

struct ArcLengthOptions {
  double initial_lambda = 0.05;  ///< load factor of the first predictor step (> 0)
  double max_lambda = 1e9;       ///< stop when λ exceeds this
  double max_displacement = 0;  ///< stop when the largest nodal displacement exceeds this (0 = off)
  int max_steps = 300;
  int desired_iterations = 15;  ///< step control target (modified-Newton iterations)
  int max_iterations = 40;
  double tolerance = 1e-8;           ///< residual norm relative to |λ f|
  double critical_tolerance = 2e-4;  ///< relative width of the bracket on the critical λ
  /// A path has stalled, and ends, when `stall_steps` steps in a row were each accepted only after
  /// a cut-back and each raised λ by less than stall_tolerance·λ: it creeps towards a limit it
  /// cannot pass (the radius shrinking step by step towards its floor). λ_critical is then the
  /// largest λ reached, as for a step that cannot converge; the λ the remaining creep could add
  /// is far below critical_tolerance. 0 steps: never.
  int stall_steps = 3;
  double stall_tolerance = 2e-5;
  /// A path whose last two steps, each accepted after a cut-back, raised λ by less than
  /// pinned_tolerance·λ ends then (when stall_steps > 0): the radius has shrunk to where the creep
  /// adds nothing that could be reported, and the stall's further steps would change λ by as
  /// little (on the real-size Great Court's paths 1e-8 relative, at 10 factorisations a step).
  /// One such step is not enough: the next attempt can still bracket the critical point (the
  /// perfect path of a generated monkey saddle). 0: never.
  double pinned_tolerance = 1e-6;
  bool stop_at_critical = true;
  Progress progress = {};  ///< told after every step (empty: nobody listens)
  /// Called at every point added to the path (λ = 0 first, in path order) with its converged
  /// state: e.g. to evaluate section forces along the path without keeping the states.
  std::function<void(const FrameState& state, double lambda)> on_point;
  /// Quantities whose first crossing the path records (ArcLengthResult::crossing_steps).
  std::vector<PathCrossing> crossings;
  /// The corrector relaxes a residual concentrated on a few nodes locally before its global
  /// iteration (fem/frame_relax.h); empty: never. Changes the iterates, not the path.
  std::optional<LocalRelaxOptions> relaxation = LocalRelaxOptions{};
  /// A symbolic analysis of the tangent's pattern that the path's solvers copy (paths of one
  /// frame's geometries share it: TangentSolver::analyze_like); null: each orders its own.
  std::shared_ptr<const TangentSolver> analysis;
};

/// The accepted step on which a crossing's quantity first reached its level: its start (a
/// converged point of the path and its last increment), its radius, and the quantity at both
/// ends. What locate_crossing needs to follow the step again.
struct CrossingStep {
  FrameState from;
  double lambda_from = 0, lambda_to = 0;
  Eigen::VectorXd du_from;  ///< the increment that led to `from` (empty at the path's start)
  double radius = 0;
  double value_from = 0, value_to = 0;
  bool indefinite_start = false;  ///< the path's start tangent was indefinite
};

struct PathPoint {
  double lambda = 0;
  double displacement = 0;  ///< largest nodal displacement norm
  int negative_pivots = 0;
};

struct ArcLengthResult {
  std::vector<PathPoint> path;  ///< converged points (λ = 0 first)
  double lambda_critical = 0;   ///< first limit point / bifurcation; else the largest λ reached
  LimitType limit_type = LimitType::none;
  FrameState critical_state;  ///< the last stable state before the critical point
  FrameState final_state;
  int steps = 0, iterations = 0, cutbacks = 0;
  int factorizations = 0;  ///< tangent assemblies + factorisations (the dominant cost)
  int relaxations = 0;     ///< local relaxations of the corrector's iterates (frame_relax.h)
  std::string stop_reason;
  double critical_mode_alignment = 0;  ///< |φ·K⁻¹f| / |K⁻¹f| at the last stable point
  /// Per options.crossings: the step that first carried the quantity from below its level to
  /// it or above (empty when no accepted step did).
  std::vector<std::optional<CrossingStep>> crossing_steps;
};

/// Follows the path from `start` (λ = 0, must be the unloaded reference or a stress-free
/// state). Never throws for non-convergence: it reports what it found.
ArcLengthResult arc_length(const FrameMesh& mesh, const FrameAssembler& assembler,
                           const ArcLengthOptions& options, const FrameState& start);

/// The same path traced one attempted step at a time: `arc_length` advances one to its end.
/// A caller can follow several paths at once and end one early (analysis/frame_analysis.cpp
/// ends an imperfection candidate once it has passed a lower candidate's critical point). The
/// points of a path do not depend on when or on which thread it is advanced.
class ArcLengthPath {
 public:
  /// `mesh`, `assembler` and `options` must outlive the path; `start` is copied. Nothing is
  /// computed before the first advance().
  ArcLengthPath(const FrameMesh& mesh, const FrameAssembler& assembler,
                const ArcLengthOptions& options, const FrameState& start);
  ~ArcLengthPath();
  ArcLengthPath(const ArcLengthPath&) = delete;
  ArcLengthPath& operator=(const ArcLengthPath&) = delete;
  /// One attempted step (accepted, cut back, or refining the bracket on a critical point); the
  /// first call factorises the start's tangent. False once the path has ended.
  bool advance();
  bool ended() const { return ended_; }
  /// λ of the path's last converged point (0 before the first step).
  double lambda() const;
  /// The path's result: when it has not ended, it ends here (stop reason `reason`, λ the
  /// largest reached, no critical point). Call once.
  ArcLengthResult finish(const std::string& reason);

 private:
  struct State;
  std::unique_ptr<State> state_;
  bool ended_ = false;
};

/// λ where `crossing` (a PathCrossing and its level) is met on its recorded step: the step is
/// followed again from its start (the tangent there factorised afresh, the same arc-length norm
/// and corrector) with radii chosen by TOMS 748 (Alefeld, Potra, Shi 1995) until a point's
/// quantity is within `tolerance` × level of the level (or the bracket on the radius is 1e-7 of
/// the step's); λ is then interpolated linearly in the quantity between the points nearest the
/// level on either side. `factorizations` counts what it cost (on the 8 327-beam Aquadom design
/// 10–13: 3–4 runs of the step and their refreshed tangents). Empty when
/// a shorter step does not converge (the caller then reads λ off the path's points).
std::optional<double> locate_crossing(const FrameMesh& mesh, const FrameAssembler& assembler,
                                      const ArcLengthOptions& options, const PathCrossing& crossing,
                                      const CrossingStep& step, int& factorizations,
                                      double tolerance = 1e-6);

}  // namespace gridshell::fem
