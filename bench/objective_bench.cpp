// The objective search (design --objective) as a whole, wall time on all cores:
//
//   ./build/objective_bench                        Botanic at 2018 m (the goal's ~1200-cell
//                                                  surface, goal ≤ 60 s on 2 cores) and the
//                                                  built-in default surface at 300 cells (the
//                                                  default `gridshell design` searches: ≤ 10 s
//                                                  including its non-linear analysis)
//   ./build/objective_bench --benchmark_filter=Mass  `--objective mass` on Botanic at the
//                                                  default 300 cells, eurocode loads, final
//                                                  sizing non-linear (goal ≤ 120 s on 2 cores)
//
// Each benchmark runs the search once (balanced; every objective searches the same pool) with
// the final analysis at LBA, and reports the number of candidate designs and the chosen one's
// λ_LBA and δ ratios to the isotropic reference.

#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include <spdlog/spdlog.h>

#include "gridshell/pipeline/objective.h"
#include "gridshell/surfaces/load.h"

using namespace gridshell;

namespace {

void run_search(benchmark::State& state, const std::string& surface_spec, double length) {
  spdlog::set_level(spdlog::level::warn);
  if (surface_spec.rfind("builtin:", 0) != 0 && !std::filesystem::exists(surface_spec)) {
    state.SkipWithError("shared data absent");
    return;
  }
  const Surface surface = load_surface(surface_spec);
  DesignOptions base;
  base.tessellation.length = length;
  base.analyze = analysis::AnalysisLevel::buckling;
  ObjectiveResult r;
  for (auto _ : state) r = design_for_objective(surface, base);
  state.counters["designs"] = static_cast<double>(r.candidates.size());
  const Candidate& c = r.candidates[r.chosen];
  state.counters["lambda_ratio"] = c.lambda / r.candidates.front().lambda;
  state.counters["delta_ratio"] = c.delta / r.candidates.front().delta;
}

void BM_ObjectiveBotanic(benchmark::State& state) {
  run_search(state, std::string(GRIDSHELL_SHARED_DIR) + "/data/surfaces/Botanic.ply", 2018);
}
BENCHMARK(BM_ObjectiveBotanic)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void BM_ObjectiveDefaultSurface(benchmark::State& state) {
  run_search(state, "builtin:funicular", 0);
}
BENCHMARK(BM_ObjectiveDefaultSurface)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

/// `design Botanic.ply --objective mass`: 11 candidates sized at LBA, the lightest sized again
/// with the imperfect non-linear λ; counters: designs, the final mass and the saving against the
/// lightest isotropic candidate.
void BM_ObjectiveMassBotanic(benchmark::State& state) {
  spdlog::set_level(spdlog::level::warn);
  const std::string spec = std::string(GRIDSHELL_SHARED_DIR) + "/data/surfaces/Botanic.ply";
  if (!std::filesystem::exists(spec)) {
    state.SkipWithError("shared data absent");
    return;
  }
  const Surface surface = load_surface(spec);
  DesignOptions base;
  base.frame.loads = analysis::LoadModel::eurocode;
  ObjectiveOptions o;
  o.objective = Objective::mass;
  ObjectiveResult r;
  for (auto _ : state) r = design_for_objective(surface, base, o);
  state.counters["designs"] = static_cast<double>(r.candidates.size());
  state.counters["mass_kg"] = r.mass_kg;
  state.counters["saving_vs_iso"] = r.mass_saving_vs_isotropic;
}
BENCHMARK(BM_ObjectiveMassBotanic)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
