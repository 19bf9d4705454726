// Regularization speed and convergence (src/gridshell/optimize).
//
//   ./build/optimize_bench --figures   convergence tables on perturbed duals (no timing loop)
//   ./build/optimize_bench             Google Benchmark: time per iteration at ~10 K polygons
//   ./build/optimize_bench --real RAW.obj SURFACE [key=value ...]
//       regularizes a raw tessellation (e.g. gridshell_raw.obj of `design`) on its surface with
//       RegularizeOptions overrides (restretch, size_anchor, size_evening, planarity_guard,
//       boundary_fairing, max_iterations; scale= scales the surface as `--scale`) and prints the
//       acceptance ratios (docs/regularization.md) against the raw mesh. Environment: GRIDSHELL_WRITE=FILE.obj
//       writes the result, GRIDSHELL_HISTORY=1 prints the energy per iteration,
//       GRIDSHELL_WALKCHECK=A compares SurfaceProjector's walk with its tree for moves of A × the
//       diagonal.
//   GRIDSHELL_GUARD=W ./build/optimize_bench --benchmark_filter=ToConvergence: the 10 K case with
//       planarity guard W (its cost shows in solve_ms_per_it).
//
// Test meshes: the polygonal dual of a built-in surface (valence 3, hex-dominant), vertices
// perturbed by ±0.25 × mean edge length (seeded) and put back on the surface.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "gridshell/core/rng.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/dual.h"
#include "gridshell/optimize/metrics.h"
#include "gridshell/optimize/projector.h"
#include "gridshell/optimize/regularize.h"
#include "gridshell/surfaces/builtin.h"
#include "gridshell/surfaces/load.h"

using namespace gridshell;

namespace {

struct Case {
  TriMesh surface;
  PolyMesh raw;
  std::vector<VertexConstraint> constraints;
};

Case perturbed_dual(const std::string& spec, double amplitude, std::uint64_t seed) {
  Case c;
  c.surface = make_builtin(spec).mesh;
  const DualMesh d = dual_polygon_mesh(c.surface);
  c.raw = d.mesh;
  c.constraints.resize(c.raw.num_vertices(), VertexConstraint::free);
  for (int v = 0; v < c.raw.num_vertices(); ++v) {
    if (d.corner[v])
      c.constraints[v] = VertexConstraint::fixed;
    else if (d.on_boundary[v])
      c.constraints[v] = VertexConstraint::boundary;
  }
  const double L = mesh_metrics(c.raw).edge_length_mean;
  const SurfaceProjector proj(c.surface);
  Rng rng(seed);
  for (int v = 0; v < c.raw.num_vertices(); ++v) {
    if (c.constraints[v] == VertexConstraint::fixed) continue;
    Vec3 p = c.raw.vertex(v);
    p += amplitude * L * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    p = c.constraints[v] == VertexConstraint::boundary ? proj.closest_boundary_point(p)
                                                       : proj.closest_point(p);
    c.raw.V.row(v) = p.transpose();
  }
  return c;
}

void print_figures() {
  const char* specs[] = {"dome:res=16", "paraboloid:res=16", "court:res=32", "barrel:res=16"};
  for (const char* spec : specs) {
    const Case c = perturbed_dual(spec, 0.25, 42);
    const MeshMetrics raw = mesh_metrics(c.raw);
    std::printf("\n%s: %d faces, %d vertices; raw regularity %.4f, edge cv %.3f, planarity %.2e\n",
                spec, c.raw.num_faces(), c.raw.num_vertices(), raw.regularity_mean,
                raw.edge_length_cv, raw.planarity_mean);
    struct Variant {
      const char* name;
      RegularizeOptions o;
    };
    std::vector<Variant> variants;
    for (double w : {0.2, 1.0})
      for (double damp : {1.0, 1.5, 1.9}) {
        RegularizeOptions o;
        o.closeness = w;
        o.damping = damp;
        variants.push_back({"global (default stop)", o});
      }
    {
      RegularizeOptions o;
      o.solver = RegularizeOptions::Solver::local;
      o.damping = 0.5;
      o.max_iterations = 100;
      o.tolerance = 0;
      o.energy_tolerance = 0;
      variants.push_back({"local damped avg, 100 it", o});
      o.max_iterations = 10;
      variants.push_back({"local damped avg, 10 it", o});
    }
    for (auto& var : variants) {
      RegularizeStats st;
      const MeshMetrics m = mesh_metrics(regularize(c.raw, c.surface, c.constraints, var.o, &st));
      std::printf(
          "  %-26s w=%.2f damping=%.1f: regularity %.2fx better, edge cv %.2fx, planarity %.2fx; "
          "%d it "
          "(best %d), %.3f s, surface dist %.1e\n",
          var.name, var.o.closeness, var.o.damping, raw.regularity_mean / m.regularity_mean,
          m.edge_length_cv / raw.edge_length_cv, m.planarity_mean / raw.planarity_mean,
          st.iterations, st.best_iteration, st.seconds, st.max_surface_distance);
    }
  }
}

/// ~11 K polygons: the dual of a dome with 60 rings (res = 120).
const Case& big_case() {
  static const Case c = perturbed_dual("dome:res=120", 0.25, 42);
  return c;
}

const SurfaceProjector& big_projector() {
  static const SurfaceProjector p(big_case().surface);
  return p;
}

/// Time per iteration: a fixed number of iterations (no early stop), setup excluded from the
/// per-iteration counter.
void BM_RegularizeIterations(benchmark::State& state) {
  const Case& c = big_case();
  const SurfaceProjector& proj = big_projector();
  RegularizeOptions o;
  o.solver =
      state.range(0) == 0 ? RegularizeOptions::Solver::global : RegularizeOptions::Solver::local;
  o.damping = state.range(0) == 0 ? 1.0 : 0.5;
  o.max_iterations = static_cast<int>(state.range(1));
  o.tolerance = 0;
  o.energy_tolerance = 0;
  double per_iteration = 0, setup = 0;
  for (auto _ : state) {
    RegularizeStats st;
    PolyMesh out = regularize(c.raw, proj, c.constraints, o, &st);
    benchmark::DoNotOptimize(out.V.data());
    per_iteration = (st.seconds - st.setup_seconds) / std::max(1, st.iterations);
    setup = st.setup_seconds;
  }
  state.counters["polygons"] = c.raw.num_faces();
  state.counters["ms_per_iteration"] = 1e3 * per_iteration;
  state.counters["setup_ms"] = 1e3 * setup;
  state.SetLabel(o.solver == RegularizeOptions::Solver::global ? "global (CHOLMOD)"
                                                               : "local damped average");
}
// {solver, iterations}: CPU time per iteration = (CPU(10) − CPU(0)) / 10.
BENCHMARK(BM_RegularizeIterations)
    ->Args({0, 0})
    ->Args({0, 10})
    ->Args({1, 0})
    ->Args({1, 10})
    ->MeasureProcessCPUTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

/// Default options to convergence (energy stall or cap 30).
void BM_RegularizeToConvergence(benchmark::State& state) {
  const Case& c = big_case();
  const SurfaceProjector& proj = big_projector();
  RegularizeStats st;
  RegularizeOptions o;
  if (const char* g = std::getenv("GRIDSHELL_GUARD")) o.planarity_guard = std::atof(g);
  for (auto _ : state) {
    PolyMesh out = regularize(c.raw, proj, c.constraints, o, &st);
    benchmark::DoNotOptimize(out.V.data());
  }
  state.counters["iterations"] = st.iterations;
  state.counters["targets_ms_per_it"] = 1e3 * st.targets_seconds / std::max(1, st.iterations);
  state.counters["solve_ms_per_it"] = 1e3 * st.solve_seconds / std::max(1, st.iterations);
  state.counters["project_ms_per_it"] = 1e3 * st.projection_seconds / std::max(1, st.iterations);
  state.counters["best_iteration"] = st.best_iteration;
}
BENCHMARK(BM_RegularizeToConvergence)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_SurfaceProjectorBuild(benchmark::State& state) {
  const Case& c = big_case();
  for (auto _ : state) {
    SurfaceProjector p(c.surface);
    benchmark::DoNotOptimize(&p);
  }
  state.counters["triangles"] = c.surface.num_faces();
}
BENCHMARK(BM_SurfaceProjectorBuild)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_MeshMetrics(benchmark::State& state) {
  const Case& c = big_case();
  for (auto _ : state) {
    MeshMetrics m = mesh_metrics(c.raw);
    benchmark::DoNotOptimize(m.regularity_mean);
  }
}
BENCHMARK(BM_MeshMetrics)->Unit(benchmark::kMillisecond)->Iterations(5);

void print_big_figures() {
  const Case& c = big_case();
  const MeshMetrics raw = mesh_metrics(c.raw);
  RegularizeStats st;
  const MeshMetrics m = mesh_metrics(regularize(c.raw, big_projector(), c.constraints, {}, &st));
  std::printf(
      "\ndome:res=120 (%d polygons): regularity %.2fx better, edge cv %.2fx, planarity "
      "%.2fx; %d iterations (best %d), %.2f s total, %.1f ms/iteration, surface dist %.1e\n",
      c.raw.num_faces(), raw.regularity_mean / m.regularity_mean,
      m.edge_length_cv / raw.edge_length_cv, m.planarity_mean / raw.planarity_mean, st.iterations,
      st.best_iteration, st.seconds,
      1e3 * (st.seconds - st.setup_seconds) / std::max(1, st.iterations), st.max_surface_distance);
}

}  // namespace

/// Spread of the cells' sizes: population std of log(face area).
double log_area_spread(const PolyMesh& m) {
  double s = 0, s2 = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const double l = std::log(std::max(polygon_area(m, f), 1e-300));
    s += l;
    s2 += l * l;
  }
  const double n = m.num_faces();
  return std::sqrt(std::max(0.0, s2 / n - (s / n) * (s / n)));
}

int real_tessellation(int argc, char** argv) {
  const PolySurface raw = load_poly_surface(argv[0]);
  RegularizeOptions o;
  SurfaceOptions so;
  for (int i = 2; i < argc; ++i) {
    const std::string kv = argv[i];
    const auto eq = kv.find('=');
    const std::string k = kv.substr(0, eq);
    const double v = std::atof(kv.substr(eq + 1).c_str());
    if (k == "restretch")
      o.restretch = v;
    else if (k == "boundary_fairing")
      o.boundary_fairing = v;
    else if (k == "max_iterations")
      o.max_iterations = static_cast<int>(v);
    else if (k == "scale")
      so.scale = v;
    else if (k == "size_anchor")
      o.size_anchor = v;
    else if (k == "energy_tolerance")
      o.energy_tolerance = v;
    else if (k == "damping")
      o.damping = v;
    else if (k == "size_evening")
      o.size_evening = v;
    else if (k == "planarity_guard")
      o.planarity_guard = v;
    else {
      std::fprintf(stderr, "unknown option %s\n", k.c_str());
      return 2;
    }
  }
  const Surface surface = load_surface(argv[1], so);
  if (std::getenv("GRIDSHELL_WALKCHECK")) {
    SurfaceProjector proj(surface.mesh);
    Rng rng(1);
    const double amp = std::atof(std::getenv("GRIDSHELL_WALKCHECK")) * proj.diagonal();
    int bad = 0;
    double worst = 0;
    for (int v = 0; v < raw.mesh.num_vertices(); ++v) {
      int tri = -1;
      const Vec3 q0 = proj.closest_point_walk(raw.mesh.vertex(v), tri);
      const Vec3 p = q0 + amp * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      const double da = (proj.closest_point(p) - p).norm();
      const double dw = (proj.closest_point_walk(p, tri) - p).norm();
      if (dw > da + 1e-12 * proj.diagonal()) {
        ++bad;
        worst = std::max(worst, (dw - da) / proj.diagonal());
      }
    }
    std::printf("walk check: %d of %d farther than the tree, worst %.2e of the diagonal\n", bad,
                raw.mesh.num_vertices(), worst);
  }
  std::vector<VertexConstraint> cons = classify_vertices(raw.mesh);
  for (int v : raw.supports)
    if (cons[v] == VertexConstraint::free) cons[v] = VertexConstraint::fixed;
  RegularizeStats st;
  const PolyMesh reg = regularize(raw.mesh, surface.mesh, cons, o, &st);
  const MeshMetrics a = mesh_metrics(raw.mesh), b = mesh_metrics(reg);
  std::printf(
      "%d faces: regularity %.4f -> %.4f (%.2fx), edge cv %.3f -> %.3f (%.3fx), planarity "
      "%.3fx, log-area spread %.3fx, length %.3fx, %d it (best %d), %.2f s, off M %.1e of the "
      "diagonal\n",
      raw.mesh.num_faces(), a.regularity_mean, b.regularity_mean,
      a.regularity_mean / b.regularity_mean, a.edge_length_cv, b.edge_length_cv,
      b.edge_length_cv / a.edge_length_cv, b.planarity_mean / a.planarity_mean,
      log_area_spread(reg) / log_area_spread(raw.mesh), b.total_length / a.total_length,
      st.iterations, st.best_iteration, st.seconds, st.max_surface_distance);
  if (const char* out = std::getenv("GRIDSHELL_WRITE")) io::write_obj(out, reg);
  if (std::getenv("GRIDSHELL_HISTORY"))
    for (std::size_t i = 0; i < st.energy_history.size(); ++i)
      std::printf("  %zu energy %.5f\n", i, st.energy_history[i]);
  return 0;
}

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--real") == 0 && i + 2 < argc)
      return real_tessellation(argc - i - 1, argv + i + 1);
    if (std::strcmp(argv[i], "--planarize") == 0 && i + 2 < argc) {
      const Case c = perturbed_dual(argv[i + 1], 0.25, 42);
      const MeshMetrics raw = mesh_metrics(c.raw);
      for (int its : {10, 30, 100, 300}) {
        RegularizeOptions o;
        o.closeness = std::atof(argv[i + 2]);
        o.max_iterations = its;
        o.tolerance = 0;
        o.energy_tolerance = 0;
        RegularizeStats st;
        const MeshMetrics m = mesh_metrics(planarize(c.raw, c.surface, c.constraints, o, &st));
        std::printf(
            "planarize w=%.2f %3d it (ran %d, best %d): planarity %.2fx raw, regularity %.2fx\n",
            o.closeness, its, st.iterations, st.best_iteration,
            m.planarity_mean / raw.planarity_mean, m.regularity_mean / raw.regularity_mean);
      }
      return 0;
    }
    if (std::strcmp(argv[i], "--stretch") == 0 && i + 2 < argc) {
      // --stretch SPEC GROWTH: regularize with a given stretch cap growth (inf = uncapped).
      const Case c = perturbed_dual(argv[i + 1], 0.25, 42);
      const MeshMetrics raw = mesh_metrics(c.raw);
      for (int its : {10, 30, 100}) {
        RegularizeOptions o;
        o.stretch_growth = std::atof(argv[i + 2]);
        o.max_iterations = its;
        o.energy_tolerance = 0;
        o.tolerance = 0;
        RegularizeStats st;
        const MeshMetrics m = mesh_metrics(regularize(c.raw, c.surface, c.constraints, o, &st));
        std::printf(
            "%s growth %s, %3d it (best %d): regularity %.2fx better, cv %.2fx, "
            "planarity %.2fx\n",
            argv[i + 1], argv[i + 2], its, st.best_iteration,
            raw.regularity_mean / m.regularity_mean, m.edge_length_cv / raw.edge_length_cv,
            m.planarity_mean / raw.planarity_mean);
      }
      return 0;
    }
    if (std::strcmp(argv[i], "--figures") == 0) {
      print_figures();
      print_big_figures();
      return 0;
    }
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
