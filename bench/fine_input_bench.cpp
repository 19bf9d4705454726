// A finely meshed input: `design builtin:paraboloid:res=354 --cells 1000 -D 3 -A 3
// --analyze linear` — 250 632 triangles — at the resolution the cells need (the default) and at
// the input's (goal: ≤ 10 s and ≤ 1 GB on 2 idle cores; docs/shell.md "Analysis resolution").
// The default objective search on fine inputs (the whole of `design builtin:paraboloid:res=N
// [--cells 1000] --analyze linear` but the files): res=354 at 1000 cells (goal ≤ 6 s, ≤ 600
// MiB), res=1000 (2 M triangles) at 1000 cells (≤ 30 s, ≤ 2 GiB) and at the default 300 cells
// (≤ 20 s, ≤ 2 GiB); docs/performance.md "Fine CAD meshes".
// Peak RSS is the process's, so run one benchmark per process for the memory figure:
//   ./build/fine_input_bench --benchmark_filter=cells
//   ./build/fine_input_bench --benchmark_filter=input
//   ./build/fine_input_bench --benchmark_filter=Search/res354_1000
//   ./build/fine_input_bench --benchmark_filter=Search/res1000_1000
//   ./build/fine_input_bench --benchmark_filter=Search/res1000_300

#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <spdlog/spdlog.h>

#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/objective.h"
#include "gridshell/surfaces/builtin.h"
#include "gridshell/surfaces/load.h"

using namespace gridshell;

namespace {

void BM_FineParaboloidDesign(benchmark::State& state, AnalysisResolution resolution) {
  BuiltinOptions b;
  b.res = 354;
  const Surface s = make_builtin("paraboloid", b);
  DesignOptions o;
  o.field_options.D = o.field_options.A = 3;
  o.tessellation.cells = 1000;
  o.analyze = analysis::AnalysisLevel::linear;
  o.analysis_resolution = resolution;
  DesignResult r;
  for (auto _ : state) {
    r = run_design(s, o);
    benchmark::DoNotOptimize(r.metrics.total_length);
  }
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  state.counters["input_triangles"] = s.mesh.num_faces();
  state.counters["analysis_triangles"] =
      r.details.contains("analysis_surface")
          ? r.details["analysis_surface"]["triangles"].get<double>()
          : static_cast<double>(s.mesh.num_faces());
  state.counters["cells"] = r.mesh.num_faces();
  state.counters["delta_mm"] = r.structure ? 1e3 * r.structure->delta_max_m : 0;
  for (const auto& [stage, seconds] : r.timings) state.counters[stage + "_s"] = seconds;
  state.counters["peak_rss_MB"] = ru.ru_maxrss / 1024.0;
}
BENCHMARK_CAPTURE(BM_FineParaboloidDesign, cells, AnalysisResolution::cells)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_FineParaboloidDesign, input, AnalysisResolution::input)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

/// The default objective search (balanced: 7–11 candidates at equal length) on the paraboloid
/// at `res`, `cells` cells (0: the default 300), analysis linear; loading the built-in included.
void BM_FineParaboloidSearch(benchmark::State& state, int res, int cells) {
  ObjectiveResult r;
  int triangles = 0;
  for (auto _ : state) {
    const Surface s = load_surface("builtin:paraboloid:res=" + std::to_string(res));
    triangles = s.mesh.num_faces();
    DesignOptions o;
    o.tessellation.cells = cells;
    o.analyze = analysis::AnalysisLevel::linear;
    r = design_for_objective(s, o);
    benchmark::DoNotOptimize(r.design.metrics.total_length);
  }
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  state.counters["input_triangles"] = triangles;
  state.counters["designs"] = static_cast<double>(r.candidates.size());
  state.counters["cells"] = r.design.mesh.num_faces();
  state.counters["field_triangles"] = r.design.field.size();
  state.counters["peak_rss_MB"] = ru.ru_maxrss / 1024.0;
}
BENCHMARK_CAPTURE(BM_FineParaboloidSearch, res354_1000, 354, 1000)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_FineParaboloidSearch, res1000_1000, 1000, 1000)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_FineParaboloidSearch, res1000_300, 1000, 0)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
