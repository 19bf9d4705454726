// `gridshell studio`'s /api/design over HTTP on the built-in surface (builtin:funicular, D = A
// = 2, linear + LBA): the whole answer as the page gets it (design, analysis, JSON). Each
// request has a new seed, so that the server's last-design cache never answers.
// BM_StudioDesign: the server has designed the same surface, D, A and cells before with another
// seed (its DesignCache holds the stress, field and M′: a new seed or a re-design on the page);
// BM_StudioDesignFirst: a new server's first design. Goals (docs/studio.md): median ≤ 1 s at
// 300 cells, ≤ 3 s at 1000 cells.
// Counter process_cpu_s: the whole process's CPU time per request (server threads included) — on
// a busy machine the wall time is several times this, on an idle one about equal (the pipeline
// is mostly serial).
// Run: ./build/studio_bench  (medians of 7 requests each; --benchmark_filter=/1000 for one size)

#include <benchmark/benchmark.h>

#include <ctime>

#include <spdlog/spdlog.h>

#include "gridshell/studio/server.h"

#include <httplib.h>  // last: its <resolv.h> defines `_res`, which breaks Eigen headers after it

using namespace gridshell;

namespace {

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::string design_query(int cells, int seed) {
  return "/api/design?surface=builtin:funicular&D=2&A=2&cells=" + std::to_string(cells) +
         "&seed=" + std::to_string(seed);
}

/// `warm`: the server has designed the same surface, D, A and cells before (another seed), so
/// the request finds the analysis surface, stress, field and M′ in the server's DesignCache — a
/// new seed or a re-design on the page; else the server's first design (a new server).
void studio_design(benchmark::State& state, bool warm) {
  spdlog::set_level(spdlog::level::warn);
  studio::ServerOptions options;
  options.port = 0;
  studio::Server server(options);
  const int port = server.start();
  httplib::Client client("127.0.0.1", port);
  client.set_read_timeout(600, 0);
  client.set_default_headers({{"X-Gridshell-Token", server.token()}});  // the page's token
  static int seed = 100;
  const int cells = static_cast<int>(state.range(0));
  const auto ok = [](const httplib::Result& res) { return res && res->status == 200; };
  if (warm && !ok(client.Get(design_query(cells, 1)))) {
    state.SkipWithError("priming request failed");
    return;
  }
  std::size_t bytes = 0;
  double cpu = 0;
  for (auto _ : state) {
    const double cpu0 = process_cpu_seconds();
    const auto res = client.Get(design_query(cells, ++seed));
    if (!ok(res)) {
      state.SkipWithError("request failed");
      break;
    }
    bytes = res->body.size();
    cpu += process_cpu_seconds() - cpu0;
  }
  state.counters["answer_MB"] = static_cast<double>(bytes) / 1e6;
  state.counters["process_cpu_s"] = cpu / static_cast<double>(state.iterations());
  server.stop();
}

void BM_StudioDesign(benchmark::State& state) {
  studio_design(state, true);
}
void BM_StudioDesignFirst(benchmark::State& state) {
  studio_design(state, false);
}
/// Both cases: 300 and 1000 cells, 7 single requests each, medians reported.
void studio_cases(benchmark::internal::Benchmark* b) {
  b->Arg(300)->Arg(1000)->Iterations(1)->Repetitions(7)->ReportAggregatesOnly(true);
  b->UseRealTime()->Unit(benchmark::kMillisecond);
}
BENCHMARK(BM_StudioDesign)->Apply(studio_cases);
BENCHMARK(BM_StudioDesignFirst)->Apply(studio_cases);

}  // namespace

BENCHMARK_MAIN();
