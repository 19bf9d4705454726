// A finely meshed input: `design builtin:paraboloid:res=354 --cells 1000 -D 3 -A 3
// --analyze linear` — 250 632 triangles — at the resolution the cells need (the default) and at
// the input's (goal: ≤ 10 s and ≤ 1 GB on 2 idle cores; docs/shell.md "Analysis resolution").
// Peak RSS is the process's, so run one benchmark per process for the memory figure:
//   ./build/fine_input_bench --benchmark_filter=cells
//   ./build/fine_input_bench --benchmark_filter=input

#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <spdlog/spdlog.h>

#include "gridshell/pipeline/design.h"
#include "gridshell/surfaces/builtin.h"

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

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
