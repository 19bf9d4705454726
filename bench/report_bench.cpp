// report.html for a 10 K-beam grid-shell: a 70 × 70 quad grid (5 041 joints, 9 940 beams,
// 4 900 panels) with per-beam forces, per-joint displacements, per-panel density and planarity
// and 5 buckling modes (synthetic values of realistic magnitude), written to a temporary folder.
// Counters: the page's size and its data block's size in MB.
// Run: ./build/report_bench

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>

#include "gridshell/report/assets.h"
#include "gridshell/report/report_html.h"

using namespace gridshell;

namespace {

report::ReportInput large_input(int n) {
  PolyMesh mesh;
  mesh.V.resize((n + 1) * (n + 1), 3);
  std::vector<int> supports;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = 40.0 * i / n - 20, y = 40.0 * j / n - 20;
      mesh.V.row(i * (n + 1) + j) << x, y, 8 - 0.01 * (x * x + y * y) + 0.001 * x * y;
      if (i == 0 || i == n) supports.push_back(i * (n + 1) + j);
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j;
      mesh.faces.push_back({a, a + n + 1, a + n + 2, a + 1});
    }
  report::ReportInput in = report::gridshell_report_input(mesh, supports, nullptr);
  const auto nb = in.beams.size();
  for (std::size_t b = 0; b < nb; ++b) in.axial_force.push_back(-2.5e4 * std::sin(0.37 * b));
  in.displacement = 0.012 * mesh.V.array().sin().matrix();
  for (int f = 0; f < mesh.num_faces(); ++f)
    in.density.push_back(1 + 2 * std::cos(0.1 * f) * std::cos(0.1 * f));
  for (int k = 0; k < 5; ++k) {
    in.buckling_lambdas.push_back(3.1 + k);
    in.buckling_modes.push_back((mesh.V.array() * (0.2 + k)).cos().matrix() / std::sqrt(3.0));
  }
  return in;
}

void BM_ReportHtml10kBeams(benchmark::State& state) {
  const report::ReportInput in = large_input(70);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "gridshell_report_bench";
  std::filesystem::create_directories(dir);
  report::ReportWritten w;
  for (auto _ : state) w = report::write_report_html(dir, in);
  state.counters["beams"] = static_cast<double>(in.beams.size());
  state.counters["page_MB"] = static_cast<double>(w.bytes) / 1e6;
  state.counters["data_MB"] = static_cast<double>(w.bytes - report::viewer_script().size() -
                                                  report::report_template().size()) /
                              1e6;
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_ReportHtml10kBeams)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
