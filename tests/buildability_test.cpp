// FreeGrid's buildability figures (optimize/buildability.h) against closed forms (regular grids,
// a twisted quad, rectangles, two-beam stars), a grid with two known joint types, the
// exhaustive pairing search, invariance under rigid motions and scaling, and report.json of a
// design and a baseline through the command line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "gridshell/core/error.h"
#include "gridshell/core/rng.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/buildability.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace gridshell;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// An nx × ny grid of quads with corners at (x[i], y[j], z(i, j)); vertex (i, j) = j (nx+1) + i.
template <class Z>
PolyMesh quad_grid(const std::vector<double>& x, const std::vector<double>& y, Z z) {
  const int nx = static_cast<int>(x.size()) - 1, ny = static_cast<int>(y.size()) - 1;
  PolyMesh m;
  m.V.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.V.row(j * (nx + 1) + i) << x[i], y[j], z(i, j);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i;
      m.faces.push_back({a, a + 1, a + nx + 2, a + nx + 1});
    }
  return m;
}

std::vector<double> spaced(int n, double step) {
  std::vector<double> v(n + 1);
  for (int i = 0; i <= n; ++i) v[i] = step * i;
  return v;
}

int clusters_of_valence(const Buildability& b, int valence) {
  for (const ValenceClusters& v : b.by_valence)
    if (v.valence == valence) return v.clusters;
  return 0;
}

Vec3 random_unit(Rng& rng) {
  for (;;) {
    const Vec3 v(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (v.norm() > 0.1 && v.norm() <= 1) return v.normalized();
  }
}

}  // namespace

TEST(Buildability, PlanarRegularQuadGridIsFlatUniformWithOneJointPerValence) {
  const PolyMesh m = quad_grid(spaced(6, 1.5), spaced(6, 1.5), [](int, int) { return 0.0; });
  const Buildability b = buildability(m, {});
  EXPECT_DOUBLE_EQ(b.face_planarity, 1.0);
  EXPECT_EQ(b.joints, 49);
  EXPECT_EQ(b.beams, 84);
  EXPECT_DOUBLE_EQ(b.beam_length_similarity, 1.0);
  // Corners (valence 2), edge joints (3) and interior joints (4): one type each.
  ASSERT_EQ(b.by_valence.size(), 3u);
  EXPECT_EQ(b.by_valence[0].valence, 2);
  EXPECT_EQ(b.by_valence[0].joints, 4);
  EXPECT_EQ(b.by_valence[1].joints, 20);
  EXPECT_EQ(b.by_valence[2].joints, 25);
  EXPECT_EQ(clusters_of_valence(b, 2), 1);
  EXPECT_EQ(clusters_of_valence(b, 3), 1);
  EXPECT_EQ(clusters_of_valence(b, 4), 1);
  EXPECT_EQ(b.joint_clusters, 3);
  EXPECT_EQ(b.distinct_sections, 1);
  EXPECT_EQ(b.capped_comparisons, 0);
}

TEST(Buildability, RegularTriangleGridHasOneInteriorJointType) {
  // Equilateral triangles of side 2: rows offset by half a side.
  const int n = 8;
  PolyMesh m;
  m.V.resize((n + 1) * (n + 1), 3);
  const double h = std::sqrt(3.0);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.V.row(j * (n + 1) + i) << 2.0 * i + j, h * j, 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      m.faces.push_back({a, a + 1, a + n + 1});
      m.faces.push_back({a + 1, a + n + 2, a + n + 1});
    }
  const Buildability b = buildability(m, {});
  EXPECT_DOUBLE_EQ(b.face_planarity, 1.0);  // triangles count as flat
  EXPECT_NEAR(b.beam_length_similarity, 1.0, 1e-14);
  EXPECT_EQ(clusters_of_valence(b, 6), 1);
  // Every interior joint (valence 6) is in that one cluster.
  std::set<int> interior;
  const Topology t = build_topology(m);
  for (int v = 0; v < m.num_vertices(); ++v)
    if (t.vertex_neighbors[v].size() == 6) interior.insert(b.joint_cluster[v]);
  EXPECT_EQ(interior.size(), 1u);
}

TEST(Buildability, TwistedQuadPlanarityIsTheClosedForm) {
  // Corners alternately ±h over the unit square: the best-fit plane is z = 0, every corner at h,
  // each side √(1 + 4h²) long: Δ = h / (2 √(1 + 4h²)).
  const double h = 0.05;
  PolyMesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, h, 1, 0, -h, 1, 1, h, 0, 1, -h, 2, 0.5, 0;
  m.faces = {{0, 1, 2, 3}};
  const double delta = h / (2 * std::sqrt(1 + 4 * h * h));
  EXPECT_NEAR(buildability(m, {}).face_planarity, 1 + delta, 1e-15);
  // A triangle counts as 0 in the mean over faces.
  m.faces.push_back({1, 4, 2});
  EXPECT_NEAR(buildability(m, {}).face_planarity, 1 + delta / 2, 1e-15);
}

TEST(Buildability, BeamLengthSimilarityUsesTheSampleDeviationAndLeavesOutShortBeams) {
  // One 1 × 3 rectangle: lengths 1, 3, 1, 3, mean 2, sample deviation √(4/3).
  PolyMesh m = quad_grid({0, 1}, {0, 3}, [](int, int) { return 0.0; });
  Buildability b = buildability(m, {});
  EXPECT_NEAR(b.beam_length_similarity, 1 + std::sqrt(4.0 / 3.0) / 2, 1e-15);
  EXPECT_EQ(b.short_beams, 0);
  // A 0.05 × 1 rectangle: the two 5 cm beams are left out, the two 1 m beams are equal.
  m = quad_grid({0, 0.05}, {0, 1}, [](int, int) { return 0.0; });
  b = buildability(m, {});
  EXPECT_EQ(b.short_beams, 2);
  EXPECT_DOUBLE_EQ(b.beam_length_similarity, 1.0);
  // Rows of spacing 1 and 2 alternating (x), 1.5 (y): the figure from the lengths by hand.
  m = quad_grid({0, 1, 3, 4, 6}, {0, 1.5, 3}, [](int, int) { return 0.0; });
  std::vector<double> l;
  for (double dx : {1.0, 2.0, 1.0, 2.0})
    for (int row = 0; row < 3; ++row) l.push_back(dx);
  for (int col = 0; col < 5; ++col) l.insert(l.end(), {1.5, 1.5});
  double mean = 0, ss = 0;
  for (double x : l) mean += x / static_cast<double>(l.size());
  for (double x : l) ss += (x - mean) * (x - mean);
  EXPECT_NEAR(buildability(m, {}).beam_length_similarity,
              1 + std::sqrt(ss / static_cast<double>(l.size() - 1)) / mean, 1e-14);
}

TEST(Buildability, CorrugatedGridHasTwoInteriorJointTypes) {
  // z = 1 on every third column: interior joints next to a ridge (i mod 3 = 0 or 2, mirror
  // images of each other by a half turn about z) and on a ridge (i mod 3 = 1).
  const PolyMesh m =
      quad_grid(spaced(9, 1), spaced(5, 1), [](int i, int) { return i % 3 == 1 ? 1.0 : 0.0; });
  const Buildability b = buildability(m, {});
  EXPECT_EQ(clusters_of_valence(b, 4), 2);
  std::set<int> beside, ridge;
  for (int j = 1; j < 5; ++j)
    for (int i = 1; i < 9; ++i) (i % 3 == 1 ? ridge : beside).insert(b.joint_cluster[j * 10 + i]);
  EXPECT_EQ(beside.size(), 1u);
  EXPECT_EQ(ridge.size(), 1u);
  EXPECT_NE(*beside.begin(), *ridge.begin());
  EXPECT_NEAR(b.face_planarity, 1.0, 1e-12);  // a folded plate: every panel flat
}

TEST(Buildability, TwoBeamDistanceIsTheClosedForm) {
  // Stars of two beams at angles θ1 and θ2: best aligned along their bisectors, each beam off
  // by |θ1 − θ2|/2, a chord of 2 sin(|θ1 − θ2|/4).
  for (const auto& [t1, t2] : {std::pair{1.0, 1.2}, std::pair{2.0, 1.1}, std::pair{0.3, 3.0}}) {
    const std::vector<Vec3> a{Vec3::UnitX(), Vec3(std::cos(t1), std::sin(t1), 0)};
    const std::vector<Vec3> b{Vec3(0, 0, 1), Vec3(std::sin(t2), 0, std::cos(t2))};
    EXPECT_NEAR(joint_distance(a, b), 2 * std::sin(std::abs(t1 - t2) / 4), 1e-12);
  }
  EXPECT_EQ(joint_distance({Vec3::UnitX()}, {Vec3::UnitX(), Vec3::UnitY()}),
            std::numeric_limits<double>::infinity());
}

TEST(Buildability, MirrorImagesAreDifferentJointsRotatedCopiesTheSame) {
  // Three beams at distinct angles: its mirror image has the same angles but no rotation maps
  // one on the other (FreeGrid aligns by proper rotations).
  const std::vector<Vec3> a{Vec3::UnitX(), Vec3(0.2, 1, 0).normalized(),
                            Vec3(0.3, 0.5, 0.8).normalized()};
  std::vector<Vec3> mirror, turned;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (const Vec3& u : a) mirror.push_back(Vec3(u.x(), u.y(), -u.z()));
  for (int i : {2, 0, 1}) turned.push_back(R * a[i]);
  EXPECT_GT(joint_distance(a, mirror), 0.05);
  EXPECT_LT(joint_distance(a, turned), 1e-7);
  EXPECT_EQ(cluster_joints({a, mirror}).clusters, 2);
  EXPECT_EQ(cluster_joints({a, turned, a}).clusters, 1);
}

TEST(Buildability, PrunedSearchAgreesWithTheExhaustiveDistance) {
  // Pairs of stars near the tolerance: the clustering puts them together exactly when the
  // exhaustive distance is within δ.
  Rng rng(7);
  const double delta = BuildabilityOptions{}.joint_tolerance;
  int together = 0, apart = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int k = 2 + trial % 5;
    std::vector<Vec3> a, b;
    for (int i = 0; i < k; ++i) a.push_back(random_unit(rng));
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(rng.uniform(0, 2 * kPi), random_unit(rng)).toRotationMatrix();
    const double noise = rng.uniform(0, 2.5 * delta);
    for (int i = 0; i < k; ++i)
      b.push_back((R * a[(i + trial) % k] + noise * random_unit(rng)).normalized());
    const double d = joint_distance(a, b);
    if (std::abs(d - delta) < 1e-9) continue;  // too close to call
    const bool near = d <= delta;
    (near ? together : apart)++;
    EXPECT_EQ(cluster_joints({a, b}).clusters, near ? 1 : 2) << "valence " << k << ", d " << d;
  }
  EXPECT_GT(together, 50);
  EXPECT_GT(apart, 50);
}

TEST(Buildability, FiguresDoNotChangeUnderRotationTranslationAndScale) {
  Rng rng(3);
  PolyMesh m = quad_grid(spaced(12, 1.0), spaced(10, 1.0), [](int i, int j) {
    return 0.05 * (i - 6) * (i - 6) - 0.04 * (j - 5) * (j - 5);
  });
  for (int v = 0; v < m.num_vertices(); ++v)
    m.V.row(v) += Eigen::RowVector3d(rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1), 0);
  const Buildability b = buildability(m, {});
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(1.1, Vec3(0.3, -1, 2).normalized()).toRotationMatrix();
  PolyMesh moved = m;
  for (int v = 0; v < m.num_vertices(); ++v)
    moved.V.row(v) = (2.5 * (R * m.vertex(v)) + Vec3(40, -7, 3)).transpose();
  const Buildability c = buildability(moved, {});
  EXPECT_GT(b.joint_clusters, 100);  // jittered: nearly every joint its own type
  EXPECT_EQ(c.joint_clusters, b.joint_clusters);
  EXPECT_EQ(c.joint_cluster, b.joint_cluster);
  EXPECT_NEAR(c.face_planarity, b.face_planarity, 1e-12);
  EXPECT_NEAR(c.beam_length_similarity, b.beam_length_similarity, 1e-12);
  EXPECT_GT(b.face_planarity, 1.0);
  EXPECT_GT(b.beam_length_similarity, 1.0);
}

TEST(Buildability, DistinctSectionsCountsTheNamesGiven) {
  const PolyMesh m = quad_grid({0, 1, 2}, {0, 1}, [](int, int) { return 0.0; });  // 7 beams
  EXPECT_EQ(buildability(m, {}).distinct_sections, 1);
  EXPECT_EQ(buildability(m, std::vector<std::string>(7, "CHS 88.9x4")).distinct_sections, 1);
  EXPECT_EQ(buildability(m, {"CHS 88.9x4", "CHS 114.3x5", "CHS 88.9x4", "CHS 60.3x3", "CHS 88.9x4",
                             "CHS 114.3x5", "CHS 88.9x4"})
                .distinct_sections,
            3);
  EXPECT_THROW(buildability(m, {"CHS 88.9x4"}), Error);
}

TEST(Buildability, RefusesBadOptionsAndIndices) {
  PolyMesh m = quad_grid({0, 1}, {0, 1}, [](int, int) { return 0.0; });
  BuildabilityOptions o;
  o.joint_tolerance = 0;
  EXPECT_THROW(buildability(m, {}, o), Error);
  o = {};
  o.min_beam_length = -1;
  EXPECT_THROW(buildability(m, {}, o), Error);
  m.faces.push_back({0, 1, 7});
  EXPECT_THROW(buildability(m, {}), Error);
}

TEST(BuildabilityCli, DesignAndBaselineReportTheBlock) {
  const fs::path d = test::temp_dir("buildability_cli_design");
  const auto r = test::run_gridshell(
      "design builtin:dome --cells 120 --seed 1 --analyze none --figures none --quiet -o " +
      d.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json report = test::read_json(d / "report.json");
  const nlohmann::json& b = report.at("buildability");
  const nlohmann::json& mesh = report.at("mesh");
  // Face planarity is 1 + the mesh's mean panel planarity (the same Δ(f), no triangles here).
  EXPECT_NEAR(b.at("face_planarity").get<double>(), 1 + mesh.at("planarity_mean").get<double>(),
              1e-12);
  EXPECT_EQ(b.at("joints").get<int>(), mesh.at("vertices").get<int>());
  // 1 + sample deviation / mean = 1 + population cv · √(n / (n − 1)) (no beam under 0.1 m).
  const double n = mesh.at("edges").get<double>();
  EXPECT_EQ(b.at("short_beams").get<int>(), 0);
  EXPECT_NEAR(b.at("beam_length_similarity").get<double>(),
              1 + mesh.at("edge_length_cv").get<double>() * std::sqrt(n / (n - 1)), 1e-12);
  int sum = 0;
  for (const auto& [valence, count] : b.at("joint_clusters_by_valence").items())
    sum += count.get<int>();
  EXPECT_EQ(b.at("joint_clusters").get<int>(), sum);
  // The dome's design is 6-fold symmetric: congruent joints come in groups.
  EXPECT_GE(b.at("joint_clusters").get<int>(), 2);
  EXPECT_LT(b.at("joint_clusters").get<int>(), b.at("joints").get<int>());
  EXPECT_EQ(b.at("distinct_sections").get<int>(), 1);
  EXPECT_DOUBLE_EQ(b.at("joint_tolerance").get<double>(), 0.01);
  EXPECT_EQ(b.at("capped_comparisons").get<int>(), 0);
  // CONTRACT.md's names of the same figures.
  EXPECT_EQ(b.at("planarity"), b.at("face_planarity"));
  EXPECT_EQ(b.at("beam_similarity"), b.at("beam_length_similarity"));
  EXPECT_EQ(b.at("sections_distinct"), b.at("distinct_sections"));

  const fs::path q = test::temp_dir("buildability_cli_quad");
  const auto s = test::run_gridshell(
      "baseline builtin:dome --kind quad --length 440 --analyze none --figures none --quiet -o " +
      q.string());
  ASSERT_EQ(s.status, 0) << s.err;
  const nlohmann::json qb = test::read_json(q / "report.json").at("buildability");
  EXPECT_GT(qb.at("face_planarity").get<double>(), 1.0);
  EXPECT_GT(qb.at("joint_clusters").get<int>(), 1);
  EXPECT_EQ(qb.at("distinct_sections").get<int>(), 1);
}
