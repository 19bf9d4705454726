// The anisotropic quad baseline (grids/quad_aniso.h), its statistics, the recovery of quads
// stored as triangle pairs (grids/recover_quads.h) and the baseline kinds.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

#include "gridshell/core/error.h"
#include "gridshell/grids/baseline_kind.h"
#include "gridshell/grids/quad_aniso.h"
#include "gridshell/grids/recover_quads.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/projector.h"
#include "gridshell/pipeline/baseline_field.h"
#include "gridshell/surfaces/builtin.h"
#include "gridshell/surfaces/load.h"
#include "test_support.h"

using namespace gridshell;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// A flat rectangle [0, w] × [0, h] split into 2 n m right triangles (counter-clockwise from +z).
Surface plane(double w, double h, int n, int m) {
  Surface s;
  s.mesh.V.resize((n + 1) * (m + 1), 3);
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= n; ++i) s.mesh.V.row(j * (n + 1) + i) << w * i / n, h * j / m, 0;
  s.mesh.F.resize(2 * n * m, 3);
  int f = 0;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      s.mesh.F.row(f++) << a, b, d;
      s.mesh.F.row(f++) << a, d, c;
    }
  return s;
}

/// Mean beam length of the interior beams whose midpoint has x in [x0, x1].
double mean_beam(const PolyMesh& g, double x0, double x1) {
  const Topology t = build_topology(g);
  double sum = 0;
  int count = 0;
  for (const auto& e : t.edges) {
    if (t.on_boundary[e[0]] || t.on_boundary[e[1]]) continue;
    const Vec3 a = g.vertex(e[0]), b = g.vertex(e[1]);
    const double x = 0.5 * (a.x() + b.x());
    if (x < x0 || x > x1) continue;
    sum += (a - b).norm(), ++count;
  }
  return count ? sum / count : 0;
}

}  // namespace

/// The grid of a 40 × 20 m plane for a field at 30° with a = 2 and density `d`, h = 2 m on M′.
template <class Fd>
QuadAnisoResult plane_grid(const Surface& s, Fd d, Field& field) {
  field = test::synthetic_field(s.mesh, d, [](const Vec3&) { return 2.0; });
  for (Vec3& v : field.u) v = Vec3(std::cos(kPi / 6), std::sin(kPi / 6), 0);
  QuadAnisoOptions o;
  o.spacing = 2.0;  // on M′: 2 m across u and 4 m along u where d = 1
  return quad_aniso(s, field, o);
}

/// The quad-aniso grid of `s` at total length `length` for the design's stress field at (D, A)
/// (returned in `field`), as `gridshell baseline --kind quad-aniso` builds it.
QuadAnisoResult stress_grid(const Surface& s, double D, double A, double length, Field& field) {
  DesignOptions d;
  d.field_options.D = D;
  d.field_options.A = A;
  field = baseline_field(s, d);
  QuadAnisoOptions o;
  o.length = length;
  return quad_aniso(s, field, o);
}

/// The regularity targets (docs/quad_aniso.md): valence 4 and quads ≥ 85 %, simple faces, no stub beams.
void expect_regular_quads(const QuadMeshStats& st) {
  EXPECT_GE(st.valence4_share, 0.85);
  EXPECT_GE(st.quad_share, 0.85);
  EXPECT_EQ(st.non_simple_faces, 0);
  EXPECT_GE(st.min_edge_ratio, 0.1);
  EXPECT_GE(st.min_area_ratio, 0.02);  // no sliver panel
  EXPECT_EQ(st.overlaps, 0);           // no beams crossing, no panel over another
}

void expect_valid_quads(const QuadMeshStats& st) {
  EXPECT_GT(st.interior_joints, 60);
  expect_regular_quads(st);
  EXPECT_GE(st.aligned_share, 0.85);
}

// Constant direction at 30°, a = 2, d = 1: the quads follow u and u⊥ and are twice as long
// along u as across; the grid lies on the plane and reaches its boundary.
TEST(QuadAniso, PlaneWithConstantFieldFollowsDirectionAndAspect) {
  const Surface s = plane(40, 20, 80, 40);
  Field field;
  const QuadAnisoResult r = plane_grid(
      s, [](const Vec3&) { return 1.0; }, field);
  const PolyMesh& g = r.grid.mesh;
  EXPECT_EQ(r.folded_edges, 0);
  QuadMeshStatsOptions so;
  so.strong_a = 2, so.aspect_a = 1.5;
  const QuadMeshStats st = quad_mesh_stats(g, s.mesh, field, so);
  expect_valid_quads(st);
  EXPECT_NEAR(st.median_aspect, 2.0, 0.4);
  // Size: 4 m along u, 2 m across: mean interior beam ≈ 3 m.
  EXPECT_NEAR(mean_beam(g, 0, 40), 3.0, 0.45);
  double max_z = 0, min_x = 1e9, max_x = -1e9;
  for (int v = 0; v < g.num_vertices(); ++v) {
    max_z = std::max(max_z, std::abs(g.V(v, 2)));
    min_x = std::min(min_x, g.V(v, 0)), max_x = std::max(max_x, g.V(v, 0));
  }
  EXPECT_LT(max_z, 1e-9);
  EXPECT_LT(min_x, 1e-6);
  EXPECT_GT(max_x, 40 - 1e-6);
  // The lattice at 30° cuts the rectangle's corners; each gap is filled up to the corner, which
  // becomes a joint, and the grid covers the plane up to its boundary.
  for (const Vec3& corner : {Vec3(0, 0, 0), Vec3(40, 0, 0), Vec3(40, 20, 0), Vec3(0, 20, 0)}) {
    double nearest = 1e9;
    for (int v = 0; v < g.num_vertices(); ++v)
      nearest = std::min(nearest, (g.vertex(v) - corner).norm());
    EXPECT_LT(nearest, 1e-9) << corner.transpose();
  }
  EXPECT_GT(st.coverage, 0.99);
  EXPECT_LE(st.coverage, 1 + 1e-9);
}

// d rising from 1 to 2 along x: quads half as big where d = 2, still stretched a = 2-fold
// (a single-level position field gives 1.5 here; the multiresolution hierarchy gives 1.9).
TEST(QuadAniso, PlaneWithGradedDensityHasSizesInverseToD) {
  const Surface s = plane(40, 20, 80, 40);
  Field field;
  const QuadAnisoResult r = plane_grid(
      s, [](const Vec3& c) { return 1 + std::clamp((c.x() - 5) / 30, 0.0, 1.0); }, field);
  const PolyMesh& g = r.grid.mesh;
  QuadMeshStatsOptions so;
  so.strong_a = 2, so.aspect_a = 1.5;
  const QuadMeshStats st = quad_mesh_stats(g, s.mesh, field, so);
  expect_valid_quads(st);
  EXPECT_NEAR(st.median_aspect, 2.0, 0.3);
  const double sparse = mean_beam(g, 0, 5), dense = mean_beam(g, 35, 40);
  ASSERT_GT(dense, 0);
  EXPECT_NEAR(sparse / dense, 2.0, 0.4);
}

namespace {
/// The targets for a strongly anisotropic field (a ≥ 2.5 asked): regular, simple, no
/// stub beams, beams along the field, quads stretched.
void expect_issue_targets(const QuadMeshStats& st) {
  expect_regular_quads(st);
  EXPECT_GE(st.aligned_share, 0.7);
  EXPECT_GT(st.aspect_quads, 20);
  EXPECT_GE(st.median_aspect, 1.5);
}
}  // namespace

// The direction turns by 60° across the plane and a = 3: M′ is curved, so the lattice needs
// defects; the targets hold all the same (valence 4 and quads ≥ 85 %, ≥ 70 % of beams
// within 15° of u or u⊥, median aspect ≥ 1.5 where a ≥ 2.5).
TEST(QuadAniso, PlaneWithTurningFieldMeetsTheTargets) {
  const Surface s = plane(40, 20, 80, 40);
  Field field = test::synthetic_field(
      s.mesh, [](const Vec3&) { return 1.0; }, [](const Vec3&) { return 3.0; });
  for (int f = 0; f < s.mesh.num_faces(); ++f) {
    const double theta = kPi / 3 * test::centroid(s.mesh, f).x() / 40;
    field.u[f] = Vec3(std::cos(theta), std::sin(theta), 0);
  }
  QuadAnisoOptions o;
  o.spacing = 1.5;
  const QuadAnisoResult r = quad_aniso(s, field, o);
  const QuadMeshStats st = quad_mesh_stats(r.grid.mesh, s.mesh, field);
  EXPECT_GT(st.interior_joints, 60);
  expect_issue_targets(st);
  // And the stretch is about the a asked for.
  EXPECT_NEAR(st.median_aspect, 3.0, 0.5);
}

// Where the metric is isotropic (a = 1) the field's direction is no constraint: the left half
// has a = 3 along x, the right half a = 1 with directions that swirl at the scale of a few cells
// (as stress directions do where the two principal stresses are alike). The cross field follows
// u in proportion to a − 1, so the right half stays a plain lattice; following the swirl there
// as well (full weight and a short smoothing length) costs lattice defects.
TEST(QuadAniso, DirectionsWhereTheMetricIsIsotropicDoNotBendTheLattice) {
  const Surface s = plane(40, 20, 80, 40);
  Field field = test::synthetic_field(
      s.mesh, [](const Vec3&) { return 1.0; },
      [](const Vec3& c) { return c.x() < 20 ? 3.0 : 1.0; });
  for (int f = 0; f < s.mesh.num_faces(); ++f) {
    const Vec3 c = test::centroid(s.mesh, f);
    if (c.x() < 20) continue;
    const double theta = 0.8 * std::sin(0.8 * c.x()) * std::cos(0.6 * c.y());
    field.u[f] = Vec3(std::cos(theta), std::sin(theta), 0);
  }
  QuadAnisoOptions o;
  o.spacing = 1.5;
  const QuadMeshStats weighted = quad_mesh_stats(quad_aniso(s, field, o).grid.mesh, s.mesh, field);
  o.full_alignment_anisotropy = 1;  // coherence only, and a short smoothing length
  o.direction_smoothing = 0.07;     // (data weight ≈ 4 per neighbour)
  const QuadMeshStats followed = quad_mesh_stats(quad_aniso(s, field, o).grid.mesh, s.mesh, field);
  EXPECT_GT(weighted.interior_joints, 100);
  EXPECT_GE(weighted.valence4_share, 0.98);  // measured 0.995 and 0.994
  EXPECT_GE(weighted.quad_share, 0.98);
  // The premise: following the swirl costs defects (measured 89 % valence 4, 79 % quads).
  EXPECT_LT(followed.valence4_share + followed.quad_share, 1.8);
  expect_issue_targets(weighted);
}

// The acceptance on the surface the targets name: Botanic at (3, 3) with the design's stress
// field, at the paper's 2018 m.
TEST(QuadAniso, BotanicAt33MeetsTheTargets) {
  SKIP_WITHOUT_SHARED_DATA();
  const Surface s = load_surface(test::shared_file("surfaces/Botanic.ply").string(), {});
  Field field;
  const QuadAnisoResult r = stress_grid(s, 3, 3, 2018, field);
  EXPECT_NEAR(total_edge_length(r.grid.mesh) / 2018, 1.0, 0.05);
  const QuadMeshStats st = quad_mesh_stats(r.grid.mesh, s.mesh, field);
  EXPECT_GT(st.interior_joints, 500);
  EXPECT_GT(st.strong_beams, 100);
  expect_issue_targets(st);
  EXPECT_FALSE(r.grid.supports.empty());
}

TEST(QuadAniso, LengthIsFittedAndTheRunIsDeterministic) {
  const Surface s = make_builtin("dome:res=24");
  Field field = uniform_field(s.mesh);
  for (int f = 0; f < s.mesh.num_faces(); ++f) {  // u along x, projected on the face
    const Vec3 n = (s.mesh.vertex(s.mesh.F(f, 1)) - s.mesh.vertex(s.mesh.F(f, 0)))
                       .cross(s.mesh.vertex(s.mesh.F(f, 2)) - s.mesh.vertex(s.mesh.F(f, 0)))
                       .normalized();
    field.u[f] = (Vec3::UnitX() - n * n.x()).normalized();
  }
  QuadAnisoOptions o;
  o.length = 400;
  const QuadAnisoResult a = quad_aniso(s, field, o), b = quad_aniso(s, field, o);
  EXPECT_NEAR(total_edge_length(a.grid.mesh) / 400, 1.0, 0.05);
  EXPECT_EQ(a.grid.mesh.faces, b.grid.mesh.faces);
  EXPECT_TRUE(a.grid.mesh.V == b.grid.mesh.V);
  EXPECT_FALSE(a.grid.supports.empty());
  // D = A = 1: an isotropic field-aligned quad mesh.
  const QuadMeshStats st = quad_mesh_stats(a.grid.mesh, s.mesh, field);
  EXPECT_LE(st.median_aspect_all, 1.2);
  EXPECT_GE(st.quad_share, 0.85);
  EXPECT_GE(st.valence4_share, 0.8);
  EXPECT_EQ(st.non_simple_faces, 0);
}

/// A flat disk of radius R, a square grid of 2 n × n cells mapped onto it (area-preserving
/// enough for a test), triangles counter-clockwise from +z.
Surface disk(double R, int n) {
  Surface s = plane(2, 2, n, n);
  for (int v = 0; v < s.mesh.num_vertices(); ++v) {
    const double x = s.mesh.V(v, 0) - 1, y = s.mesh.V(v, 1) - 1;
    s.mesh.V.row(v) << R * x * std::sqrt(1 - y * y / 2), R * y * std::sqrt(1 - x * x / 2), 0;
  }
  return s;
}

// Hoop directions on a flat disk at constant size: a lattice that follows them at a constant
// spacing must start a new radial line every h / (2π) of radius. Polar lines are the frame of a
// defect-free grid only with cells ∝ r (the conformal scale: ∇s = −J ∇θ = ∇ log r); with
// `integrable_scale` κ the spacing grows as r^κ — a closed form the beams are measured against
// — and fewer rows start.
TEST(QuadAniso, HoopFieldOnADiskScalesTheSpacingAsRToTheKappa) {
  const Surface s = disk(10, 48);
  Field field = uniform_field(s.mesh);
  for (int f = 0; f < s.mesh.num_faces(); ++f) {
    const Vec3 c = test::centroid(s.mesh, f);
    field.u[f] = Vec3(-c.y(), c.x(), 0).normalized();
  }
  auto grid = [&](double kappa) {
    QuadAnisoOptions o;
    o.spacing = 0.8;
    o.integrable_scale = kappa;
    o.max_scale_change = 4;  // no clamp between r = 3 and r = 9
    return quad_aniso(s, field, o);
  };
  auto ring_beam = [](const PolyMesh& g, double r0, double r1) {
    const Topology t = build_topology(g);
    double sum = 0;
    int count = 0;
    for (const auto& e : t.edges) {
      const Vec3 a = g.vertex(e[0]), b = g.vertex(e[1]);
      const double r = (0.5 * (a + b)).norm();
      if (r >= r0 && r <= r1 && !t.on_boundary[e[0]] && !t.on_boundary[e[1]])
        sum += (a - b).norm(), ++count;
    }
    return sum / count;
  };
  const QuadAnisoResult flat = grid(0), half = grid(0.5);
  // Beams between r = 7 and 9 against those between r = 3 and 5: (8 / 4)^κ.
  EXPECT_NEAR(ring_beam(flat.grid.mesh, 7, 9) / ring_beam(flat.grid.mesh, 3, 5), 1.0, 0.1);
  EXPECT_NEAR(ring_beam(half.grid.mesh, 7, 9) / ring_beam(half.grid.mesh, 3, 5), std::sqrt(2.0),
              0.12);
  EXPECT_EQ(flat.spacing_factor_p10, 1.0);
  EXPECT_LT(half.spacing_factor_p10, 0.9);
  EXPECT_GT(half.spacing_factor_p90, 1.1);
  const QuadMeshStats a = quad_mesh_stats(flat.grid.mesh, s.mesh, field),
                      b = quad_mesh_stats(half.grid.mesh, s.mesh, field);
  RecordProperty("constant_valence4_quads",
                 std::to_string(a.valence4_share) + " " + std::to_string(a.quad_share));
  RecordProperty("scaled_valence4_quads",
                 std::to_string(b.valence4_share) + " " + std::to_string(b.quad_share));
  // Measured: 0.898 + 0.871 at a constant spacing, 0.909 + 0.905 with κ = 0.5 (the best of 8
  // starts; 0.884 + 0.929 as the best of 4).
  EXPECT_GT(b.valence4_share + b.quad_share, a.valence4_share + a.quad_share + 0.02);
}

// A grid of a dozen cells jumps by a row of cells (> 10 % of its length) between two spacings as
// close as the fit places them; then other lattice starts are tried at the spacings that came
// closest. With only two spacings per fit every target of a sweep is still met within ±5 %.
TEST(QuadAniso, LengthOfSmallGridsIsMetByOtherLatticeStarts) {
  const Surface s = make_builtin("dome:res=24");
  Field field = uniform_field(s.mesh);
  // The premise, checked: at 140 m the two spacings tried (the secant on the median length) give
  // no grid within ±5 %, so without the extra starts it throws.
  QuadAnisoOptions without;
  without.length = 140;
  without.max_fits = 2;
  without.max_starts = without.starts;
  without.extra_starts = 0;
  EXPECT_THROW(quad_aniso(s, field, without), Error);
  for (double length = 110; length <= 160; length += 5) {  // 115 and 140 need the extra starts
    QuadAnisoOptions o;
    o.length = length;
    o.max_fits = 2;
    o.max_starts = o.starts;  // 4 starts per spacing: the choice's extra starts come after the fit
    const QuadAnisoResult r = quad_aniso(s, field, o);
    EXPECT_NEAR(total_edge_length(r.grid.mesh) / length, 1.0, 0.05) << length;
  }
}

// The result is the best of its lattice starts: at a fixed spacing, the grid of N starts is the
// one of the N single-start runs (seeds seed + 7919 k) with the highest sum of the shares of
// valence-4 joints, quads and beams within 15° of u or u⊥ where a ≥ 2, measured here by
// quad_mesh_stats. A grid of ~40 cells gets max_starts starts (start_cells / cells > 8).
TEST(QuadAniso, SmallGridIsTheBestOfItsLatticeStarts) {
  const Surface s = plane(40, 20, 40, 20);
  Field field;
  const auto graded = [](const Vec3& p) { return 1 + 2 * p.x() / 40; };
  field = test::synthetic_field(s.mesh, graded, [](const Vec3& p) { return 1 + 2 * p.y() / 20; });
  for (int f = 0; f < s.mesh.num_faces(); ++f) {  // u turning by 90° across the plane
    const double t = kPi / 2 * test::centroid(s.mesh, f).x() / 40;
    field.u[f] = Vec3(std::cos(t), std::sin(t), 0);
  }
  auto quality = [&](const PolyMesh& g) {
    return quad_grid_quality(quad_mesh_stats(g, s.mesh, field));
  };
  QuadAnisoOptions o;
  o.spacing = 4;
  o.max_starts = 8;
  const QuadAnisoResult all = quad_aniso(s, field, o);
  EXPECT_EQ(all.grids, 8);
  double best = 0;
  std::vector<double> each;
  for (int k = 0; k < 8; ++k) {
    QuadAnisoOptions one = o;
    one.starts = one.max_starts = 1;
    one.seed = o.seed + 7919 * static_cast<std::uint64_t>(k);
    const QuadAnisoResult r = quad_aniso(s, field, one);
    EXPECT_EQ(r.grids, 1);
    each.push_back(quality(r.grid.mesh));
    best = std::max(best, each.back());
  }
  EXPECT_DOUBLE_EQ(quality(all.grid.mesh), best);
  // The starts differ: the best is worth choosing.
  EXPECT_GT(best, *std::min_element(each.begin(), each.end()));
  // The starts are built in parallel; on one thread the result is the same grid.
  QuadAnisoResult serial;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    serial = quad_aniso(s, field, o);
  }
  EXPECT_EQ(serial.grid.mesh.faces, all.grid.mesh.faces);
  EXPECT_TRUE(serial.grid.mesh.V == all.grid.mesh.V);
}

// The ranking of lattice starts, on figures made by hand: bars missed first, then the sum.
TEST(QuadAniso, StartsAreRankedByTheBarsTheyMissThenByTheirShares) {
  auto stats = [](double valence4, double quads, int strong, double aligned,
                  double coverage = 1.0) {
    QuadMeshStats st;
    st.valence4_share = valence4;
    st.quad_share = quads;
    st.strong_beams = strong;
    st.aligned_share = aligned;
    st.coverage = coverage;
    return st;
  };
  const double fair = quad_grid_quality(stats(0.86, 0.86, 10, 0.71));
  // Perfect in two, short of 70 % aligned: a larger sum (2.6 against 2.43), yet ranked lower.
  EXPECT_GT(fair, quad_grid_quality(stats(1.0, 1.0, 10, 0.6)));
  // Both meet every bar: the sum decides.
  EXPECT_GT(quad_grid_quality(stats(0.9, 0.9, 10, 0.8)), fair);
  // One bar missed beats two.
  EXPECT_GT(quad_grid_quality(stats(0.5, 0.9, 10, 0.9)),
            quad_grid_quality(stats(0.84, 0.84, 10, 1.0)));
  // No beam where a ≥ 2: alignment counts as met, as 1.
  EXPECT_DOUBLE_EQ(quad_grid_quality(stats(0.9, 0.95, 0, 0.0)), 0.9 + 0.95 + 1.0 + 1.0);
  EXPECT_DOUBLE_EQ(quad_grid_quality(stats(0.9, 0.95, 10, 0.8)), 0.9 + 0.95 + 0.8 + 1.0);
  // Coverage is a bar too (90 %): a hole takes its joints out of the interior shares, and a
  // start with a hole was chosen for its better shares (the cap (3, 3) at 315 m, 67 % covered).
  EXPECT_GT(quad_grid_quality(stats(0.86, 0.86, 10, 0.71, 0.95)),
            quad_grid_quality(stats(1.0, 1.0, 10, 1.0, 0.8)));
  // Faces that overlap (a walk in the wrong order) cover more than the surface: 3 % over counts
  // as 3 % short (g_hill (2, 4) at 1090 m: a start whose faces covered 105.7 % was chosen).
  EXPECT_NEAR(quad_grid_quality(stats(0.9, 0.9, 10, 0.8, 1.03)),
              quad_grid_quality(stats(0.9, 0.9, 10, 0.8, 0.97)), 1e-12);
  EXPECT_LT(quad_grid_quality(stats(0.9, 0.9, 10, 0.8, 1.03)),
            quad_grid_quality(stats(0.9, 0.9, 10, 0.8, 1.0)));
}

// A hole about one cell wide: the extraction walks the loop of beams around it on M′ like any
// other face, and that face would be a panel over the void (before the fix: 7 of these 8
// single-start grids had one). No face may have its centroid over the hole, and the hole stays a
// boundary of the grid.
TEST(QuadAniso, NoPanelOverAHoleOfOneCell) {
  const Surface full = plane(30, 20, 60, 40);
  std::vector<int> index(full.mesh.num_vertices(), -1);
  std::vector<std::array<int, 3>> kept;
  int count = 0;
  const auto in_hole = [](const Vec3& c) {
    return std::abs(c.x() - 15) < 1.5 && std::abs(c.y() - 10) < 1.5;
  };
  for (int f = 0; f < full.mesh.num_faces(); ++f) {
    Vec3 c = Vec3::Zero();
    for (int k = 0; k < 3; ++k) c += full.mesh.vertex(full.mesh.F(f, k)) / 3;
    if (in_hole(c)) continue;
    std::array<int, 3> t{};
    for (int k = 0; k < 3; ++k) {
      int& i = index[full.mesh.F(f, k)];
      if (i < 0) i = count++;
      t[k] = i;
    }
    kept.push_back(t);
  }
  Surface s;
  s.mesh.V.resize(count, 3);
  for (int v = 0; v < full.mesh.num_vertices(); ++v)
    if (index[v] >= 0) s.mesh.V.row(index[v]) = full.mesh.V.row(v);
  s.mesh.F.resize(static_cast<int>(kept.size()), 3);
  for (int f = 0; f < static_cast<int>(kept.size()); ++f)
    s.mesh.F.row(f) << kept[f][0], kept[f][1], kept[f][2];
  const Field field = uniform_field(s.mesh);
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    QuadAnisoOptions o;
    o.spacing = 3.5;  // cells of 3.5 m around a hole of 3 m
    o.seed = seed;
    o.starts = o.max_starts = 1;
    const PolyMesh g = quad_aniso(s, field, o).grid.mesh;
    int over = 0;
    for (const auto& f : g.faces) {
      Vec3 c = Vec3::Zero();
      for (int v : f) c += g.vertex(v) / static_cast<double>(f.size());
      over += in_hole(c);
    }
    EXPECT_EQ(over, 0) << seed;
    EXPECT_EQ(build_topology(g).boundary_loops.size(), 2u) << seed;
  }
}

// A fine input (a disk of 15 m radius in 28 800 triangles) is built on the design's coarsened
// analysis copy at lengths whose cells need far fewer triangles, and the joints are then moved onto
// the input: each onto the input surface, those on the copy's boundary (chords of the input's) onto
// its boundary.
TEST(QuadAniso, FineInputIsBuiltOnTheDesignsCoarseCopy) {
  const Surface s = disk(15, 120);
  DesignOptions d;
  d.field = FieldInput::uniform;
  const std::optional<Surface> coarse = baseline_surface(s, d, 300);
  ASSERT_TRUE(coarse.has_value());
  EXPECT_LT(4 * coarse->mesh.num_faces(), s.mesh.num_faces());
  EXPECT_FALSE(baseline_surface(s, d, 0).has_value());      // --spacing: no length to size by
  EXPECT_FALSE(baseline_surface(s, d, 30000).has_value());  // cells finer than the input's
  DesignOptions file = d;
  file.field = FieldInput::file;  // values per input triangle: the input it must be
  EXPECT_FALSE(baseline_surface(s, file, 300).has_value());
  QuadAnisoOptions o;
  o.length = 300;
  o.max_starts = o.starts;
  PolyMesh g = quad_aniso(*coarse, uniform_field(coarse->mesh), o).grid.mesh;
  const SurfaceProjector from(coarse->mesh), onto(s.mesh);
  const double tol = 1e-6 * onto.diagonal();
  std::vector<char> was_boundary(g.num_vertices());
  double chord_gap = 0;
  for (int v = 0; v < g.num_vertices(); ++v) {
    was_boundary[v] = from.boundary_distance(g.vertex(v)) <= tol;
    if (was_boundary[v]) chord_gap = std::max(chord_gap, onto.boundary_distance(g.vertex(v)));
  }
  EXPECT_GT(chord_gap, 10 * tol);  // the premise: the copy's boundary is not the input's
  move_onto_input(g, coarse->mesh, s.mesh);
  int moved = 0;
  for (int v = 0; v < g.num_vertices(); ++v) {
    EXPECT_LT(onto.distance(g.vertex(v)), tol);
    if (!was_boundary[v]) continue;
    EXPECT_LT(onto.boundary_distance(g.vertex(v)), tol);
    ++moved;
  }
  EXPECT_GT(moved, 10);
}

// Coverage is the grid's face area over the surface's: unit squares over the left half of a
// 4 × 2 plane cover exactly half of it, and the whole grid of them all of it.
TEST(QuadAniso, CoverageIsTheGridsShareOfTheSurfaceArea) {
  const Surface s = plane(4, 2, 4, 2);
  const Field field = uniform_field(s.mesh);
  PolyMesh g;
  g.V.resize(15, 3);
  for (int j = 0; j <= 2; ++j)
    for (int i = 0; i <= 4; ++i) g.V.row(j * 5 + i) << i, j, 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i)
      g.faces.push_back({j * 5 + i, j * 5 + i + 1, j * 5 + i + 6, j * 5 + i + 5});
  EXPECT_NEAR(quad_mesh_stats(g, s.mesh, field).coverage, 0.5, 1e-12);
  for (int j = 0; j < 2; ++j)
    for (int i = 2; i < 4; ++i)
      g.faces.push_back({j * 5 + i, j * 5 + i + 1, j * 5 + i + 6, j * 5 + i + 5});
  EXPECT_NEAR(quad_mesh_stats(g, s.mesh, field).coverage, 1.0, 1e-12);
}

// Two 20 × 10 m planes 10 m apart in one surface (two roofs in one file): each gets its grid.
// Before, only the grid's largest component was kept: one roof, half the surface covered.
TEST(QuadAniso, EachPieceOfTheSurfaceGetsItsGrid) {
  const Surface left = plane(20, 10, 40, 20);
  Surface s = left;
  const int nv = left.mesh.num_vertices(), nf = left.mesh.num_faces();
  s.mesh.V.conservativeResize(2 * nv, 3);
  s.mesh.F.conservativeResize(2 * nf, 3);
  for (int v = 0; v < nv; ++v)
    s.mesh.V.row(nv + v) = left.mesh.V.row(v) + Eigen::RowVector3d(30, 0, 0);
  for (int f = 0; f < nf; ++f) s.mesh.F.row(nf + f) = left.mesh.F.row(f).array() + nv;
  const Field field = uniform_field(s.mesh);
  QuadAnisoOptions o;
  o.spacing = 1.0;
  const PolyMesh g = quad_aniso(s, field, o).grid.mesh;
  int on_left = 0, on_right = 0;
  for (int v = 0; v < g.num_vertices(); ++v) (g.V(v, 0) < 25 ? on_left : on_right)++;
  EXPECT_NEAR(on_left, on_right, 0.1 * on_left);
  const QuadMeshStats st = quad_mesh_stats(g, s.mesh, field);
  EXPECT_GT(st.coverage, 0.95);
  expect_regular_quads(st);
}

// Cells 3× larger beyond x = 22 m than before x = 20 m (d from 1 to 1/3 within 2 m): M′, which
// makes the metric Euclidean, is crushed along the change, and beams ordered about each joint on
// M′ alone were out of order there: faces were walked across the large cells and only 77 % of
// the plane was covered. With the walk on M as well (the one covering more is kept): 96 %.
TEST(QuadAniso, LargeCellsBesideSmallOnesAreFaces) {
  const Surface s = plane(40, 20, 80, 40);
  const Field field = test::synthetic_field(
      s.mesh, [](const Vec3& c) { return 1 / (1 + std::clamp(c.x() - 20, 0.0, 2.0)); },
      [](const Vec3&) { return 2.0; });
  QuadAnisoOptions o;
  o.spacing = 1.5;
  const QuadMeshStats st = quad_mesh_stats(quad_aniso(s, field, o).grid.mesh, s.mesh, field);
  EXPECT_GT(st.coverage, 0.93);
  EXPECT_GT(st.interior_joints, 60);
  expect_regular_quads(st);
}

// The built-in court at (1, 1) and 600 m: its best lattice start has 3 overlaps (beams that
// cross, a joint inside a panel not its own) unless they are removed. Faces that overlap are
// left out, and the grid can be built.
TEST(QuadAniso, NoTwoPanelsOverlap) {
  const Surface s = make_builtin("court");
  Field field;
  const QuadAnisoResult r = stress_grid(s, 1, 1, 600, field);
  const QuadMeshStats st = quad_mesh_stats(r.grid.mesh, s.mesh, field);
  EXPECT_EQ(st.overlaps, 0);
  EXPECT_GT(st.coverage, 0.9);
  EXPECT_NEAR(total_edge_length(r.grid.mesh) / 600, 1.0, 0.05);
}

TEST(QuadAniso, RejectsBadInput) {
  const Surface s = plane(4, 2, 4, 2);
  const Field field = uniform_field(s.mesh);
  QuadAnisoOptions o;  // neither spacing nor length
  EXPECT_THROW(quad_aniso(s, field, o), Error);
  Field short_field = field;
  short_field.u.pop_back();
  o.spacing = 1;
  EXPECT_THROW(quad_aniso(s, short_field, o), Error);
  o.direction_smoothing = 0;
  EXPECT_THROW(quad_aniso(s, field, o), Error);
  o.direction_smoothing = 0.25;
  o.integrable_scale = -0.5;
  EXPECT_THROW(quad_aniso(s, field, o), Error);
  o.integrable_scale = 0.5;
  o.max_scale_change = 0.8;
  EXPECT_THROW(quad_aniso(s, field, o), Error);
  o.max_scale_change = 1.25;
  o.start_cells = -1;
  EXPECT_THROW(quad_aniso(s, field, o), Error);
  o.start_cells = 4000;
  o.gap_joints = -1;
  EXPECT_THROW(quad_aniso(s, field, o), Error);
  o.gap_joints = 0;
  o.min_face_area = 1;
  EXPECT_THROW(quad_aniso(s, field, o), Error);
  o.min_face_area = -0.1;
  EXPECT_THROW(quad_aniso(s, field, o), Error);
}

TEST(RecoverQuads, PairsTheTrianglesOfASplitQuadGrid) {
  // A 6 × 4 grid of skewed quads, each split along a diagonal chosen alternately.
  Surface s = plane(12, 8, 6, 4);
  for (int v = 0; v < s.mesh.num_vertices(); ++v) s.mesh.V(v, 0) += 0.3 * s.mesh.V(v, 1);
  for (int f = 0; f < s.mesh.num_faces(); f += 4) {  // flip the diagonal of every other quad
    const int a = s.mesh.F(f, 0), b = s.mesh.F(f, 1), d = s.mesh.F(f, 2), c = s.mesh.F(f + 1, 2);
    s.mesh.F.row(f) << a, b, c;
    s.mesh.F.row(f + 1) << b, d, c;
  }
  const RecoveredQuads r = recover_quads(s.mesh);
  EXPECT_EQ(r.mesh.num_faces(), 24);
  EXPECT_EQ(r.triangles, 0);
  // The grid's own beams only: 30 along x of 2 m, 28 skewed ones of √(0.6² + 2²) m.
  EXPECT_NEAR(total_edge_length(r.mesh), 30 * 2 + 28 * std::sqrt(0.36 + 4), 1e-9);
  // Every quad is one cell of the grid: area 12·8 / 24 = 4 m².
  for (int f = 0; f < r.mesh.num_faces(); ++f) EXPECT_NEAR(polygon_area(r.mesh, f), 4.0, 1e-9);
}

TEST(RecoverQuads, BotanicIsTangs1076Quads) {
  SKIP_WITHOUT_SHARED_DATA();
  const Surface s = load_surface(test::shared_file("surfaces/Botanic.ply").string(), {});
  ASSERT_EQ(s.mesh.num_faces(), 2152);
  const RecoveredQuads r = recover_quads(s.mesh);
  EXPECT_EQ(r.mesh.num_faces(), 1076);
  EXPECT_EQ(r.triangles, 0);
  EXPECT_EQ(r.mesh.num_vertices(), 1121);
  EXPECT_TRUE(check_mesh(r.mesh).ok());
  // Tang's panels are planar quads: a wrong pairing would show as a bent quad.
  double worst = 0;
  std::vector<double> bend;
  for (const auto& q : r.mesh.faces) {
    const Vec3 a = r.mesh.vertex(q[0]), b = r.mesh.vertex(q[1]), c = r.mesh.vertex(q[2]),
               d = r.mesh.vertex(q[3]);
    const Vec3 n = (c - a).cross(d - b).normalized();  // the diagonals' common normal
    bend.push_back(std::abs((b - a).dot(n)) / (0.5 * ((c - a).norm() + (d - b).norm())));
    worst = std::max(worst, bend.back());
  }
  std::sort(bend.begin(), bend.end());
  EXPECT_LT(bend[bend.size() / 2], 1e-3);
  EXPECT_LT(std::count_if(bend.begin(), bend.end(), [](double x) { return x > 0.01; }), 22);
  EXPECT_LT(worst, 0.05);
  EXPECT_GE(quad_mesh_stats(r.mesh, s.mesh, uniform_field(s.mesh)).valence4_share, 0.95);
}

TEST(BaselineKind, WordsRoundTrip) {
  for (BaselineKind k : {BaselineKind::quad, BaselineKind::quad_aniso, BaselineKind::tri,
                         BaselineKind::voronoi_iso, BaselineKind::original})
    EXPECT_EQ(parse_baseline_kind(to_string(k)), k);
  EXPECT_EQ(std::string(to_string(BaselineKind::quad_aniso)), "quad-aniso");
  EXPECT_THROW(parse_baseline_kind("hex"), Error);
}
