// Shell analysis benchmarks: a 50 K-triangle solve (goal ≤ 2 s, ≤ 1 GB on 2 cores) and
// convergence studies of the benchmarks of ../shared/reference/benchmarks.md printed as tables
// (copied into docs/shell.md). Run: ./build/shell_bench [--tables]

#include <benchmark/benchmark.h>
#include <link.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>

#include <spdlog/spdlog.h>

#include "gridshell/fem/shell_solver.h"
#include "gridshell/surfaces/builtin.h"
#include "gridshell/surfaces/grid.h"

using namespace gridshell;
using namespace gridshell::fem;

namespace {

constexpr double kPi = std::numbers::pi;

template <class Map>
TriMesh grid(int nu, int nv, Map map) {
  return parametric_grid(nu, nv, [&map](double s, double t) { return Vec3(map(s, t)); });
}

int nearest(const TriMesh& m, const Vec3& p) {
  int best = 0;
  for (int v = 1; v < m.num_vertices(); ++v)
    if ((m.vertex(v) - p).norm() < (m.vertex(best) - p).norm()) best = v;
  return best;
}

// Scordelis–Lo, whole roof, N × N per quarter.
double scordelis_lo(int N, double* seconds) {
  const double R = 25, Lr = 50, phi = 40 * kPi / 180;
  ShellModel model;
  model.mesh = grid(2 * N, 2 * N, [&](double s, double t) {
    const double th = -phi + 2 * phi * s;
    return Vec3(R * std::sin(th), Lr * t, R * std::cos(th));
  });
  model.material.E = 4.32e8;
  model.material.nu = 0;
  model.thickness = 0.25;
  model.fixed.assign(model.mesh.num_vertices(), {false, false, false, false, false, false});
  for (int v = 0; v < model.mesh.num_vertices(); ++v) {
    const double y = model.mesh.V(v, 1);
    if (std::abs(y) < 1e-9 || std::abs(y - Lr) < 1e-9)
      model.fixed[v][kUx] = model.fixed[v][kUz] = true;
  }
  model.fixed[nearest(model.mesh, Vec3(0, 0, R))][kUy] = true;
  ShellLoad q;
  q.kind = ShellLoad::Kind::kSurface;
  q.q = Vec3(0, 0, -90);
  model.loads.push_back(q);
  const auto t0 = std::chrono::steady_clock::now();
  const ShellResult r = solve_shell(model);
  *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return -r.displacement(nearest(model.mesh, Vec3(R * std::sin(phi), Lr / 2, R * std::cos(phi))),
                         kUz);
}

// Pinched hemisphere with an 18° hole, whole model, N × N per quarter.
double hemisphere(int N, double* seconds) {
  const double R = 10, hole = 18 * kPi / 180;
  TriMesh g = grid(4 * N, N, [&](double s, double t) {
    const double th = 2 * kPi * s, ph = kPi / 2 - (kPi / 2 - hole) * t;
    return Vec3(R * std::sin(ph) * std::cos(th), R * std::sin(ph) * std::sin(th), R * std::cos(ph));
  });
  // Weld the seam (column 4N onto column 0).
  const int nu = 4 * N;
  std::vector<int> map(g.num_vertices());
  for (int v = 0; v < g.num_vertices(); ++v) map[v] = v % (nu + 1) == nu ? v - nu : v;
  std::vector<int> newid(g.num_vertices(), -1);
  int cnt = 0;
  for (int v = 0; v < g.num_vertices(); ++v)
    if (map[v] == v) newid[v] = cnt++;
  ShellModel model;
  model.mesh.V.resize(cnt, 3);
  for (int v = 0; v < g.num_vertices(); ++v)
    if (map[v] == v) model.mesh.V.row(newid[v]) = g.V.row(v);
  model.mesh.F = g.F;
  for (int f = 0; f < g.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) model.mesh.F(f, k) = newid[map[g.F(f, k)]];
  model.material.E = 6.825e7;
  model.material.nu = 0.3;
  model.thickness = 0.04;
  model.fixed.assign(cnt, {false, false, false, false, false, false});
  const TriMesh& m = model.mesh;
  const int A = nearest(m, Vec3(R, 0, 0)), B = nearest(m, Vec3(-R, 0, 0));
  const int C = nearest(m, Vec3(0, R, 0)), D = nearest(m, Vec3(0, -R, 0));
  model.fixed[A][kUy] = model.fixed[A][kUz] = true;
  model.fixed[B][kUy] = model.fixed[B][kUz] = true;
  model.fixed[C][kUx] = model.fixed[C][kUz] = true;
  auto force = [&](int v, Vec3 F) {
    ShellLoad L;
    L.node = v;
    L.force = F;
    model.loads.push_back(L);
  };
  force(A, Vec3(2, 0, 0));
  force(B, Vec3(-2, 0, 0));
  force(C, Vec3(0, -2, 0));
  force(D, Vec3(0, 2, 0));
  const auto t0 = std::chrono::steady_clock::now();
  const ShellResult r = solve_shell(model);
  *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return 0.5 * (r.displacement(A, kUx) - r.displacement(B, kUx));
}

// Navier plate, N × N cells: w / w_ref.
double navier(int N) {
  const double a = 2, t = 0.02, E = 2e11, nu = 0.3, q = 1e3;
  ShellModel model;
  model.mesh = grid(N, N, [&](double s, double u) { return Vec3(a * s, a * u, 0); });
  model.material.E = E;
  model.material.nu = nu;
  model.thickness = t;
  model.fixed.assign(model.mesh.num_vertices(), {false, false, false, false, false, false});
  for (int v = 0; v < model.mesh.num_vertices(); ++v) {
    const double x = model.mesh.V(v, 0), y = model.mesh.V(v, 1);
    if (x < 1e-9 || y < 1e-9 || x > a - 1e-9 || y > a - 1e-9) model.fixed[v][kUz] = true;
  }
  model.fixed[0][kUx] = model.fixed[0][kUy] = true;
  model.fixed[N][kUy] = true;
  ShellLoad L;
  L.kind = ShellLoad::Kind::kSurface;
  L.q = Vec3(0, 0, -q);
  model.loads.push_back(L);
  const ShellResult r = solve_shell(model);
  const double D = E * t * t * t / (12 * (1 - nu * nu));
  return -r.displacement(nearest(model.mesh, Vec3(a / 2, a / 2, 0)), kUz) /
         (0.00406235 * q * std::pow(a, 4) / D);
}

void print_tables() {
  std::printf("Scordelis-Lo roof (whole roof), reference 0.3024\n");
  std::printf(
      "| N per quarter | triangles | w_B | w_B / 0.3024 | solve s |\n|---|---|---|---|---|\n");
  for (int N : {4, 8, 12, 16, 24, 32}) {
    double s = 0;
    const double w = scordelis_lo(N, &s);
    std::printf("| %d | %d | %.5f | %.4f | %.3f |\n", N, 8 * N * N, w, w / 0.3024, s);
  }
  std::printf("\nPinched hemisphere, 18 deg hole (whole model), reference 0.094\n");
  std::printf(
      "| N per quarter | triangles | u_A | u_A / 0.094 | solve s |\n|---|---|---|---|---|\n");
  for (int N : {8, 16, 24, 32, 48}) {
    double s = 0;
    const double w = hemisphere(N, &s);
    std::printf("| %d | %d | %.5f | %.4f | %.3f |\n", N, 8 * N * N, w, w / 0.094, s);
  }
  std::printf("\nNavier plate (simply supported, nu = 0.3), w / (0.00406235 q a^4 / D)\n");
  std::printf("| N | triangles | ratio |\n|---|---|---|\n");
  for (int N : {4, 8, 12, 16, 32}) std::printf("| %d | %d | %.5f |\n", N, 2 * N * N, navier(N));
  std::fflush(stdout);
}

// The shared objects that libblas.so.3 and liblapack.so.3 resolve to (Debian alternatives), e.g.
// ".../blis-serial/libblas.so.3": the factorisation time depends on them.
std::string linear_algebra_libraries() {
  std::string out;
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* data) {
        const std::string name = info->dlpi_name ? info->dlpi_name : "";
        if (name.find("libblas.so") != std::string::npos ||
            name.find("liblapack.so") != std::string::npos) {
          std::error_code ec;
          const auto real = std::filesystem::canonical(name, ec);
          auto& s = *static_cast<std::string*>(data);
          s += (s.empty() ? "" : " ") + (ec ? name : real.string());
        }
        return 0;
      },
      &out);
  return out;
}

// builtin:paraboloid:res=R, 2 R² triangles: R = 160 is the 50 K goal, R = 50 a design-size model
// (5000 triangles) where per-call BLAS overhead matters more than kernel speed.
void BM_ShellParaboloid(benchmark::State& state) {
  BuiltinOptions o;
  o.res = static_cast<int>(state.range(0));
  const Surface s = make_builtin("paraboloid", o);
  ShellOptions options;  // second argument 0: one monolithic factorisation, for comparison
  if (state.range(1) == 0) options.split_min_dofs = 1 << 30;
  ShellResult r;
  for (auto _ : state) {
    r = analyze_surface_stress(s, {}, options);
    benchmark::DoNotOptimize(r.max_displacement);
  }
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  state.counters["triangles"] = s.mesh.num_faces();
  state.counters["dofs"] = r.dofs;
  state.counters["assemble_s"] = r.timings.get("assemble");
  state.counters["order_s"] = r.timings.get("order");
  state.counters["L_nnz"] = r.factor_nnz;
  state.counters["GFlop"] = r.factor_flops * 1e-9;
  state.counters["factor_s"] = r.timings.get("factorize");
  state.counters["factor_cpu_s"] = r.cpu_factor;
  state.counters["GFlop/s_cpu"] = r.cpu_factor > 0 ? r.factor_flops * 1e-9 / r.cpu_factor : 0;
  state.counters["solve_s"] = r.timings.get("solve");
  state.counters["peak_rss_MB"] = ru.ru_maxrss / 1024.0;
  state.SetLabel("ordering=" + r.ordering + " " + linear_algebra_libraries());
}
BENCHMARK(BM_ShellParaboloid)
    ->Name("BM_Shell50K")
    ->Args({160, 1})
    ->Args({160, 0})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime();
BENCHMARK(BM_ShellParaboloid)
    ->Name("BM_Shell5K")
    ->Args({50, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3)
    ->MeasureProcessCPUTime();

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  // --tables: print the convergence tables only (docs/shell.md); otherwise run the benchmarks.
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--tables") {
      print_tables();
      return 0;
    }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
