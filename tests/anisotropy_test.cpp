// Cell-level acceptance of the stress-driven anisotropic tessellation: the field is
// turned into a metric (deform_metric), the engine tessellates M′ and maps the cells back to M,
// and the cells on M are measured against what the field asks for:
//   - density ramp (D = 4): cell area ∝ 1/d², median areas of the extreme thirds in the ratio
//     predicted from the ramp;
//   - anisotropy ramp (A = 3): cell aspect (second-moment tensor) ≈ a, long axes along u;
//   - D = A = 1: the isotropic tessellation;
//   - M′ refined to q: every edge ≤ q = R/5;
//   - the default funicular at D = A = 3, whose M′ used to fold: no folded edge, no inverted
//     triangle, and `design` runs without retrying or softening the field; Aquadom likewise.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <Eigen/Eigenvalues>

#include "gridshell/fem/shell_solver.h"
#include "gridshell/field/field.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/metric/deform.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/surfaces/builtin.h"
#include "gridshell/surfaces/grid.h"
#include "gridshell/surfaces/load.h"
#include "gridshell/voronoi/tessellation.h"
#include "test_support.h"

using namespace gridshell;

namespace {

constexpr double kSide = 10;  // the flat square [0, 10]²

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

/// Area, centroid and covariance (second moments about the centroid / area) of a planar
/// polygon in the xy plane, by the exact triangle formula ∫ x xᵀ = A/12 (Σ vvᵀ + s sᵀ).
struct Moments {
  double area = 0;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
};

Moments polygon_moments(const PolyMesh& m, int f) {
  const auto& face = m.faces[f];
  const Eigen::Vector2d o = m.vertex(face[0]).head<2>();
  double area = 0;
  Eigen::Vector2d first = Eigen::Vector2d::Zero();
  Eigen::Matrix2d second = Eigen::Matrix2d::Zero();
  for (std::size_t k = 1; k + 1 < face.size(); ++k) {
    const Eigen::Vector2d b = m.vertex(face[k]).head<2>() - o;
    const Eigen::Vector2d c = m.vertex(face[k + 1]).head<2>() - o;
    const double a = 0.5 * (b.x() * c.y() - b.y() * c.x());
    const Eigen::Vector2d s = b + c;  // the third vertex is the origin o
    area += a;
    first += a * s / 3;
    second += a / 12 * (b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  Moments mo;
  mo.area = std::abs(area);
  const Eigen::Vector2d mean = first / area;
  mo.c = o + mean;
  mo.cov = second / area - mean * mean.transpose();
  return mo;
}

/// Interior cells of a tessellation (no joint on the boundary).
std::vector<int> interior_cells(const Tessellation& t) {
  std::vector<int> out;
  for (int f = 0; f < t.mesh.num_faces(); ++f) {
    bool inside = true;
    for (int v : t.mesh.faces[f]) inside = inside && !t.on_boundary[v];
    if (inside) out.push_back(f);
  }
  return out;
}

/// The pipeline of `design` on a field given per face: deform to edges ≤ R on M′ (R estimated
/// from the area of M′), tessellate M′ with `cells` cells, map back to M.
struct Pipeline {
  Deformed def;
  Tessellation tess;
};

Pipeline tessellate_field(const TriMesh& m, const Field& fd, int cells) {
  double area_def = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Vec3 a = m.vertex(m.F(f, 0)), b = m.vertex(m.F(f, 1)), c = m.vertex(m.F(f, 2));
    area_def += 0.5 * (b - a).cross(c - a).norm() * fd.d[f] * fd.d[f] / fd.a[f];
  }
  DeformOptions dopt;
  dopt.max_edge = std::sqrt(area_def / (2.598076211353316 * cells));
  Pipeline r;
  r.def = deform_metric(m, fd, dopt);
  TessellationOptions topt;
  topt.cells = cells;
  r.tess = tessellate(r.def.rest, r.def.deformed, {}, topt);
  return r;
}

/// Triangles of `m` whose normal points against the summed normals of the triangles around
/// their corners (a triangle turned over in M′).
int inverted_triangles(const TriMesh& m) {
  auto normal = [&](int f) {
    const Vec3 p0 = m.vertex(m.F(f, 0));
    return Vec3((m.vertex(m.F(f, 1)) - p0).cross(m.vertex(m.F(f, 2)) - p0));
  };
  std::vector<Vec3> vn(m.num_vertices(), Vec3::Zero());
  for (int f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) vn[m.F(f, k)] += normal(f);
  int count = 0;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Vec3 n = normal(f);
    const Vec3 around = vn[m.F(f, 0)] + vn[m.F(f, 1)] + vn[m.F(f, 2)] - 3 * n;
    if (n.dot(around) < 0) ++count;
  }
  return count;
}

}  // namespace

TEST(Anisotropy, DensityRampCellAreasFollowOneOverDSquared) {
  // d = 1 + 3x/10 (D = 4), a = 1. Cells of equal area on M′ cover area ∝ 1/d² on M, and are
  // spread uniformly in M′ area, i.e. with density ∝ d² on M. Within a third [d0, d1] of the
  // ramp the median cell therefore sits at d_m with d_m³ = (d0³ + d1³)/2, and the ratio of the
  // median areas of the sparse third (d ∈ [1, 2]) and the dense third (d ∈ [3, 4]) is
  // (d_m,dense / d_m,sparse)² = (45.5^⅓ / 4.5^⅓)² = 4.68 — the extreme cells differ by 16×.
  const TriMesh m = flat_grid(24, 24, kSide, kSide);
  const auto d_of = [](const Vec3& c) { return 1 + 3 * c.x() / kSide; };
  const Field fd = test::synthetic_field(m, d_of, [](const Vec3&) { return 1.0; });
  const Pipeline r = tessellate_field(m, fd, 300);
  EXPECT_EQ(r.def.folded_edges, 0);
  EXPECT_EQ(r.tess.quality.euler, 1);
  EXPECT_EQ(r.tess.quality.boundary_loops, 1);
  std::vector<double> sparse, dense, normalised;
  for (int f : interior_cells(r.tess)) {
    const Moments mo = polygon_moments(r.tess.mesh, f);
    const double x = mo.c.x();
    if (x < kSide / 3) sparse.push_back(mo.area);
    if (x > 2 * kSide / 3) dense.push_back(mo.area);
    const double d = d_of(Vec3(x, 0, 0));
    normalised.push_back(mo.area * d * d);
  }
  ASSERT_GE(sparse.size(), 10u);
  ASSERT_GE(dense.size(), 50u);
  const double predicted = std::pow(45.5 / 4.5, 2.0 / 3.0);
  const double ratio = median(sparse) / median(dense);
  // Area × d² is the cell area on M′: the same for all cells up to the CVT's spread.
  std::vector<double> sorted = normalised;
  std::sort(sorted.begin(), sorted.end());
  const double spread = sorted[sorted.size() * 9 / 10] / sorted[sorted.size() / 10];
  std::printf(
      "d-ramp: %d cells, %zu sparse / %zu dense interior; median area ratio %.3f "
      "(predicted %.3f); area·d² 90/10 percentile ratio %.3f\n",
      r.tess.mesh.num_faces(), sparse.size(), dense.size(), ratio, predicted, spread);
  EXPECT_NEAR(ratio / predicted, 1.0, 0.2);
  EXPECT_LT(spread, 1.6);
}

TEST(Anisotropy, AnisotropyRampCellsStretchAlongU) {
  // a = 1 + 2y/10 (A = 3), d = 1, u = x: cells of M′ come back stretched a-fold along x.
  // Aspect of a cell = √(λmax/λmin) of its second-moment tensor (1 for a regular hexagon, exactly
  // a for one stretched a-fold).
  const TriMesh m = flat_grid(24, 24, kSide, kSide);
  const auto a_of = [](const Vec3& c) { return 1 + 2 * c.y() / kSide; };
  const Field fd = test::synthetic_field(
      m, [](const Vec3&) { return 1.0; }, a_of);
  const Pipeline r = tessellate_field(m, fd, 300);
  EXPECT_EQ(r.def.folded_edges, 0);
  std::vector<double> iso, aniso, rel, angles;
  for (int f : interior_cells(r.tess)) {
    const Moments mo = polygon_moments(r.tess.mesh, f);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(mo.cov);
    const double aspect = std::sqrt(es.eigenvalues()[1] / es.eigenvalues()[0]);
    const double y = mo.c.y();
    const double a = a_of(Vec3(0, y, 0));
    rel.push_back(aspect / a);
    if (y < kSide / 6) iso.push_back(aspect);
    if (y > 5 * kSide / 6) {
      aniso.push_back(aspect);
      const Eigen::Vector2d axis = es.eigenvectors().col(1);
      angles.push_back(std::acos(std::min(1.0, std::abs(axis.x()))) * 180 / std::numbers::pi);
    }
  }
  ASSERT_GE(iso.size(), 15u);
  ASSERT_GE(aniso.size(), 8u);
  std::sort(angles.begin(), angles.end());
  const double within20 =
      static_cast<double>(std::upper_bound(angles.begin(), angles.end(), 20.0) - angles.begin()) /
      angles.size();
  std::printf(
      "a-ramp: %zu iso / %zu aniso interior cells; median aspect %.3f (a in [1, 1.33]) / %.3f "
      "(a in [2.67, 3]); median aspect/a %.3f; long axis within 20 deg of u: %.0f%%, median "
      "angle %.1f deg\n",
      iso.size(), aniso.size(), median(iso), median(aniso), median(rel), 100 * within20,
      median(angles));
  // Bands of the ramp y < 10/6 and y > 50/6: a ∈ [1, 1.33] and [2.67, 3] (interior cells start
  // about one cell away from the boundary, so the band medians are a ≈ 1.2 and 2.8).
  EXPECT_NEAR(median(iso), 1.2, 0.15);
  EXPECT_NEAR(median(aniso), 2.8, 0.3);
  EXPECT_NEAR(median(rel), 1.0, 0.15);
  EXPECT_GE(within20, 0.9);
}

TEST(Anisotropy, ConventionsDecideWhichWayCellsStretchAndWhereTheyShrink) {
  // Compression along y dominates everywhere (|s2| = 2 + 0.5x > s1 = 1 + 0.1x along x) and rises
  // with x. The paper's reading (along, rising): cells long along y, small on the right.
  // Across and falling: cells long along x, small on the left. Judged on the interior cells:
  // the share whose long axis is within 30° of the expected direction (among clearly stretched
  // ones, aspect > 1.3), and the ratio of median cell areas, left third over right third.
  const TriMesh m = flat_grid(24, 24, kSide, kSide);
  StressField st(m.num_faces());
  for (int f = 0; f < m.num_faces(); ++f) {
    const double x = test::centroid(m, f).x();
    st[f] = {1 + 0.1 * x, -(2 + 0.5 * x), Vec3::UnitX(), Vec3::UnitY()};
  }
  struct Cells {
    double along_y = 0, along_x = 0;  // shares of stretched cells
    double left_over_right = 0;       // median area ratio
  };
  auto run = [&](StretchAxis stretch, DensityTrend density) {
    FieldOptions fo;
    fo.D = 2.5;
    fo.A = 2.5;
    fo.stretch = stretch;
    fo.density = density;
    const Pipeline r = tessellate_field(m, make_field(m, st, fo), 250);
    EXPECT_EQ(r.def.folded_edges, 0);
    Cells c;
    std::vector<double> left, right;
    int stretched = 0;
    for (int f : interior_cells(r.tess)) {
      const Moments mo = polygon_moments(r.tess.mesh, f);
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(mo.cov);
      if (std::sqrt(es.eigenvalues()[1] / es.eigenvalues()[0]) > 1.3) {
        ++stretched;
        const Eigen::Vector2d axis = es.eigenvectors().col(1);
        const double cos30 = std::cos(std::numbers::pi / 6);
        c.along_x += std::abs(axis.x()) > cos30;
        c.along_y += std::abs(axis.y()) > cos30;
      }
      if (mo.c.x() < kSide / 3) left.push_back(mo.area);
      if (mo.c.x() > 2 * kSide / 3) right.push_back(mo.area);
    }
    EXPECT_GE(stretched, 20);
    c.along_x /= std::max(1, stretched);
    c.along_y /= std::max(1, stretched);
    c.left_over_right = median(left) / median(right);
    std::printf("%s/%s: %d stretched interior cells, %.0f%% long along x, %.0f%% along y; "
                "median area left/right %.2f\n",
                to_string(stretch), to_string(density), stretched, 100 * c.along_x,
                100 * c.along_y, c.left_over_right);
    return c;
  };
  const Cells paper = run(StretchAxis::along, DensityTrend::rising);
  EXPECT_GE(paper.along_y, 0.8);
  // Expected ratios: area ∝ a/d² with both d and a rising with x in the paper's reading, about
  // (2.25²/2.25)/(1.25²/1.25) = 1.8 between the thirds; (2.25²/1.25)/(1.25²/2.25) ≈ 5.8 falling.
  EXPECT_GT(paper.left_over_right, 1.5);
  const Cells other = run(StretchAxis::across, DensityTrend::falling);
  EXPECT_GE(other.along_x, 0.8);
  EXPECT_LT(other.left_over_right, 1 / 3.0);
}

TEST(Anisotropy, UnitDensityAndAnisotropyGiveTheIsotropicTessellation) {
  // D = A = 1 (u arbitrary): M′ is M up to round-off, and the cells are those of the isotropic
  // tessellation of M. Lloyd's iterations amplify round-off, so the two runs are compared by
  // their figures, not vertex by vertex.
  const TriMesh m = flat_grid(16, 12, 8, 6);
  Field fd = uniform_field(m);
  for (auto& u : fd.u) u = Vec3(1, 1, 0).normalized();
  TessellationOptions topt;
  topt.cells = 120;
  const Deformed def = deform_metric(m, fd, DeformOptions{});
  EXPECT_LT((def.deformed.V - m.V).cwiseAbs().maxCoeff(), 1e-9);
  const Tessellation a = tessellate(def.rest, def.deformed, {}, topt);
  const Tessellation b = tessellate(m, m, {}, topt);
  EXPECT_EQ(a.mesh.num_faces(), b.mesh.num_faces());
  EXPECT_NEAR(a.radius, b.radius, 1e-9 * b.radius);
  EXPECT_NEAR(a.quality.total_length / b.quality.total_length, 1.0, 0.01);
  EXPECT_NEAR(a.quality.edge_length_cv, b.quality.edge_length_cv, 0.03);
  for (const Tessellation* t : {&a, &b}) {
    std::vector<double> aspect, area;
    for (int f : interior_cells(*t)) {
      const Moments mo = polygon_moments(t->mesh, f);
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(mo.cov);
      aspect.push_back(std::sqrt(es.eigenvalues()[1] / es.eigenvalues()[0]));
      area.push_back(mo.area);
    }
    std::sort(area.begin(), area.end());
    std::printf("D = A = 1: %d cells, median aspect %.3f, area 90/10 percentile ratio %.3f\n",
                t->mesh.num_faces(), median(aspect),
                area[area.size() * 9 / 10] / area[area.size() / 10]);
    EXPECT_LT(median(aspect), 1.15);
    EXPECT_LT(area[area.size() * 9 / 10] / area[area.size() / 10], 1.3);
  }
}

TEST(Anisotropy, FinalDeformedSurfaceHasNoEdgeAboveAFifthOfR) {
  // The paper's support-mesh rule: q = R/5 on M′, with the R that the tessellation then uses.
  const TriMesh m = flat_grid(12, 12, kSide, kSide);
  const Field fd = test::synthetic_field(
      m, [](const Vec3& c) { return 1 + 2 * c.x() / kSide; },
      [](const Vec3& c) { return 1 + 2 * c.y() / kSide; });
  double area_def = 0;
  for (int f = 0; f < m.num_faces(); ++f)
    area_def += 0.5 * (kSide / 12) * (kSide / 12) * fd.d[f] * fd.d[f] / fd.a[f];
  const double R = std::sqrt(area_def / (2.598076211353316 * 60));
  DeformOptions o;
  o.max_edge = R / 5;
  const Deformed def = deform_metric(m, fd, o);
  double longest = 0;
  const Topology t = build_topology(def.deformed);
  for (const auto& [a, b] : t.edges)
    longest = std::max(longest, (def.deformed.vertex(a) - def.deformed.vertex(b)).norm());
  std::printf("q = R/5 = %.4f m: %d → %d faces, longest edge of M' %.4f m\n", R / 5, m.num_faces(),
              def.deformed.num_faces(), longest);
  EXPECT_LE(longest, R / 5);
  EXPECT_EQ(def.max_edge, longest);
  EXPECT_EQ(def.folded_edges, 0);
}

TEST(Anisotropy, DefaultFunicularDeformsWithoutFolds) {
  // The default surface of `design` (point supports at the corners) at D = A = 3: the stress
  // field's direction turns by 90° in strips around the crown (radial near the top, hoop further
  // out) where the raw anisotropy dips to ≈ 1 but the saturation raised it to ≈ 2.5; M′ then
  // folded (12 folded edges) and the engine could not extract disk cells. With the anisotropy
  // blended towards 1 where the smoothed direction is incoherent, M′ is fold-free.
  const Surface s = make_builtin("funicular");
  const fem::ShellResult shell = fem::analyze_surface_stress(s);
  FieldOptions fo;
  fo.D = 3;
  fo.A = 3;
  const Field fd = make_field(s.mesh, shell.stress, fo);
  double area_def = 0;
  const FaceFrames fr = face_frames(s.mesh);
  for (int f = 0; f < s.mesh.num_faces(); ++f) area_def += fr.area[f] * fd.d[f] * fd.d[f] / fd.a[f];
  DeformOptions o;
  o.max_edge = std::sqrt(area_def / (2.598076211353316 * 300));  // as design for 300 cells
  const Deformed def = deform_metric(s.mesh, fd, o);
  std::printf("funicular D = A = 3: %d faces, %d folded edges, %d inverted triangles\n",
              def.deformed.num_faces(), def.folded_edges, inverted_triangles(def.deformed));
  EXPECT_EQ(def.folded_edges, 0);
  EXPECT_EQ(inverted_triangles(def.deformed), 0);
  // The coherence blending does not switch the anisotropy off: most of the shell stays anisotropic.
  EXPECT_EQ(*std::max_element(fd.a.begin(), fd.a.end()), 3.0);
  EXPECT_GT(median(fd.a), 2.0);

  // And the whole pipeline runs at the requested contrast, first seed.
  DesignOptions d;
  d.analyze = analysis::AnalysisLevel::none;
  d.finish = Finish::raw;
  const DesignResult r = run_design(s, d);
  EXPECT_FALSE(r.details["field"].contains("softened_from"));
  EXPECT_FALSE(r.details.contains("tessellation_seed_retries"));
  EXPECT_EQ(r.details["metric"]["folded_edges"].get<int>(), 0);
  EXPECT_EQ(r.tessellation.quality.euler, 1);
}

TEST(Anisotropy, AquadomDeformsWithoutTurnedOverTriangles) {
  // Aquadom at D = A = 3 sized for ~1200 cells: the initial guess (targets integrated in place)
  // had 3 folded edges next to supports, which the bending regulariser (against that shape) kept;
  // M′ ended with 10 folded edges and 17 triangles turned over. The membrane-only iterations
  // before the reference is taken, and the orientation-preserving local fit, remove them.
  SKIP_WITHOUT_SHARED_DATA();
  const Surface s = load_surface(test::shared_file("surfaces/aquadom_Vouga.ply").string());
  const fem::ShellResult shell = fem::analyze_surface_stress(s);
  FieldOptions fo;
  fo.D = 3;
  fo.A = 3;
  const Field fd = make_field(s.mesh, shell.stress, fo);
  const FaceFrames fr = face_frames(s.mesh);
  double area_def = 0;
  for (int f = 0; f < s.mesh.num_faces(); ++f) area_def += fr.area[f] * fd.d[f] * fd.d[f] / fd.a[f];
  DeformOptions o;
  o.max_edge = std::sqrt(area_def / (2.598076211353316 * 1200));
  const Deformed def = deform_metric(s.mesh, fd, o);
  std::printf(
      "Aquadom D = A = 3: %d faces, %d folded edges, %d inverted triangles, residual %.4f\n",
      def.deformed.num_faces(), def.folded_edges, inverted_triangles(def.deformed), def.residual);
  EXPECT_EQ(def.folded_edges, 0);
  EXPECT_EQ(inverted_triangles(def.deformed), 0);
  EXPECT_LT(def.residual, 0.01);
}

TEST(Anisotropy, BarrelAtThreeExtractsWithoutSoftening) {
  // builtin barrel at D = A = 3 (300 cells): M′ near the supported long edges bends back within
  // a cell size, so the Euclidean (restricted) Voronoi regions of about 25 cells there fall into
  // several pieces — non-disk cells that no refinement repairs; the pipeline failed the
  // extraction for two seeds and softened the field to D = A = 2. The engine now gives each
  // detached piece to the neighbouring cell it shares most border with.
  const Surface s = make_builtin("barrel");
  DesignOptions d;
  d.field_options.D = 3;
  d.field_options.A = 3;
  d.analyze = analysis::AnalysisLevel::none;
  d.finish = Finish::raw;
  const DesignResult r = run_design(s, d);
  const Tessellation& t = r.tessellation;
  std::printf("barrel D = A = 3: %d faces, %d vertices moved from detached pieces, hex %.3f\n",
              t.mesh.num_faces(), t.orphan_vertices, t.quality.hex_share_interior);
  EXPECT_FALSE(r.details["field"].contains("softened_from"));
  EXPECT_FALSE(r.details.contains("tessellation_seed_retries"));
  EXPECT_GT(t.orphan_vertices, 0);  // the case this test is about did occur
  EXPECT_TRUE(t.quality.manifold);
  EXPECT_EQ(t.quality.euler, 1);
  EXPECT_EQ(t.quality.boundary_loops, 1);
  EXPECT_EQ(t.quality.valence3_share_interior, 1.0);
  EXPECT_EQ(t.mesh.num_faces(), 300);
  EXPECT_GE(t.quality.hex_share_interior, 0.6);
}
