#pragma once
/// \file combination_runs.h
/// How far each load combination is analysed (docs/checks.md, "Loads and combinations"), one
/// rule for a design's combinations and for a MODEL.json's (`gridshell analyze frame.json`), so
/// that re-analysing a design's frame.json governs by the same combinations:
///
/// * the primary combination is the one analysed in full beforehand (its result is given);
/// * every other ULS combination: linear + LBA when the primary has an LBA, else linear;
///   SLS combinations: linear;
/// * the non-linear path (with the primary's stability and imperfection settings) only for ULS
///   combinations whose λ_LBA is within kNonlinearMargin of the smallest λ_LBA over all ULS
///   combinations (the others cannot govern λ unless their imperfection sensitivity differs by
///   more than that), and only when the primary followed one.
///
/// Cost: one analysis per combination at the level above; the non-linear ones dominate. The
/// combinations are analysed in parallel (TBB; `analyze` must be thread-safe); the results do not
/// depend on the thread count.

#include <cstddef>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "gridshell/analysis/frame_analysis.h"

namespace gridshell::analysis {

inline constexpr double kNonlinearMargin = 0.15;

/// One combination as the rule sees it.
struct CombinationRun {
  bool uls = true;
  bool primary = false;  ///< the combination already analysed in full (its result is given)
};

struct CombinationRunsResult {
  std::vector<FrameResult> results;  ///< per combination (the primary's copied in)
  std::vector<char> nonlinear;       ///< per combination: the non-linear path was followed
};

/// Analyses combination k at `level` (the caller builds its frame and options).
using AnalyzeCombination = std::function<FrameResult(std::size_t k, AnalysisLevel level)>;

/// A ULS combination's governing λ: the smaller of λ_imperfect and λ_perfect (the imperfect one
/// can come out above: FrameResult::imperfection_note), else λ_nonlinear, else λ_LBA; and the
/// name of the figure it is ("lambda_imperfect", …).
std::pair<std::optional<double>, const char*> combination_lambda(const FrameResult& r);

/// Runs the rule above over `combinations`; `primary` is the result of the primary one.
CombinationRunsResult run_combinations(const std::vector<CombinationRun>& combinations,
                                       const FrameResult& primary,
                                       const AnalyzeCombination& analyze);

}  // namespace gridshell::analysis
