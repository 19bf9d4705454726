// Regularization speed and convergence (src/gridshell/optimize).
//
//   ./build/optimize_bench --figures   convergence tables on perturbed duals (no timing loop)
//   ./build/optimize_bench             Google Benchmark: time per iteration at ~10 K polygons
//
// Test meshes: the polygonal dual of a built-in surface (valence 3, hex-dominant), vertices
// perturbed by ±0.25 × mean edge length (seeded) and put back on the surface.

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "gridshell/core/rng.h"
#include "gridshell/optimize/dual.h"
#include "gridshell/optimize/metrics.h"
#include "gridshell/optimize/projector.h"
#include "gridshell/optimize/regularize.h"
#include "gridshell/surfaces/builtin.h"

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
    for (double w : {0.05, 0.2, 1.0}) {
      RegularizeOptions o;
      o.closeness = w;
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
          "  %-26s w=%.2f: regularity %.2fx better, edge cv %.2fx, planarity %.2fx; %d it "
          "(best %d), %.3f s, surface dist %.1e\n",
          var.name, var.o.closeness, raw.regularity_mean / m.regularity_mean,
          m.edge_length_cv / raw.edge_length_cv, m.planarity_mean / raw.planarity_mean,
          st.iterations, st.best_iteration, st.seconds, st.max_surface_distance);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
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
    if (std::strcmp(argv[i], "--figures") == 0) {
      print_figures();
      return 0;
    }
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
