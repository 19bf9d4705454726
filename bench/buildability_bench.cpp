// Buildability figures (optimize/buildability.h) on grid-shells of about 20 000 joints: the joint
// clustering must stay about linear in the joints.
//
//   ./build/buildability_bench                 Google Benchmark: one run of `buildability` per case
//   ./build/buildability_bench --figures       the figures of each case (no timing loop)
//
// Cases (seeded, built here): the polygonal dual of a built-in dome with its joints perturbed
// (valence 3, every joint a type of its own: the most centres to compare with), a quad grid on a
// paraboloid with perturbed joints (valence 4: the hash has less to tell joints apart), and a
// regular triangle grid (valence 6, one interior type: 6! pairings per comparison unpruned).

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "gridshell/core/rng.h"
#include "gridshell/optimize/buildability.h"
#include "gridshell/optimize/dual.h"
#include "gridshell/surfaces/builtin.h"

using namespace gridshell;

namespace {

PolyMesh perturbed_dual() {
  const TriMesh surface = make_builtin("dome:res=116").mesh;
  PolyMesh m = dual_polygon_mesh(surface).mesh;
  Rng rng(5);
  for (int v = 0; v < m.num_vertices(); ++v)
    m.V.row(v) +=
        0.05 * Eigen::RowVector3d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
  return m;
}

PolyMesh quad_grid(int n, bool triangles, double jitter) {
  PolyMesh m;
  m.V.resize((n + 1) * (n + 1), 3);
  Rng rng(9);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = triangles ? i + 0.5 * j : i, y = triangles ? 0.8660254037844386 * j : j;
      const double z =
          triangles ? 0 : 0.002 * ((x - n / 2.0) * (x - n / 2.0) + (y - n / 2.0) * (y - n / 2.0));
      m.V.row(j * (n + 1) + i) << x + jitter * rng.uniform(-1, 1), y + jitter * rng.uniform(-1, 1),
          z;
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      if (triangles) {
        m.faces.push_back({a, a + 1, a + n + 1});
        m.faces.push_back({a + 1, a + n + 2, a + n + 1});
      } else {
        m.faces.push_back({a, a + 1, a + n + 2, a + n + 1});
      }
    }
  return m;
}

const PolyMesh& mesh_of(int which) {
  static const PolyMesh meshes[] = {perturbed_dual(), quad_grid(140, false, 0.1),
                                    quad_grid(140, true, 0)};
  return meshes[which];
}

const char* kNames[] = {"dual of dome:res=116, perturbed",
                        "quad grid 140x140 on a paraboloid, perturbed",
                        "triangle grid 140x140, regular"};

void BM_Buildability(benchmark::State& state) {
  const PolyMesh& m = mesh_of(static_cast<int>(state.range(0)));
  Buildability b;
  for (auto _ : state) b = buildability(m, {});
  state.SetLabel(kNames[state.range(0)]);
  state.counters["joints"] = b.joints;
  state.counters["clusters"] = b.joint_clusters;
  state.counters["capped"] = b.capped_comparisons;
}
BENCHMARK(BM_Buildability)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::strcmp(argv[1], "--figures") == 0) {
    for (int k = 0; k < 3; ++k) {
      const Buildability b = buildability(mesh_of(k), {});
      std::printf("%s: %d joints, %d clusters, planarity %.5f, length similarity %.4f, capped %d\n",
                  kNames[k], b.joints, b.joint_clusters, b.face_planarity, b.beam_length_similarity,
                  b.capped_comparisons);
    }
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  return 0;
}
