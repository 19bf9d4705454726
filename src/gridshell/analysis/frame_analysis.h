#pragma once
/// \file frame_analysis.h
/// The structural evaluation of a frame (a grid-shell) as the paper judges it: δ, the largest
/// displacement of a linear analysis under the reference load; λ_LBA, the smallest positive
/// eigenvalue of K + λ K_G; λ, the load factor of the first limit point or bifurcation of the
/// geometrically non-linear path (arc-length), optionally with an imperfection shaped like the
/// first buckling mode; and the non-linear equilibrium at a given factor.
///
/// Cost: linear one sparse Cholesky; the LBA reuses its factor (~60 Lanczos steps of a forward
/// and a back substitution and a K_G product); the non-linear path
/// one corotational tangent + factorisation per step and refresh (Lilium, 7 547 beams: 22 steps,
/// 47 factorisations, 302 cheap corrector iterations).

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gridshell/checks/member_checks.h"
#include "gridshell/core/timings.h"
#include "gridshell/fem/frame_arclength.h"
#include "gridshell/fem/frame_model.h"

namespace gridshell::analysis {

/// How far the analysis goes: `none`; `linear` (δ); `buckling` (+ LBA); `nonlinear` (+ the
/// arc-length path). The option words of `--analyze`.
enum class AnalysisLevel { none, linear, buckling, nonlinear };
AnalysisLevel parse_analysis_level(const std::string& word);  ///< throws Error("--analyze")
const char* to_string(AnalysisLevel level);

/// How far a non-linear path must go to fix the figures asked for. `critical`: to its first
/// critical point (λ, λ_δ, λ_y, the stability block). `displacement_limit`: only λ_δ (and λ_y
/// below it) is asked — e.g. a sweep ranking by λ_δ — so each path stops at its first point past
/// the displacement limit, or at a critical point that comes first; λ (and λ_perfect,
/// λ_imperfect) are then reported only when a critical point came first.
enum class PathGoal { critical, displacement_limit };

/// Arc-length options with initial_lambda = 0 (automatic).
inline fem::ArcLengthOptions automatic_arc() {
  fem::ArcLengthOptions a;
  a.initial_lambda = 0;
  return a;
}

struct FrameResult;

struct FrameAnalysisOptions {
  bool linear = true;           ///< always done when anything else is asked
  bool buckling = true;         ///< linearised buckling (LBA)
  bool nonlinear = true;        ///< arc-length path to the first critical point
  double nonlinear_static = 0;  ///< > 0: also non-linear equilibrium at this load factor
  int buckling_modes = 5;
  bool imperfection = false;          ///< perturb the geometry by the first LBA mode for the path
  double imperfection_amplitude = 0;  ///< [m]; 0 = span / 300 (span = largest plan extent)
  /// The imperfect path in the unfavourable direction: both signs of the first mode and of the
  /// next modes whose λ_LBA is within `imperfection_mode_margin` (10 %) of the first, at most
  /// `imperfection_max_modes` modes; the lowest critical λ is λ_imperfect. Each is one path
  /// (followed in parallel with the perfect one: 5 paths at most by default).
  bool imperfection_both_signs = true;
  double imperfection_mode_margin = 0.10;
  int imperfection_max_modes = 2;
  /// false (default): the candidates are followed together, and one whose λ passes the lowest
  /// critical λ of those that have ended is ended there (it cannot be the lowest); report.json
  /// then gives for it the first λ of its path above the lowest candidate's, below which it has
  /// no critical point (`FrameResult::ImperfectionTry::lambda_above`), whatever the timing.
  /// true: every candidate is followed to its own critical point (each one's λ is reported).
  bool imperfection_full_paths = false;
  /// Arc-length settings and the path's stop rule: initial_lambda ≤ 0 = automatic (λ_LBA / 10,
  /// or the factor giving a linear displacement of span / 2000); max_displacement ≤ 0 = the
  /// automatic stop of `path_reach`; max_lambda ≥ 1e9 = 20 λ_LBA (when there is one); max_steps
  /// as set.
  fem::ArcLengthOptions arc = automatic_arc();
  /// The automatic displacement stop. 0: span / 5 (span = largest plan extent), for grid-shells,
  /// whose path may stiffen into membrane action far beyond any useful λ. > 0: this multiple of
  /// the model's size (the largest extent of its bounding box in any direction), for general
  /// frames (`analyze MODEL.json`: `kGeneralPathReach`), whose first critical point can lie at
  /// displacements of the order of their size (Lee's frame: 0.5 L; a deep arch: about R).
  double path_reach = 0;
  static constexpr double kGeneralPathReach = 3;
  /// The step cap of a general frame's path (`analyze MODEL.json`): stiff members (large EA L²/
  /// EI) make the corotational corrector take small steps on long paths (the deep arch of
  /// docs/frame.md, R / r = 1000: 907 steps to its limit point). Grid-shells: 300.
  static constexpr int kGeneralMaxSteps = 1000;
  /// Displacement limit [m] for λ_δ (FrameResult::lambda_displacement_limit); 0 = span / 100.
  double displacement_limit = 0;
  /// Which figures the paths must fix (the path stops as soon as they are known).
  PathGoal path_goal = PathGoal::critical;
  /// Member checks (checks/member_checks.h): fy and the buckling curve. The linear solution's
  /// section forces are always checked; along the non-linear path they give λ_y.
  checks::MemberCheckOptions checks{};
  /// Serviceability: δ is compared with span / deflection_limit_divisor (300: a common limit
  /// for roofs; span = largest plan extent).
  double deflection_limit_divisor = 300;
  /// With `nonlinear`: follow both the perfect and the imperfect path (first LBA mode scaled to
  /// `imperfection_amplitude`, default span / 300), so that λ_perfect, λ_imperfect and their
  /// ratio are reported together (the stability block). Doubles the path's cost. The path that
  /// sets `lambda_nonlinear` is still the one `imperfection` asks for.
  bool stability = false;
  std::string subject = "model";  ///< named in error messages
  /// Called once with the result when its linear part (displacements, forces, reactions, member
  /// checks) is recorded, before the LBA and the path: a caller may start work that reads only
  /// that part on another thread (`analyze` draws its first figures beside the LBA), copying
  /// what it reads (the result is moved out at the end). Empty: nothing. Changes no result.
  std::function<void(const FrameResult&)> after_linear{};
};

struct FrameResult {
  // The structure block of report.json.
  double delta_max_m = 0;  ///< largest nodal displacement norm (all nodes) under λ = 1
  int delta_node = -1;     ///< model node with the largest displacement (joints only)
  std::optional<double> lambda_linear_buckling;
  std::vector<double> buckling_lambdas;
  std::optional<double> lambda_nonlinear;
  fem::LimitType limit_type = fem::LimitType::none;  ///< report.json words: fem/limit_type.h
  std::string nonlinear_stop_reason;
  /// λ_δ: the load factor at which the non-linear path's largest displacement first reaches
  /// `displacement_limit_m` (linear interpolation between path points), or λ of the first
  /// critical point if that comes first; empty when the path ended before either. Stiff
  /// grid-shells whose path stiffens into membrane action reach their first critical point only
  /// at displacements of a sizeable fraction of the span (λ many times λ_LBA); λ_δ ranks them
  /// by what a designer would accept.
  std::optional<double> lambda_displacement_limit;
  double displacement_limit_m = 0;
  double mass_kg = 0, total_length_m = 0;
  // Per model node / member.
  Points nodes;                     ///< reference coordinates of the model nodes
  Points displacement;              ///< linear, per model node
  std::vector<double> axial_force;  ///< linear, per member (tension positive) [N]
  /// Strain energy per member [J]: of the linear solution under the reference load, and of the
  /// first buckling mode (with the modes within 10 % of its λ, each normalised, averaged: a
  /// symmetric structure's degenerate pairs; scaled to add up to 1; empty without LBA).
  /// Where they concentrate is where more steel would help δ and λ_LBA most (their
  /// sensitivities to a member's stiffness are proportional to these energies).
  std::vector<double> strain_energy, mode_energy;
  /// The buckling modes' shapes (same order as `buckling_lambdas`): the translation of each
  /// model node, scaled so that the largest is 1 (the sign is arbitrary). For pictures and the
  /// report's animation; empty without LBA.
  std::vector<Points> buckling_modes;
  Eigen::VectorXd reactions;        ///< linear, 6 per model node
  double equilibrium_error = 0;     ///< |Σ reactions + Σ loads| / Σ |loads| (forces)
  std::vector<fem::PathPoint> path;
  int nonlinear_steps = 0, nonlinear_iterations = 0;  ///< arc-length effort
  int nonlinear_factorizations = 0;                   ///< tangent factorisations of the path
  /// nonlinear_static results (when asked): per model node.
  std::optional<Points> nonlinear_displacement, nonlinear_rotation;
  std::vector<double> nonlinear_axial_force;
  // Member checks of the linear solution under λ = 1 (per member, the frame's member order).
  std::vector<fem::MemberForces> member_forces;  ///< linear section-force envelopes
  checks::MemberChecks checks;
  // Serviceability.
  double span_m = 0;         ///< largest plan extent of the model nodes
  double delta_limit_m = 0;  ///< span / deflection_limit_divisor
  bool delta_pass = false;   ///< delta_max_m ≤ delta_limit_m
  // Stability (with `stability` and `nonlinear`): the first critical λ of the perfect and of the
  // imperfect structure, and the imperfection amplitude used [m].
  std::optional<double> lambda_perfect, lambda_imperfect;
  double imperfection_amplitude_m = 0;
  /// The imperfection that gave λ_imperfect: buckling mode (0-based) and sign (relative to the
  /// mode's shape in `buckling_modes` / modes.csv), and every one tried with its critical λ.
  int imperfection_mode = -1;
  double imperfection_sign = 0;
  struct ImperfectionTry {
    int mode = 0;
    double sign = 1;
    std::optional<double> lambda;
    /// Set (and `lambda` empty) for a candidate that was ended above the lowest candidate's
    /// critical λ: it has no critical point up to this λ, so it cannot be the lowest
    /// (FrameAnalysisOptions::imperfection_full_paths).
    std::optional<double> lambda_above;
  };
  std::vector<ImperfectionTry> imperfections_tried;
  /// Why λ_imperfect > λ_perfect, when it is (empty otherwise).
  std::string imperfection_note;
  /// λ_y: the load factor at which the largest cross-section utilisation first reaches 1 along
  /// the non-linear path (section forces of the corotational states, linear between path
  /// points); taken on the imperfect path when one is followed. Empty when the path ends first
  /// or none is followed. `lambda_yield_linear` = 1 / utilisation_max (linear estimate).
  std::optional<double> lambda_yield;
  std::string lambda_yield_path;  ///< "perfect" or "imperfect"
  /// The largest cross-section utilisation reached on that path (at its last point: < 1 when
  /// the structure buckles before any bar yields), and λ_y of the perfect path when followed.
  double path_utilisation_max = 0;
  std::optional<double> lambda_yield_perfect;
  std::optional<double> lambda_yield_linear;
  int num_elements = 0, num_dofs = 0;
  Timings timings;  ///< seconds per stage (core/timings.h)
};

/// `options` with linear / buckling / nonlinear set for `level` (none: all three off).
FrameAnalysisOptions at_level(FrameAnalysisOptions options, AnalysisLevel level);

/// Runs the analyses asked for. Throws Error(options.subject) for invalid models and mechanisms.
FrameResult analyze_frame(const fem::FrameModel& model, const FrameAnalysisOptions& options = {});

/// Perturbs the reference geometry of a discretised frame by `amplitude` × `mode` (free dofs,
/// translations) and updates element lengths and frames.
void perturb_geometry(fem::FrameMesh& mesh, const Eigen::VectorXd& mode, double amplitude);

}  // namespace gridshell::analysis
