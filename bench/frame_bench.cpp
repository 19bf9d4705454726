// Frame analysis timings on the shared surfaces, paper defaults (Ø37 steel, pinned supports,
// self-weight spread by tributary area):
//   Aquadom triangulation as a frame (11 748 beams, 2 elements per beam): linear, LBA (5 modes),
//   one Lanczos step's forward and back substitution (CHOLMOD's and ours);
//   Lilium triangulation (7 547 beams, 2 elements per beam): the non-linear λ (arc-length).
//   The Aquadom design −D 2 −A 2 --length 6000 (8 327 beams): the stability block (the perfect
//   path and four imperfection candidates).
//   One corotational element: force, analytical tangent, finite-difference tangent (µs).
// Run: ./build/frame_bench  (needs ../shared/data; prints δ and λ as counters). The Lilium case
// also prints the arc-length effort: steps, Newton iterations, tangent factorisations, seconds
// per iteration, and the process CPU time (all threads, unlike the CPU column, which counts the
// main thread only).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <ctime>
#include <filesystem>


#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/fem/frame_solver.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/design_settings.h"
#include "gridshell/surfaces/load.h"

using namespace gridshell;

namespace {
std::string shared(const std::string& rel) {
  return (std::filesystem::path(GRIDSHELL_SHARED_DIR) / "data" / rel).string();
}

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

fem::FrameModel model_of(const std::string& surface) {
  const PolySurface s = load_poly_surface(shared("surfaces/" + surface));
  return analysis::gridshell_frame(s.mesh, s.supports, {});
}

void BM_AquadomLinear(benchmark::State& state) {
  const fem::FrameModel m = model_of("aquadom_Vouga.ply");
  const fem::FrameMesh mesh = fem::discretize(m);
  const fem::FrameAssembler asmb(mesh);
  double delta = 0;
  for (auto _ : state) {
    const fem::LinearResult r = fem::linear_static(mesh, asmb);
    delta = r.displacement.rowwise().norm().maxCoeff();
  }
  state.counters["beams"] = static_cast<double>(m.members.size());
  state.counters["dofs"] = mesh.num_dofs;
  state.counters["delta_mm"] = delta * 1e3;
}
BENCHMARK(BM_AquadomLinear)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_AquadomBuckling(benchmark::State& state) {
  const fem::FrameModel m = model_of("aquadom_Vouga.ply");
  const fem::FrameMesh mesh = fem::discretize(m);
  const fem::FrameAssembler asmb(mesh);
  const fem::LinearResult lin = fem::linear_static(mesh, asmb);
  double lambda = 0;
  for (auto _ : state) {
    const fem::BucklingResult b = fem::linear_buckling(mesh, asmb, lin, {.modes = 5});
    lambda = b.lambdas.empty() ? 0 : b.lambdas.front();
  }
  state.counters["lambda_lba"] = lambda;
}
BENCHMARK(BM_AquadomBuckling)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_LiliumNonlinear(benchmark::State& state) {
  const fem::FrameModel m = model_of("liliumVouga.ply");
  analysis::FrameResult r;
  double cpu = 0;
  for (auto _ : state) {
    const double c0 = process_cpu_seconds();
    r = analysis::analyze_frame(m, {});
    cpu = process_cpu_seconds() - c0;
  }
  const double t = r.timings["nonlinear"];
  state.counters["beams"] = static_cast<double>(m.members.size());
  state.counters["dofs"] = r.num_dofs;
  state.counters["lambda_lba"] = r.lambda_linear_buckling.value_or(0);
  state.counters["lambda_nl"] = r.lambda_nonlinear.value_or(0);
  state.counters["limit_point"] = r.limit_type == gridshell::fem::LimitType::limit_point ? 1 : 0;
  state.counters["steps"] = r.nonlinear_steps;
  state.counters["iterations"] = r.nonlinear_iterations;
  state.counters["factorizations"] = r.nonlinear_factorizations;
  state.counters["t_nonlinear_s"] = t;
  state.counters["s_per_iteration"] = t / std::max(r.nonlinear_iterations, 1);
  state.counters["s_per_factorization"] = t / std::max(r.nonlinear_factorizations, 1);
  state.counters["cpu_all_threads_s"] = cpu;
}
BENCHMARK(BM_LiliumNonlinear)->Unit(benchmark::kSecond)->Iterations(1);

// The stability block of a large roof: `design aquadom_Vouga.ply -D 2 -A 2 --length 6000
// --analyze nonlinear` (8 327 beams), its frame analysed as the design does it: the perfect path
// and the imperfection candidates (both signs of the first two buckling modes), followed
// together. The design is made in the setup (not timed). Counters: λ perfect and imperfect, the
// governing mode, the seconds of the non-linear stage, and the process CPU time of all threads.
void BM_AquadomStability(benchmark::State& state) {
  const std::string surface = shared("surfaces/aquadom_Vouga.ply");
  if (!std::filesystem::exists(surface)) {
    state.SkipWithError("shared data absent");
    return;
  }
  DesignSettings settings;
  settings.options.field_options.D = 2;
  settings.options.field_options.A = 2;
  settings.options.tessellation.length = 6000;
  settings.analyze = "none";
  const DesignOptions o = build_design_options(settings);
  const DesignResult design = run_design(load_surface(surface), o);
  analysis::FrameResult r;
  double cpu = 0;
  for (auto _ : state) {
    const double c0 = process_cpu_seconds();
    r = analyze_gridshell(design.mesh, design.supports, analysis::AnalysisLevel::nonlinear,
                          o.frame, o.frame_analysis);
    cpu = process_cpu_seconds() - c0;
  }
  state.counters["beams"] = static_cast<double>(r.axial_force.size());
  state.counters["lambda_perfect"] = r.lambda_perfect.value_or(0);
  state.counters["lambda_imperfect"] = r.lambda_imperfect.value_or(0);
  state.counters["imperfection_mode"] = r.imperfection_mode + 1;
  state.counters["imperfection_sign"] = r.imperfection_sign;
  state.counters["t_nonlinear_s"] = r.timings["nonlinear"];
  state.counters["cpu_all_threads_s"] = cpu;
}
BENCHMARK(BM_AquadomStability)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

// One corotational beam element in a deformed state (Ø37 steel, 0.7 m, rotated ends): the
// internal force, the analytical tangent and the finite-difference reference (24 force
// evaluations) the analytical one replaced in production (it used 13).
std::pair<fem::CorotBeam, fem::CorotState> deformed_element() {
  fem::CorotBeam b;
  const double E = 2.1e11, A = 1.075e-3, I = 9.2e-8;
  b.s = {E * A, E * I, E * I, E / 2.6 * 2 * I};
  b.l0 = 0.7;
  const Vec3 xi(0.1, 0.2, 0.3), xj = xi + Vec3(0.3, -0.4, 0.5).normalized() * 0.7;
  b.R0 = fem::element_frame(xi, xj, Vec3::Zero());
  const fem::Mat3 Q = fem::rotation_exp(Vec3(0.2, -0.5, 0.4));
  fem::CorotState st{Q * xi, Q * xj * 1.001, fem::rotation_exp(Vec3(0.03, 0.01, -0.02)) * Q,
                     fem::rotation_exp(Vec3(-0.01, 0.04, 0.02)) * Q};
  return {b, st};
}

void BM_CorotForce(benchmark::State& state) {
  const auto [b, st] = deformed_element();
  for (auto _ : state) benchmark::DoNotOptimize(fem::corot_force(b, st));
}
BENCHMARK(BM_CorotForce);

void BM_CorotTangent(benchmark::State& state) {
  const auto [b, st] = deformed_element();
  fem::Vec12 f;
  for (auto _ : state) benchmark::DoNotOptimize(fem::corot_tangent(b, st, &f));
}
BENCHMARK(BM_CorotTangent);

void BM_CorotTangentFiniteDifference(benchmark::State& state) {
  const auto [b, st] = deformed_element();
  for (auto _ : state) benchmark::DoNotOptimize(fem::corot_tangent_finite_difference(b, st));
}
BENCHMARK(BM_CorotTangentFiniteDifference);
}  // namespace

BENCHMARK_MAIN();
