// Metric deformation and field processing at the size of libigl's frame-field deformer
// reference (32 K faces: 2.4 s for 50 iterations on this kind of machine).
// Run: ./build/metric_bench --benchmark_counters_tabular=true

#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <cmath>

#include <algorithm>
#include <filesystem>

#include "gridshell/field/field.h"
#include "gridshell/field/field_io.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/topology.h"
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

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

/// Accuracy of M′ against the targets: median relative error of the stretch along u (d/a) and
/// across u (d), and of the aspect (across/along = a).
void stretch_counters(benchmark::State& state, const Deformed& r) {
  const Stretch s = measure_stretch(r.rest, r.deformed, r.field);
  std::vector<double> ea, ec, easp;
  for (int f = 0; f < r.rest.num_faces(); ++f) {
    const double d = r.field.d[f], a = r.field.a[f];
    ea.push_back(std::abs(s.along[f] / (d / a) - 1));
    ec.push_back(std::abs(s.across[f] / d - 1));
    easp.push_back(std::abs((s.across[f] / s.along[f]) / a - 1));
  }
  state.counters["err_along"] = median(ea);
  state.counters["err_across"] = median(ec);
  state.counters["err_aspect"] = median(easp);
  state.counters["folds"] = r.folded_edges;
}

/// The published curvedVault stress field (BLK, nearest-point import), D = A = 3, refined to
/// q = R/5 with R = 2 m on M′.
void BM_CurvedVaultBlk(benchmark::State& state) {
  const std::filesystem::path dir =
      std::filesystem::path(GRIDSHELL_SHARED_DIR) / "data" / "stress-fields";
  if (!std::filesystem::exists(dir / "curvedVault.ply")) {
    state.SkipWithError("../shared/data absent");
    return;
  }
  const TriMesh m = triangulate(io::read_mesh(dir / "curvedVault.ply").mesh);
  Deformed r;
  for (auto _ : state) {
    const StressField st = read_field_file((dir / "curvedVault_SF_pin.blk").string(), m);
    const Field fd = make_field(m, st, FieldOptions{});
    DeformOptions o;
    o.max_edge = 2.0 / 5;
    r = deform_metric(m, fd, o);
  }
  state.counters["faces_in"] = m.num_faces();
  state.counters["faces_out"] = r.rest.num_faces();
  state.counters["rounds"] = r.rounds;
  state.counters["residual"] = r.residual;
  stretch_counters(state, r);
}
BENCHMARK(BM_CurvedVaultBlk)->Unit(benchmark::kMillisecond);

/// Aquadom with a synthetic field (not a shell analysis): u along the steepest slope, density and
/// anisotropy growing with the slope; D = A = 3; R chosen for ~1200 cells on M′ (hexagon area
/// ≈ 0.866 R²), q = R / range(0): 5 is the paper's q, 1 what `design` uses (metric_edge = 1). Field + deformation + refinement time.
void BM_AquadomSynthetic(benchmark::State& state) {
  const std::filesystem::path file =
      std::filesystem::path(GRIDSHELL_SHARED_DIR) / "data" / "surfaces" / "aquadom_Vouga.ply";
  if (!std::filesystem::exists(file)) {
    state.SkipWithError("../shared/data absent");
    return;
  }
  const TriMesh m = triangulate(io::read_mesh(file).mesh);
  const FaceFrames fr = face_frames(m);
  StressField st(m.num_faces());
  for (int f = 0; f < m.num_faces(); ++f) {
    Vec3 g = -Vec3::UnitZ() + fr.n[f].z() * fr.n[f];  // downhill tangent
    const double slope = g.norm();
    if (slope < 1e-6) g = fr.t1[f];
    st[f].d2 = g.normalized();
    st[f].d1 = fr.n[f].cross(st[f].d2);
    st[f].s2 = -(1 + 3 * slope);
    st[f].s1 = -(1 + 3 * slope) / (1 + 4 * slope);
  }
  Deformed r;
  double R = 0;
  for (auto _ : state) {
    const Field fd = make_field(m, st, FieldOptions{});
    double area = 0;
    for (int f = 0; f < m.num_faces(); ++f) area += fr.area[f] * fd.d[f] * fd.d[f] / fd.a[f];
    R = std::sqrt(area / (1200 * 0.866));
    DeformOptions o;
    o.max_edge = R / static_cast<double>(state.range(0));
    r = deform_metric(m, fd, o);
  }
  state.counters["R"] = R;
  state.counters["faces_in"] = m.num_faces();
  state.counters["faces_out"] = r.rest.num_faces();
  state.counters["rounds"] = r.rounds;
  state.counters["residual"] = r.residual;
  stretch_counters(state, r);
}
BENCHMARK(BM_AquadomSynthetic)->Arg(5)->Arg(1)->Unit(benchmark::kMillisecond);

/// The connectivity of a fine input (paraboloid grid of res × res squares, two triangles each):
/// built by the metric's every refinement round, the coarsening, the projector and the symmetry
/// check. Arg: res (354: 250 K triangles, 1000: 2 M).
void BM_BuildTopology(benchmark::State& state) {
  const TriMesh m = make_builtin(fmt::format("paraboloid:res={}", state.range(0))).mesh;
  std::size_t edges = 0;
  for (auto _ : state) edges = build_topology(m).edges.size();
  state.counters["faces"] = m.num_faces();
  state.counters["edges"] = static_cast<double>(edges);
}
BENCHMARK(BM_BuildTopology)->Arg(354)->Arg(1000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
