// `gridshell studio`'s /api/design over HTTP on the built-in surface (builtin:funicular, D = A
// = 2, linear + LBA): the whole answer as the page gets it (design, analysis, JSON). Each
// request has a new seed, so that the server's last-design cache never answers. Goals
// (docs/studio.md): median ≤ 1 s at 300 cells, ≤ 3 s at 1000 cells.
// Run: ./build/studio_bench  (medians of 7 requests each)

#include <benchmark/benchmark.h>

#include <spdlog/spdlog.h>

#include "gridshell/studio/server.h"

#include <httplib.h>  // last: its <resolv.h> defines `_res`, which breaks Eigen headers after it

using namespace gridshell;

namespace {

void BM_StudioDesign(benchmark::State& state) {
  spdlog::set_level(spdlog::level::warn);
  studio::ServerOptions options;
  options.port = 0;
  studio::Server server(options);
  const int port = server.start();
  httplib::Client client("127.0.0.1", port);
  client.set_read_timeout(600, 0);
  static int seed = 100;
  std::size_t bytes = 0;
  for (auto _ : state) {
    const auto res = client.Get("/api/design?surface=builtin:funicular&D=2&A=2&cells=" +
                                std::to_string(state.range(0)) + "&seed=" + std::to_string(++seed));
    if (!res || res->status != 200) {
      state.SkipWithError("request failed");
      break;
    }
    bytes = res->body.size();
  }
  state.counters["answer_MB"] = static_cast<double>(bytes) / 1e6;
  server.stop();
}
BENCHMARK(BM_StudioDesign)
    ->Arg(300)
    ->Arg(1000)
    ->Iterations(1)
    ->Repetitions(7)
    ->ReportAggregatesOnly(true)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
