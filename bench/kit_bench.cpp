// The model kit (gridshell kit, kit/kit.h), wall time on all cores:
//
//   ./build/kit_bench    BM_KitBotanic1200: the whole kit (every joint's STL, the print plates,
//                        rods, panels, assembly page) of a 1200-cell design of Botanic (D = A = 3,
//                        no analysis; 2408 joints) at 1:20 with 3 mm rods (at 1:50 its shortest
//                        beams leave no room for two sockets) — goal ≤ 30 s on 2 cores;
//                        BM_KitDome: the 12-cell dome of the tests at 1:50.
//
// The design folders are made once, before the timed loop. Counters: joints, plates.

#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include <spdlog/spdlog.h>

#include "gridshell/fabrication/fabrication_files.h"
#include "gridshell/kit/kit.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/surfaces/load.h"

using namespace gridshell;

namespace {

const std::string kBotanic = std::string(GRIDSHELL_SHARED_DIR) + "/data/surfaces/Botanic.ply";

/// A design folder (joints.csv, beams.csv, panels.csv) of `cells` cells of `surface`.
std::filesystem::path design_folder(const std::string& surface, int cells,
                                    const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "gridshell_kit_bench" / name;
  std::filesystem::create_directories(dir);
  DesignOptions o;
  o.tessellation.cells = cells;
  o.analyze = analysis::AnalysisLevel::none;
  const DesignResult r = run_design(load_surface(surface), o);
  fabrication::write_fabrication_files(dir, r.mesh, r.supports, {});
  return dir;
}

void run_kit(benchmark::State& state, const std::filesystem::path& design, double scale) {
  kit::KitOptions options;
  options.scale = scale;
  const std::filesystem::path out = design.parent_path() / (design.filename().string() + "_kit");
  kit::KitResult r;
  for (auto _ : state) r = kit::write_kit(design, out, options);
  state.counters["joints"] = r.joints;
  state.counters["plates"] = r.plates;
  std::filesystem::remove_all(out);
}

void BM_KitBotanic1200(benchmark::State& state) {
  spdlog::set_level(spdlog::level::warn);
  if (!std::filesystem::exists(kBotanic)) {
    state.SkipWithError("shared data absent");
    return;
  }
  run_kit(state, design_folder(kBotanic, 1200, "botanic_1200"), 20);
}
BENCHMARK(BM_KitBotanic1200)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void BM_KitDome(benchmark::State& state) {
  spdlog::set_level(spdlog::level::warn);
  run_kit(state, design_folder("builtin:dome", 12, "dome_12"), 50);
}
BENCHMARK(BM_KitDome)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
