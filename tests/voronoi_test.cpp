// The tessellation engine: support-mesh refinement, and the acceptance invariants of the
// tessellation on the built-in surfaces (and the shared ones when present).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <numbers>

#include <tbb/global_control.h>

#include "gridshell/core/error.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/surfaces/builtin.h"
#include "gridshell/surfaces/load.h"
#include "gridshell/voronoi/engine.h"
#include "gridshell/voronoi/support_mesh.h"
#include "gridshell/voronoi/tessellation.h"
#include "test_support.h"

using namespace gridshell;

namespace {

/// Distance from p to the triangle mesh (brute force, independent of the engine).
double distance_to_mesh(const TriMesh& m, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (int t = 0; t < m.num_faces(); ++t) {
    const Vec3 a = m.vertex(m.F(t, 0)), b = m.vertex(m.F(t, 1)), c = m.vertex(m.F(t, 2));
    // Project onto the plane, test inside, else distance to the three segments.
    const Vec3 n = (b - a).cross(c - a);
    const double nn = n.squaredNorm();
    if (nn > 0) {
      const Vec3 q = p - n * (n.dot(p - a) / nn);
      const double u = n.dot((b - a).cross(q - a)), v = n.dot((c - b).cross(q - b)),
                   w = n.dot((a - c).cross(q - c));
      if (u >= 0 && v >= 0 && w >= 0) best = std::min(best, (p - q).norm());
    }
    for (auto [x, y] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
      const double s =
          std::clamp((p - x).dot(y - x) / std::max((y - x).squaredNorm(), 1e-300), 0.0, 1.0);
      best = std::min(best, (p - (x + s * (y - x))).norm());
    }
  }
  return best;
}

/// Sharp boundary corners of a mesh (turning angle > 30°), computed from build_topology.
std::vector<int> sharp_corners(const TriMesh& m) {
  const Topology t = build_topology(m);
  std::vector<int> out;
  for (const auto& loop : t.boundary_loops) {
    const int n = static_cast<int>(loop.size());
    for (int k = 0; k < n; ++k) {
      const Vec3 d1 = (m.vertex(loop[k]) - m.vertex(loop[(k + n - 1) % n])).normalized();
      const Vec3 d2 = (m.vertex(loop[(k + 1) % n]) - m.vertex(loop[k])).normalized();
      if (d1.dot(d2) < std::cos(30.0 * std::numbers::pi / 180)) out.push_back(loop[k]);
    }
  }
  return out;
}

void expect_invariants(const Surface& s, const Tessellation& T, const std::string& name) {
  SCOPED_TRACE(name);
  const TessellationQuality q = measure_quality(T.mesh);
  const Topology in = build_topology(s.mesh);
  EXPECT_TRUE(q.manifold) << check_mesh(T.mesh).describe().front();
  EXPECT_EQ(q.euler, s.mesh.num_vertices() - in.num_edges() + s.mesh.num_faces());
  EXPECT_EQ(q.boundary_loops, static_cast<int>(in.boundary_loops.size()));
  EXPECT_GE(q.valence3_share_interior, 0.98);
  EXPECT_GE(q.hex_share_interior, 0.75);
  EXPECT_LE(q.edge_length_cv, 0.30);
  const double diag = bbox_diagonal(s.mesh.V);
  // No degenerate face: every face has a real area and no edge collapses.
  for (int f = 0; f < T.mesh.num_faces(); ++f)
    EXPECT_GT(polygon_area(T.mesh, f), 1e-4 * T.radius * T.radius) << "face " << f;
  EXPECT_GT(q.edge_length_min, 1e-6 * diag);
  // Every vertex on the input surface, and its (triangle, barycentrics) give it back.
  double worst = 0, worst_map = 0;
  for (int v = 0; v < T.mesh.num_vertices(); ++v) {
    worst = std::max(worst, distance_to_mesh(s.mesh, T.mesh.vertex(v)));
    const int t = T.vertex_triangle[v];
    const Vec3 b = T.vertex_bary[v];
    const Vec3 p = b(0) * s.mesh.vertex(s.mesh.F(t, 0)) + b(1) * s.mesh.vertex(s.mesh.F(t, 1)) +
                   b(2) * s.mesh.vertex(s.mesh.F(t, 2));
    worst_map = std::max(worst_map, (p - T.mesh.vertex(v)).norm());
  }
  EXPECT_LE(worst, 1e-6 * diag);
  EXPECT_LE(worst_map, 1e-6 * diag);
  // Every sharp boundary corner of the input is an output vertex.
  for (int c : sharp_corners(s.mesh)) {
    double d = std::numeric_limits<double>::infinity();
    for (int v = 0; v < T.mesh.num_vertices(); ++v)
      d = std::min(d, (T.mesh.vertex(v) - s.mesh.vertex(c)).norm());
    EXPECT_LE(d, 1e-9 * diag) << "corner " << c;
  }
  // Supports exist when the input has some, and are sorted boundary/corner vertices or nearest.
  if (!s.supports.empty()) {
    EXPECT_FALSE(T.supports.empty());
  }
  EXPECT_TRUE(std::is_sorted(T.supports.begin(), T.supports.end()));
  EXPECT_EQ(T.seeds.size(), static_cast<std::size_t>(T.mesh.num_faces()));
}

Tessellation run(const Surface& s, int cells, std::uint64_t seed = 1) {
  TessellationOptions o;
  o.cells = cells;
  o.seed = seed;
  return tessellate(s.mesh, s.mesh, s.supports, o);
}

}  // namespace

TEST(SupportMesh, RefinementKeepsSurfaceAndMapsBack) {
  const Surface s = make_builtin("dome:res=8");
  SupportMesh m = make_support_mesh(s.mesh, s.mesh);
  const double h = 0.7;
  refine_to_length(m, h);
  double longest = 0;
  for (int t = 0; t < m.deformed.num_faces(); ++t)
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (m.deformed.vertex(m.deformed.F(t, k)) -
                                   m.deformed.vertex(m.deformed.F(t, (k + 1) % 3)))
                                      .norm());
  EXPECT_LE(longest, h);
  EXPECT_GT(m.deformed.num_faces(), 4 * s.mesh.num_faces());
  // Same area, conforming (a manifold with the same Euler characteristic and boundary count).
  EXPECT_NEAR(surface_area(m.rest), surface_area(s.mesh), 1e-9 * surface_area(s.mesh));
  const Topology a = build_topology(s.mesh), b = build_topology(m.rest);
  EXPECT_EQ(m.rest.num_vertices() - b.num_edges() + m.rest.num_faces(),
            s.mesh.num_vertices() - a.num_edges() + s.mesh.num_faces());
  EXPECT_EQ(a.boundary_loops.size(), b.boundary_loops.size());
  EXPECT_TRUE(check_mesh(to_poly(m.rest)).ok());
  // Every refined corner maps back to the same point through the parent triangle.
  double worst = 0;
  for (int t = 0; t < m.rest.num_faces(); ++t)
    for (int k = 0; k < 3; ++k) {
      Vec3 bary = Vec3::Zero();
      bary(k) = 1;
      const auto [ot, ob] = to_original(m, t, bary);
      const Vec3 p = ob(0) * s.mesh.vertex(s.mesh.F(ot, 0)) +
                     ob(1) * s.mesh.vertex(s.mesh.F(ot, 1)) +
                     ob(2) * s.mesh.vertex(s.mesh.F(ot, 2));
      worst = std::max(worst, (p - m.rest.vertex(m.rest.F(t, k))).norm());
    }
  EXPECT_LT(worst, 1e-12);
}

TEST(SupportMesh, RejectsMismatchedMeshes) {
  const Surface s = make_builtin("dome:res=8");
  TriMesh d = s.mesh;
  d.F.row(0) = d.F.row(1);
  EXPECT_THROW(make_support_mesh(s.mesh, d), Error);
}

// The labels against a brute-force nearest seed (squared distance, ties to the lowest index) at
// every support vertex, diagram after diagram, as the Lloyd steps move the seeds and each
// labelling starts from the last one's labels and nearest neighbours; then with one seed moved
// onto another (their bound is 0: searched). Most vertices lie within half their seed's
// nearest-neighbour distance, where compute_labels keeps the hint without a search.
TEST(RestrictedVoronoi, LabelsAreTheNearestSeeds) {
  const Surface s = make_builtin("funicular:res=16");
  voronoi::Engine E;
  const double R = 1.2;
  voronoi::set_up_support(E, s.mesh, s.mesh, std::vector<char>(s.mesh.num_vertices(), 0), R,
                          0.25 * R);
  TessellationOptions o;
  o.seed = 3;
  voronoi::place_seeds(E, surface_area(s.mesh), 80, o);
  const auto check = [&](const char* when) {
    const int nv = E.S.deformed.num_vertices(), ns = static_cast<int>(E.seeds.size());
    std::vector<double> nn2(ns, HUGE_VAL);
    for (int i = 0; i < ns; ++i)
      for (int j = 0; j < ns; ++j)
        if (j != i) nn2[i] = std::min(nn2[i], (E.seeds[j].pos - E.seeds[i].pos).squaredNorm());
    int wrong = 0, inside = 0;
    for (int v = 0; v < nv; ++v) {
      const Vec3 p = E.S.deformed.vertex(v);
      int best = 0;
      double bd = HUGE_VAL;
      for (int i = 0; i < ns; ++i) {
        const double d = (E.seeds[i].pos - p).squaredNorm();
        if (d < bd) bd = d, best = i;
      }
      wrong += E.label[v] != best;
      inside += 4 * bd < nn2[best];
    }
    EXPECT_EQ(wrong, 0) << when;
    return double(inside) / nv;
  };
  voronoi::compute_labels(E);
  const double first = check("first labelling");
  double share = first;
  for (int step = 0; step < 4; ++step) {
    voronoi::lloyd_step(E);
    voronoi::compute_labels(E, 0, static_cast<int>(E.label.size()));
    share = check("after a Lloyd step");
  }
  std::printf(
      "[figures] of %d support vertices, %.1f %% within half their seed's "
      "nearest-neighbour distance at the seeding, %.1f %% after 4 Lloyd steps\n",
      E.S.deformed.num_vertices(), 100 * first, 100 * share);
  EXPECT_GT(share, first);  // the cells grow rounder
  EXPECT_GT(share, 0.6);
  const int last = static_cast<int>(E.seeds.size()) - 1;
  E.seeds[last].pos = E.seeds[last - 1].pos;  // two seeds at one point: ties to the lower index
  voronoi::compute_labels(E, 0, static_cast<int>(E.label.size()));
  check("with two coincident seeds");
  EXPECT_EQ(std::count(E.label.begin(), E.label.end(), last), 0);
}

TEST(Tessellation, PlanarSquareIsAHexagonalCvt) {
  // A flat square: interior cells of a converged CVT are near-regular hexagons of edge ≈ R.
  const Surface s = make_builtin("paraboloid:rise=0.000001,span=10,res=10");
  const Tessellation T = run(s, 120);
  expect_invariants(s, T, "flat");
  EXPECT_EQ(T.mesh.num_faces(), 120);
  EXPECT_TRUE(T.converged);
  // Mean interior edge length within 15% of R (hexagon of circumradius R has edges R).
  EXPECT_NEAR(T.quality.edge_length_mean / T.radius, 1.0, 0.15);
}

TEST(Tessellation, QuasiNewtonNeedsFewerDiagramsThanLloyd) {
  // The same CVT problem by L-BFGS on the energy and by over-relaxed Lloyd steps, to the same
  // tolerance on the Lloyd move: both converge to a hexagonal CVT, L-BFGS with fewer diagrams.
  const Surface s = make_builtin("paraboloid:rise=2,span=10,res=10");
  TessellationOptions o;
  o.cells = 150;
  const Tessellation qn = tessellate(s.mesh, s.mesh, s.supports, o);
  o.quasi_newton = false;
  o.max_iterations = 1000;
  const Tessellation lloyd = tessellate(s.mesh, s.mesh, s.supports, o);
  expect_invariants(s, qn, "L-BFGS");
  expect_invariants(s, lloyd, "Lloyd");
  EXPECT_TRUE(qn.converged);
  EXPECT_TRUE(lloyd.converged);
  EXPECT_LT(3 * qn.iterations, 2 * lloyd.iterations);
  std::cout << "diagrams: L-BFGS " << qn.iterations << ", Lloyd " << lloyd.iterations
            << "; hexagons " << qn.quality.hex_share_interior << " / "
            << lloyd.quality.hex_share_interior << "\n";
  EXPECT_NEAR(qn.quality.edge_length_mean / qn.radius, 1.0, 0.15);
}

TEST(Tessellation, SameResultForAnyThreadCount) {
  const Surface s = make_builtin("dome");
  const Tessellation a = run(s, 200);
  Tessellation b;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    b = run(s, 200);
  }
  ASSERT_EQ(a.mesh.num_vertices(), b.mesh.num_vertices());
  EXPECT_TRUE(a.mesh.V == b.mesh.V);
  EXPECT_EQ(a.mesh.faces, b.mesh.faces);
  EXPECT_EQ(a.iterations, b.iterations);
}

class Builtins : public ::testing::TestWithParam<const char*> {};

TEST_P(Builtins, InvariantsAt300Cells) {
  const Surface s = make_builtin(GetParam());
  const Tessellation T = run(s, 300);
  expect_invariants(s, T, GetParam());
  EXPECT_NEAR(T.mesh.num_faces(), 300, 3);
}

INSTANTIATE_TEST_SUITE_P(All, Builtins,
                         ::testing::Values("dome", "paraboloid", "barrel", "court", "funicular"));

TEST(Tessellation, DeterministicForASeed) {
  const Surface s = make_builtin("court");
  const Tessellation a = run(s, 100, 7), b = run(s, 100, 7), c = run(s, 100, 8);
  ASSERT_EQ(a.mesh.num_vertices(), b.mesh.num_vertices());
  EXPECT_TRUE(a.mesh.V == b.mesh.V);
  EXPECT_EQ(a.mesh.faces, b.mesh.faces);
  EXPECT_EQ(a.supports, b.supports);
  EXPECT_FALSE(a.mesh.V.rows() == c.mesh.V.rows() && a.mesh.V == c.mesh.V);
}

TEST(Tessellation, LengthTargetWithinFivePercent) {
  const Surface s = make_builtin("funicular");
  TessellationOptions o;
  o.length = 500;
  const Tessellation T = tessellate(s.mesh, s.mesh, s.supports, o);
  EXPECT_NEAR(T.quality.total_length / 500, 1.0, 0.05);
  expect_invariants(s, T, "funicular length");
}

TEST(Tessellation, LengthModelMeetsTheTargetInOneRunUnderAnAnisotropicMetric) {
  // M′ = M stretched 2× along x: the cells are half as long along x on M as on M′. The length
  // model (mean stretch of M′ → M per triangle, boundary on M) must hit the target in the first
  // run; a first guess from the area of M′ alone is ≈ 20 % long here and needs a second run.
  const Surface s = make_builtin("funicular");
  TriMesh stretched = s.mesh;
  stretched.V.col(0) *= 2.0;
  for (double length : {300.0, 600.0}) {
    TessellationOptions o;
    o.length = length;
    const Tessellation T = tessellate(s.mesh, stretched, s.supports, o);
    EXPECT_EQ(T.length_runs, 1) << length;
    EXPECT_NEAR(T.quality.total_length / length, 1.0, 0.4 * o.length_tolerance) << length;
  }
}

TEST(Tessellation, RadiusGivesCellsOfThatSize) {
  const Surface s = make_builtin("paraboloid");
  TessellationOptions o;
  o.radius = 1.0;
  const Tessellation T = tessellate(s.mesh, s.mesh, s.supports, o);
  EXPECT_NEAR(T.quality.edge_length_mean, 1.0, 0.15);
}

TEST(Tessellation, SupportsFollowTheInput) {
  // Barrel: only the two ground edges are supported; the output supports lie on them.
  const Surface s = make_builtin("barrel");
  const Tessellation T = run(s, 150);
  double zmin = s.mesh.V.col(2).minCoeff();
  ASSERT_FALSE(T.supports.empty());
  for (int v : T.supports) EXPECT_NEAR(T.mesh.V(v, 2), zmin, 1e-9);
  // And every output vertex on a ground edge (not at its ends) is a support.
  int ground = 0;
  for (int v = 0; v < T.mesh.num_vertices(); ++v)
    if (std::abs(T.mesh.V(v, 2) - zmin) < 1e-9) ++ground;
  EXPECT_EQ(ground, static_cast<int>(T.supports.size()));
}

TEST(Tessellation, InteriorSupportBecomesNearestVertex) {
  Surface s = make_builtin("paraboloid");
  // The apex (interior) is the vertex with the largest z.
  int apex = 0;
  s.mesh.V.col(2).maxCoeff(&apex);
  s.supports = {apex};
  const Tessellation T = run(s, 100);
  ASSERT_EQ(T.supports.size(), 1u);
  double best = std::numeric_limits<double>::infinity();
  for (int v = 0; v < T.mesh.num_vertices(); ++v)
    best = std::min(best, (T.mesh.vertex(v) - s.mesh.vertex(apex)).norm());
  EXPECT_DOUBLE_EQ((T.mesh.vertex(T.supports[0]) - s.mesh.vertex(apex)).norm(), best);
}

TEST(Tessellation, BadOptionsThrow) {
  const Surface s = make_builtin("dome");
  TessellationOptions o;
  o.radius = 1;
  o.cells = 10;
  EXPECT_THROW(tessellate(s.mesh, s.mesh, s.supports, o), Error);
  o = {};
  o.radius = 1e-6;
  EXPECT_THROW(tessellate(s.mesh, s.mesh, s.supports, o), Error);
  o = {};
  o.length = -3;
  EXPECT_THROW(tessellate(s.mesh, s.mesh, s.supports, o), Error);
}

TEST(Tessellation, SharedSurfacesAt300Cells) {
  SKIP_WITHOUT_SHARED_DATA();
  for (const char* name : {"Shell.ply", "Botanic.ply", "BritishQuadTang.ply", "Neumunster.ply",
                           "aquadom_Vouga.ply", "liliumVouga.ply"}) {
    const auto path = gridshell::test::shared_file(std::string("surfaces/") + name);
    if (path.empty()) continue;
    const Surface s = load_surface(path.string());
    const Tessellation T = run(s, 300);
    expect_invariants(s, T, name);
  }
}
