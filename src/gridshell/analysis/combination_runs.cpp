#include "gridshell/analysis/combination_runs.h"

#include <algorithm>
#include <limits>

namespace gridshell::analysis {

CombinationRunsResult run_combinations(const std::vector<CombinationRun>& combinations,
                                       const FrameResult& primary,
                                       const AnalyzeCombination& analyze) {
  const bool buckling =
      primary.lambda_linear_buckling.has_value() || !primary.buckling_lambdas.empty();
  const bool nonlinear =
      !primary.path.empty() || primary.lambda_perfect || primary.lambda_imperfect;
  CombinationRunsResult out;
  out.results.resize(combinations.size());
  out.nonlinear.assign(combinations.size(), 0);
  double lba_min = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < combinations.size(); ++k) {
    const CombinationRun& c = combinations[k];
    if (c.primary) {
      out.results[k] = primary;
      out.nonlinear[k] = nonlinear;
    } else {
      out.results[k] =
          analyze(k, c.uls && buckling ? AnalysisLevel::buckling : AnalysisLevel::linear);
    }
    if (c.uls && out.results[k].lambda_linear_buckling)
      lba_min = std::min(lba_min, *out.results[k].lambda_linear_buckling);
  }
  for (std::size_t k = 0; k < combinations.size() && nonlinear; ++k) {
    const CombinationRun& c = combinations[k];
    const std::optional<double>& lba = out.results[k].lambda_linear_buckling;
    if (c.primary || !c.uls || !lba || *lba > (1 + kNonlinearMargin) * lba_min) continue;
    out.results[k] = analyze(k, AnalysisLevel::nonlinear);
    out.nonlinear[k] = 1;
  }
  return out;
}

}  // namespace gridshell::analysis
