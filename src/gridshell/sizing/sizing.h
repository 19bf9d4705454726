#pragma once
/// \file sizing.h
/// Member sizing: the lightest section of a list for every member of a grid-shell (or for N
/// groups of members), such that under every load combination (analysis/load_cases.h)
///
/// * every member check is ≤ 1 under every ULS combination (checks/member_checks.h: EN 1993-1-1
///   §6.2 cross-section and §6.3 member buckling, at the analysed section forces);
/// * the largest displacement under every SLS combination is ≤ span / deflection divisor
///   (FrameAnalysisOptions::deflection_limit_divisor; the paper's load: its one combination);
/// * the critical load factor of every ULS combination is ≥ `lambda_min` — the non-linear one
///   with the unfavourable imperfection when the analysis level is `nonlinear` (the same rule
///   and figures as `structure.combinations`: analysis/combination_runs.h), else λ_LBA.
///
/// Method (docs/sizing.md): a fixed-point iteration of analysis and resizing, cheap checks first.
///  1. Strength: each member takes the lightest section of the list whose checks pass under the
///     section forces of every ULS combination of the last analysis (statically indeterminate:
///     forces follow stiffness, hence the iteration). After `free_iterations` a member may only
///     move to a section at least as large in A and I_min (a ratchet, which makes the iteration
///     monotone and so finite).
///  2. Stiffness: when δ (SLS) or λ_LBA (ULS) misses its target, members are upgraded in order
///     of benefit per kilogram — for δ the member's share of the strain energy of each SLS
///     combination over its limit times its stiffness gain, for λ its share of the buckling
///     mode's strain energy (FrameResult::mode_energy) of each ULS combination under the target
///     times its gain: first-order estimates of dδ and dλ (Rayleigh quotient) — until the
///     estimated gains cover every shortfall. Upgrades are floors: a member never goes below
///     them again.
///  3. Groups (`groups` = N > 0): members sorted by the mass of the section they need are cut
///     into at most N contiguous groups minimising Σ length × mass of the group's heaviest need
///     (dynamic programming over the distinct needs); each group takes the lightest section
///     that passes for all of its members.
///  4. At the fixed point the design is analysed at the full level; when the non-linear λ misses
///     `lambda_min`, the λ_LBA target is raised by the measured knock-down λ / λ_LBA and the
///     iteration resumes (at most `max_rounds` rounds).
///
/// The result is `sized` only when the final analysis passes every check; otherwise `failure`
/// names the check, the member and the combination (never a design reported as safe that is
/// not). Deterministic. Cost: per iteration one factorisation of K shared by every combination
/// (analysis/frame_loads.h: a solve per combination, an LBA per ULS one) and O(members × list)
/// cheap section checks; per round a probe (one combination's non-linear paths), and at the end
/// the full analysis, which takes the last probe's paths when they are of the same design.

#include <string>
#include <vector>

#include "gridshell/analysis/combination_runs.h"
#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/mesh/mesh.h"
#include "gridshell/sections/sections.h"

namespace gridshell::sizing {

/// Whether the members keep the given section or are sized (`--size`).
enum class MemberSizing { given, sized };

struct SizingOptions {
  /// The sections to choose from (sections::series or a file), any order; at least one.
  std::vector<sections::Section> catalogue;
  int groups = 0;           ///< at most this many distinct sections; 0 = each member its own
  double lambda_min = 1.0;  ///< critical load factor every ULS combination must reach
  int max_iterations = 40;  ///< resizing iterations in all (bounded work)
  int free_iterations = 3;  ///< iterations before the ratchet (step 1)
  int max_rounds = 4;       ///< non-linear probes and verifications (step 4)
  /// Margin on the stiffness targets: upgrades aim at δ ≤ limit / (1 + margin) and
  /// λ_LBA ≥ target (1 + margin), so that the first-order estimates need fewer rounds.
  double target_margin = 0.03;
};

/// One iteration of the fixed point (report.json `sizing.history`).
struct SizingStep {
  int iteration = 0;
  std::string phase;           ///< "strength", "stiffness", "verify"
  double mass_kg = 0;          ///< steel of the design analysed in this iteration
  double utilisation_max = 0;  ///< largest member check over the ULS combinations
  double delta_ratio = 0;      ///< largest SLS δ / its limit
  double lambda = 0;           ///< smallest ULS λ analysed (λ_LBA, or non-linear in "verify")
  int changed = 0;             ///< members whose section changed after it
  double seconds = 0;          ///< its analysis
};

struct SizingResult {
  bool sized = false;  ///< the final design passes every check
  /// Per member (topology edge order) its section; set also when not sized (the last design).
  std::vector<sections::Section> member_sections;
  int iterations = 0;
  std::string convergence;  ///< how the iteration ended, one line
  std::string failure;      ///< empty when sized: the failing check, member and combination
  std::vector<SizingStep> history;
  double lambda_lba_target = 0;  ///< the λ_LBA target of the last round
  /// The final analysis: per combination (names in `combinations`) its result at the level
  /// asked, by the rule of analysis/combination_runs.h; `primary` indexes the ULS (or paper)
  /// one, whose result is the design's `structure`.
  std::vector<analysis::LoadCombination> combinations;
  analysis::CombinationRunsResult final;
  std::size_t primary = 0;
};

/// Sizes the members of the grid-shell `mesh` (its frame as analysis/gridshell_frame.h builds
/// it from `frame`, whose `member_sections` are ignored) at analysis level `level` (linear: no
/// λ check; buckling: λ_LBA; nonlinear: the imperfect non-linear λ). Throws Error("--sections")
/// for an empty list and what the analyses throw.
SizingResult size_members(const PolyMesh& mesh, const std::vector<int>& supports,
                          const analysis::GridshellFrameOptions& frame,
                          const analysis::FrameAnalysisOptions& analysis,
                          analysis::AnalysisLevel level, const SizingOptions& options);

/// The load combinations the design is judged by: the eurocode ones of analysis/load_cases.h for
/// `frame`'s member sections, or one "paper" combination (ULS and SLS at once: the paper's
/// load). `primary`: the index of "ULS" / "paper".
std::vector<analysis::LoadCombination> design_combinations(
    const PolyMesh& mesh, const analysis::GridshellFrameOptions& frame,
    std::size_t* primary = nullptr);

/// Every combination of `frame` analysed by the rule of analysis/combination_runs.h, the primary
/// at `level` (the design's analysis), the others as the rule says.
analysis::CombinationRunsResult analyze_combinations(
    const PolyMesh& mesh, const std::vector<int>& supports,
    const analysis::GridshellFrameOptions& frame, const analysis::FrameAnalysisOptions& analysis,
    analysis::AnalysisLevel level, const std::vector<analysis::LoadCombination>& combinations,
    std::size_t primary);

/// Mass [kg] of steel of a frame: Σ length × mass per metre of each member's section.
double steel_mass(const PolyMesh& mesh, const analysis::GridshellFrameOptions& frame);

/// The sections of a file (`--sections FILE`): one designation per line (sections.h), `#`
/// comments and blank lines ignored. Throws Error("--sections") naming the line of a bad one.
std::vector<sections::Section> read_section_list(const std::string& path);
/// `--sections WORD|FILE`: a series word of sections::parse_series ("chs", "rhs", "chs cold",
/// "bar"), else a file.
std::vector<sections::Section> parse_section_list(const std::string& text);

}  // namespace gridshell::sizing
