// Member sizing (`--size`, sizing/sizing.h), wall time on all cores:
//
//   ./build/sizing_bench    the built-in funicular at D = A = 2 (the default surface, 300 cells,
//                           eurocode loads, hot-finished CHS): the whole sized design at the
//                           non-linear level (goal: ≤ 15 s on 2 cores), and the
//                           sizing alone at the LBA level on the same grid
//
// Counters: members, sized (1/0), mass (kg), iterations, and the seconds of the cheap iterations
// and of the non-linear probes and verification.

#include <benchmark/benchmark.h>

#include <spdlog/spdlog.h>

#include "gridshell/pipeline/design.h"
#include "gridshell/sections/sections.h"
#include "gridshell/sizing/sizing.h"
#include "gridshell/surfaces/load.h"

using namespace gridshell;

namespace {

DesignOptions sized_options(analysis::AnalysisLevel level) {
  DesignOptions o;
  o.field_options.D = o.field_options.A = 2;
  o.analyze = level;
  o.frame.loads = analysis::LoadModel::eurocode;
  o.sizing = sizing::MemberSizing::sized;
  o.sizing_options.catalogue = sections::series(sections::Shape::chs);
  return o;
}

void counters(benchmark::State& state, const DesignResult& r) {
  if (!r.sizing) return;
  const sizing::SizingResult& s = *r.sizing;
  state.counters["members"] = static_cast<double>(s.member_sections.size());
  state.counters["sized"] = s.sized;
  state.counters["iterations"] = s.iterations;
  double cheap = 0, nonlinear = 0;
  for (const sizing::SizingStep& step : s.history)
    (step.phase == "probe" || step.phase == "verify" ? nonlinear : cheap) += step.seconds;
  state.counters["cheap_s"] = cheap;
  state.counters["nonlinear_s"] = nonlinear;
  state.counters["mass_kg"] = r.structure ? r.structure->mass_kg : 0;
}

void sized_funicular(benchmark::State& state, analysis::AnalysisLevel level) {
  spdlog::set_level(spdlog::level::warn);
  const Surface surface = load_surface("builtin:funicular");
  DesignResult r;
  for (auto _ : state) r = run_design(surface, sized_options(level));
  counters(state, r);
}

void BM_SizedDesignFunicular(benchmark::State& state) {
  sized_funicular(state, analysis::AnalysisLevel::nonlinear);
}
BENCHMARK(BM_SizedDesignFunicular)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void BM_SizedDesignFunicularLBA(benchmark::State& state) {
  sized_funicular(state, analysis::AnalysisLevel::buckling);
}
BENCHMARK(BM_SizedDesignFunicularLBA)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
