#include "gridshell/analysis/combination_runs.h"

#include <algorithm>
#include <limits>

#include <tbb/parallel_for.h>

namespace gridshell::analysis {

std::pair<std::optional<double>, const char*> combination_lambda(const FrameResult& r) {
  if (r.lambda_imperfect && (!r.lambda_perfect || *r.lambda_imperfect <= *r.lambda_perfect))
    return {r.lambda_imperfect, "lambda_imperfect"};
  if (r.lambda_perfect) return {r.lambda_perfect, "lambda_perfect"};
  if (r.lambda_nonlinear) return {r.lambda_nonlinear, "lambda_nonlinear"};
  return {r.lambda_linear_buckling, "lambda_lba"};
}

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
  // Each combination is an independent analysis: they run in parallel, each into its own slot.
  tbb::parallel_for(std::size_t{0}, combinations.size(), [&](std::size_t k) {
    const CombinationRun& c = combinations[k];
    if (c.primary) {
      out.results[k] = primary;
      out.nonlinear[k] = nonlinear;
    } else {
      out.results[k] =
          analyze(k, c.uls && buckling ? AnalysisLevel::buckling : AnalysisLevel::linear);
    }
  });
  double lba_min = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < combinations.size(); ++k)
    if (combinations[k].uls && out.results[k].lambda_linear_buckling)
      lba_min = std::min(lba_min, *out.results[k].lambda_linear_buckling);
  std::vector<std::size_t> again;
  for (std::size_t k = 0; k < combinations.size() && nonlinear; ++k) {
    const CombinationRun& c = combinations[k];
    const std::optional<double>& lba = out.results[k].lambda_linear_buckling;
    if (c.primary || !c.uls || !lba || *lba > (1 + kNonlinearMargin) * lba_min) continue;
    again.push_back(k);
  }
  tbb::parallel_for(std::size_t{0}, again.size(), [&](std::size_t i) {
    out.results[again[i]] = analyze(again[i], AnalysisLevel::nonlinear);
    out.nonlinear[again[i]] = 1;
  });
  return out;
}

}  // namespace gridshell::analysis
