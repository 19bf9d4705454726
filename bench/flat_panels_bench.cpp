// Flat panels (--panels flat, optimize/flat_panels.h), wall time on all cores:
//
//   ./build/flat_panels_bench    Botanic at 2018 m of beams (about 1200 cells, D = A = 3, no
//                                analysis): the whole design with flat panels (goal ≤ 30 s on 2
//                                cores) and the flat-panel stage alone on its free design
//
// Counters: panels, the flat stage's iterations and seconds, the largest corner distance to the
// panel's plane (mm) and the largest joint distance to the surface (mm).

#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include <spdlog/spdlog.h>

#include "gridshell/optimize/flat_panels.h"
#include "gridshell/optimize/projector.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/surfaces/load.h"

using namespace gridshell;

namespace {

const std::string kBotanic = std::string(GRIDSHELL_SHARED_DIR) + "/data/surfaces/Botanic.ply";

DesignOptions botanic_options(PanelMode panels) {
  DesignOptions o;
  o.tessellation.length = 2018;
  o.analyze = analysis::AnalysisLevel::none;
  o.panels = panels;
  return o;
}

void BM_FlatDesignBotanic(benchmark::State& state) {
  spdlog::set_level(spdlog::level::warn);
  if (!std::filesystem::exists(kBotanic)) {
    state.SkipWithError("shared data absent");
    return;
  }
  const Surface surface = load_surface(kBotanic);
  DesignResult r;
  for (auto _ : state) r = run_design(surface, botanic_options(PanelMode::flat));
  state.counters["panels"] = r.mesh.num_faces();
  state.counters["flat"] = r.details["flat_panels"].value("panels", "") == std::string("flat");
  state.counters["flat_s"] = r.timings.get("flat_panels");
  state.counters["out_of_plane_mm"] = 1e3 * r.panels.out_of_plane_max;
  state.counters["surface_mm"] = 1e3 * r.panels.surface_distance_max;
}
BENCHMARK(BM_FlatDesignBotanic)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void BM_FlatStageBotanic(benchmark::State& state) {
  spdlog::set_level(spdlog::level::warn);
  if (!std::filesystem::exists(kBotanic)) {
    state.SkipWithError("shared data absent");
    return;
  }
  const Surface surface = load_surface(kBotanic);
  const DesignResult free = run_design(surface, botanic_options(PanelMode::free));
  const SurfaceProjector projector(surface.mesh);
  FlatPanelResult r;
  for (auto _ : state) r = flat_panels(free.mesh, free.supports, surface.mesh, projector);
  state.counters["panels"] = r.mesh.num_faces();
  state.counters["iterations"] = r.stats.iterations;
  state.counters["out_of_plane_mm"] = 1e3 * r.stats.out_of_plane_max;
}
BENCHMARK(BM_FlatStageBotanic)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
