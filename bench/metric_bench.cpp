// Metric deformation and field processing at the size of libigl's frame-field deformer
// reference (32 K faces: 2.4 s for 50 iterations on this kind of machine).
// Run: ./build/metric_bench --benchmark_counters_tabular=true

#include <benchmark/benchmark.h>

#include <cmath>

#include "gridshell/field/field.h"
#include "gridshell/metric/deform.h"
#include "gridshell/surfaces/builtin.h"

using namespace gridshell;

namespace {

/// 32 768-face paraboloid (span 30 m, rise 6 m) with a synthetic membrane-like stress field:
/// compression along the radial direction growing towards the supports, weaker hoop stress.
struct Case {
  TriMesh mesh;
  StressField stress;
};

const Case& the_case() {
  static const Case c = [] {
    Case k;
    k.mesh = make_builtin("paraboloid:span=30,rise=6,res=128").mesh;
    const FaceFrames fr = face_frames(k.mesh);
    k.stress.resize(k.mesh.num_faces());
    for (int f = 0; f < k.mesh.num_faces(); ++f) {
      const Vec3 p = (k.mesh.vertex(k.mesh.F(f, 0)) + k.mesh.vertex(k.mesh.F(f, 1)) +
                      k.mesh.vertex(k.mesh.F(f, 2))) /
                     3;
      Vec3 radial(p.x(), p.y(), 0);
      if (radial.norm() < 1e-9) radial = Vec3::UnitX();
      Vec3 d1 = radial - radial.dot(fr.n[f]) * fr.n[f];
      d1.normalize();
      const double r = std::hypot(p.x(), p.y()) / 15;
      k.stress[f].s1 = -(0.5 + 0.3 * r);
      k.stress[f].s2 = -(1.0 + 2.0 * r * r);
      k.stress[f].d2 = d1;
      k.stress[f].d1 = fr.n[f].cross(d1);
    }
    return k;
  }();
  return c;
}

void BM_MakeField(benchmark::State& state) {
  const Case& c = the_case();
  for (auto _ : state) benchmark::DoNotOptimize(make_field(c.mesh, c.stress, FieldOptions{}));
  state.counters["faces"] = c.mesh.num_faces();
}
BENCHMARK(BM_MakeField)->Unit(benchmark::kMillisecond);

void BM_Deform50Iterations(benchmark::State& state) {
  const Case& c = the_case();
  const Field fd = make_field(c.mesh, c.stress, FieldOptions{});
  DeformOptions o;
  o.iterations = 50;
  Deformed r;
  for (auto _ : state) r = deform_metric(c.mesh, fd, o);
  state.counters["faces"] = c.mesh.num_faces();
  state.counters["residual"] = r.residual;
}
BENCHMARK(BM_Deform50Iterations)->Unit(benchmark::kMillisecond);

/// With refinement to q = R/5 for R = 1.5 m on M′ (about the paper's cell sizes for a 30 m span).
void BM_DeformRefined(benchmark::State& state) {
  const Case& c = the_case();
  const Field fd = make_field(c.mesh, c.stress, FieldOptions{});
  DeformOptions o;
  o.max_edge = static_cast<double>(state.range(0)) / 1000.0;
  Deformed r;
  for (auto _ : state) r = deform_metric(c.mesh, fd, o);
  state.counters["faces_in"] = c.mesh.num_faces();
  state.counters["faces_out"] = r.rest.num_faces();
  state.counters["rounds"] = r.rounds;
  state.counters["residual"] = r.residual;
  state.counters["max_edge"] = r.max_edge;
}
BENCHMARK(BM_DeformRefined)->Arg(600)->Arg(300)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
