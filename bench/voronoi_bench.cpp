// Tessellation engine benchmarks and quality figures.
//
//   ./build/voronoi_bench                       Google Benchmark: one Lloyd iteration at ≥ 250 K
//                                               support vertices / ~3 K seeds, and the whole
//                                               tessellation of Aquadom at ~1200 cells
//   ./build/voronoi_bench --figures [cells...]  prints the quality table (hex share, CV, valence,
//                                               Euler, loops, time) on every built-in and shared
//                                               surface at the given cell counts (default 300 1500)
//   ./build/voronoi_bench --lengths             --length runs at the paper's lengths

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "gridshell/mesh/topology.h"
#include "gridshell/surfaces/builtin.h"
#include "gridshell/surfaces/load.h"
#include "gridshell/voronoi/tessellation.h"

using namespace gridshell;

namespace {

std::string shared(const std::string& name) {
  return std::string(GRIDSHELL_SHARED_DIR) + "/data/surfaces/" + name;
}

const std::vector<std::string> kSurfaces = {"builtin:dome",           "builtin:paraboloid",
                                            "builtin:barrel",         "builtin:court",
                                            "builtin:funicular",      shared("Shell.ply"),
                                            shared("Botanic.ply"),    shared("BritishQuadTang.ply"),
                                            shared("Neumunster.ply"), shared("aquadom_Vouga.ply"),
                                            shared("liliumVouga.ply")};

void BM_LloydIteration(benchmark::State& state) {
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const Surface s = load_surface(shared("aquadom_Vouga.ply"));
  // Support edges 0.3 R at 3000 seeds give ≥ 250 K support vertices on Aquadom.
  LloydBenchmark last;
  for (auto _ : state) {
    last = benchmark_lloyd(s.mesh, 3000, 0.3, 2);
    state.SetIterationTime(last.seconds);
  }
  state.counters["support_vertices"] = last.support_vertices;
  state.counters["seeds"] = last.seeds;
}
BENCHMARK(BM_LloydIteration)->UseManualTime()->Unit(benchmark::kMillisecond)->Iterations(3);

/// The whole tessellation of Aquadom at 1200 cells (the speed goal: ≤ 3 s). Arg = worker threads
/// (0 = all). Counters: wall and process CPU seconds, CVT diagrams computed, interior hexagon
/// share, edge-length CV, support vertices.
void BM_TessellateAquadom(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                            threads > 0 ? threads : tbb::this_task_arena::max_concurrency());
  const Surface s = load_surface(shared("aquadom_Vouga.ply"));
  TessellationOptions o;
  o.cells = 1200;
  Tessellation T;
  double wall = 0, cpu = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    T = tessellate(s.mesh, s.mesh, s.supports, o);
    cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
    wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  state.counters["wall_s"] = wall;
  state.counters["cpu_s"] = cpu;
  state.counters["iterations"] = T.iterations;
  state.counters["hex_share"] = T.quality.hex_share_interior;
  state.counters["cv"] = T.quality.edge_length_cv;
  state.counters["support_vertices"] = T.support_vertices;
  std::cout << fmt::format(
      "Aquadom 1200 cells, {} thread(s): {:.2f} s wall, {:.2f} s CPU, {} CVT diagrams{}, "
      "{} faces, interior hexagons {:.1f}%, edge CV {:.3f}, {} support vertices\n",
      threads > 0 ? threads : tbb::this_task_arena::max_concurrency(), wall, cpu, T.iterations,
      T.converged ? "" : " (not converged)", T.quality.faces, 100 * T.quality.hex_share_interior,
      T.quality.edge_length_cv, T.support_vertices);
}
BENCHMARK(BM_TessellateAquadom)->Arg(0)->Arg(1)->Unit(benchmark::kSecond)->Iterations(1);

/// CV of the edges with both ends off the boundary.
double interior_cv(const PolyMesh& m) {
  const Topology t = build_topology(m);
  double s = 0, s2 = 0;
  int n = 0;
  for (const auto& e : t.edges) {
    if (t.on_boundary[e[0]] || t.on_boundary[e[1]]) continue;
    const double l = (m.vertex(e[0]) - m.vertex(e[1])).norm();
    s += l;
    s2 += l * l;
    ++n;
  }
  if (n == 0) return 0;
  const double mean = s / n;
  return std::sqrt(std::max(0.0, s2 / n - mean * mean)) / mean;
}

int figures(const std::vector<int>& counts) {
  std::cout << fmt::format(
      "{:<22} {:>6} {:>6} {:>5} {:>6} {:>6} {:>6} {:>6} {:>5} {:>5} {:>8} {:>7}\n", "surface",
      "target", "faces", "iter", "hex%", "val3%", "CV", "CVint", "euler", "loops", "supp.V",
      "time s");
  for (const std::string& name : kSurfaces) {
    if (const char* only = std::getenv("VOR_ONLY"))
      if (name.find(only) == std::string::npos) continue;
    Surface s;
    try {
      s = load_surface(name);
    } catch (const std::exception& e) {
      std::cout << name << ": " << e.what() << "\n";
      continue;
    }
    const Topology topo = build_topology(s.mesh);
    const int euler = s.mesh.num_vertices() - topo.num_edges() + s.mesh.num_faces();
    for (int n : counts) {
      TessellationOptions o;
      o.cells = n;
      if (const char* e = std::getenv("VOR_ITERS")) o.max_iterations = std::atoi(e);
      if (const char* e = std::getenv("VOR_TOL")) o.tolerance = std::atof(e);
      if (const char* e = std::getenv("VOR_BS")) o.boundary_spacing = std::atof(e);
      if (const char* e = std::getenv("VOR_SPLIT")) o.boundary_split = std::atof(e);
      if (const char* e = std::getenv("VOR_FINE")) o.fine_iterations = std::atoi(e);
      if (const char* e = std::getenv("VOR_OMEGA")) o.over_relaxation = std::atof(e);
      if (const char* e = std::getenv("VOR_COARSE")) o.coarse_edge = std::atof(e);
      if (const char* e = std::getenv("VOR_CTOL")) o.coarse_tolerance = std::atof(e);
      if (const char* e = std::getenv("VOR_XBASE")) o.extraction_base = std::atof(e);
      if (const char* e = std::getenv("VOR_QN")) o.quasi_newton = std::atoi(e) != 0;
      if (const char* e = std::getenv("VOR_HIST")) o.lbfgs_history = std::atoi(e);
      if (const char* e = std::getenv("VOR_SUPPORT")) o.support_edge = std::atof(e);
      const auto t0 = std::chrono::steady_clock::now();
      const std::clock_t c0 = std::clock();
      try {
        const Tessellation T = tessellate(s.mesh, s.mesh, s.supports, o);
        const double sec =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const auto& q = T.quality;
        const double cvi = interior_cv(T.mesh);
        const std::string base = name.substr(name.find_last_of("/:") + 1);
        std::cout << fmt::format(
            "{:<22} {:>6} {:>6} {:>5} {:>6.1f} {:>6.1f} {:>6.3f} {:>6} {:>2}/{:<2} {:>2}/{:<2} "
            "{:>8} {:>7.2f}\n",
            base, n, q.faces, T.iterations, 100 * q.hex_share_interior,
            100 * q.valence3_share_interior, q.edge_length_cv, fmt::format("{:.3f}", cvi), q.euler,
            euler, q.boundary_loops, topo.boundary_loops.size(), T.support_vertices, sec);
        if (std::getenv("VOR_TIMES"))
          std::cout << fmt::format(
              "    setup {:.2f} s, lloyd {:.2f} s, extraction {:.2f} s (wall); CPU {:.2f} s\n",
              T.seconds_setup, T.seconds_lloyd, T.seconds_extraction,
              double(std::clock() - c0) / CLOCKS_PER_SEC);
      } catch (const std::exception& e) {
        std::cout << name << " " << n << ": FAILED " << e.what() << "\n";
      }
    }
  }
  return 0;
}

int lengths() {
  const std::vector<std::pair<std::string, double>> cases = {{shared("Shell.ply"), 415},
                                                             {shared("Botanic.ply"), 2018},
                                                             {shared("aquadom_Vouga.ply"), 3898}};
  for (const auto& [name, L] : cases) {
    const Surface s = load_surface(name);
    TessellationOptions o;
    o.length = L;
    const auto t0 = std::chrono::steady_clock::now();
    const Tessellation T = tessellate(s.mesh, s.mesh, s.supports, o);
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << fmt::format(
        "{:<22} target {:>7.1f} m  got {:>8.2f} m  error {:>+6.2f}%  cells {:>5}  "
        "runs {}  hex {:.1f}%  CV {:.3f}  {:.1f} s\n",
        name.substr(name.find_last_of('/') + 1), L, T.quality.total_length,
        100 * (T.quality.total_length / L - 1), T.quality.faces, T.length_runs,
        100 * T.quality.hex_share_interior, T.quality.edge_length_cv, sec);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(std::getenv("VOR_DEBUG") ? spdlog::level::debug : spdlog::level::warn);
  if (argc > 1 && std::strcmp(argv[1], "--figures") == 0) {
    std::vector<int> counts;
    for (int i = 2; i < argc; ++i) counts.push_back(std::atoi(argv[i]));
    if (counts.empty()) counts = {300, 1500};
    return figures(counts);
  }
  if (argc > 1 && std::strcmp(argv[1], "--lengths") == 0) return lengths();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
