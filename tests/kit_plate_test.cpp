// gridshell kit's print plates: every joint once, a rigid motion of its own STL (read back with
// a reader of this test's own), base down on z = 0, footprints apart by the gap and inside the
// bed; the plates hold exactly the joints' triangles; bad beds are one line and exit 2.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "gridshell/kit/kit.h"
#include "gridshell/kit/plate.h"
#include "test_support.h"

namespace gridshell {
namespace {

constexpr double kBed = 90, kGap = 3, kMargin = 5;  // the test's --print-bed, PrintBed's gaps

using Corners = std::vector<Vec3>;  // three per triangle, STL order

/// A binary STL's corners (80-byte header, count, 50 bytes a triangle: normal, 3 corners).
Corners read_corners(const std::filesystem::path& path) {
  const std::string s = test::slurp(path);
  const auto u32 = [&s](std::size_t at) {
    std::uint32_t x = 0;
    for (int b = 0; b < 4; ++b)
      x |= static_cast<std::uint32_t>(static_cast<unsigned char>(s.at(at + b))) << (8 * b);
    return x;
  };
  Corners c;
  if (s.size() < 84) return c;
  const std::size_t n = u32(80);
  EXPECT_EQ(s.size(), 84 + 50 * n) << path;
  for (std::size_t k = 0; k < n && 84 + 50 * (k + 1) <= s.size(); ++k) {
    for (int v = 0; v < 3; ++v) {
      Vec3 p;
      for (int i = 0; i < 3; ++i) p(i) = std::bit_cast<float>(u32(84 + 50 * k + 12 + 12 * v + 4 * i));
      c.push_back(p);
    }
  }
  return c;
}

double signed_volume(const Corners& c) {
  double v = 0;
  for (std::size_t k = 0; k + 2 < c.size(); k += 3) v += c[k].dot(c[k + 1].cross(c[k + 2])) / 6;
  return v;
}

/// Area of the triangles lying in the plane {x : x·n = d} and facing along n.
double area_on_plane(const Corners& c, const Vec3& n, double d) {
  double area = 0;
  for (std::size_t k = 0; k + 2 < c.size(); k += 3) {
    const Vec3 a = (c[k + 1] - c[k]).cross(c[k + 2] - c[k]);
    bool on = a.norm() > 0 && a.normalized().dot(n) > 0.9999;
    for (int v = 0; v < 3; ++v) on = on && std::abs(c[k + v].dot(n) - d) < 1e-4;
    if (on) area += a.norm() / 2;
  }
  return area;
}

class KitPlateTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(test::temp_dir("kit_plate"));
    const auto d = test::run_gridshell(fmt::format(
        "design builtin:dome --cells 12 --analyze none --seed 1 --figures none --quiet -o {}",
        (*dir_ / "design").string()));
    ASSERT_EQ(d.status, 0) << d.err;
    const auto k = test::run_gridshell(
        fmt::format("kit {} -o {} --scale 1:50 --rod 3mm --print-bed {}x{}mm --quiet",
                    (*dir_ / "design").string(), (*dir_ / "kit").string(), kBed, kBed));
    ASSERT_EQ(k.status, 0) << k.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::filesystem::path* dir_;
};
std::filesystem::path* KitPlateTest::dir_ = nullptr;

struct Row {
  int joint = 0, plate = 0;
  double x = 0, y = 0, rotation = 0;
};

std::vector<Row> read_plates_csv(const std::filesystem::path& path) {
  std::istringstream in(test::slurp(path));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "joint,plate,x_mm,y_mm,rotation_deg");
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    Row r;
    char c = 0;
    std::istringstream l(line);
    l >> r.joint >> c >> r.plate >> c >> r.x >> c >> r.y >> c >> r.rotation;
    EXPECT_FALSE(l.fail()) << line;
    rows.push_back(r);
  }
  return rows;
}

/// The copy is the original moved rigidly: every corner's distances to four far-apart anchor
/// corners, and the distances among a spread sample of corners, kept; orientation kept.
double rigid_motion_error(const Corners& original, const Corners& copy) {
  const std::size_t n = original.size();
  std::vector<std::size_t> sample;
  for (std::size_t k = 0; k < n; k += std::max<std::size_t>(1, n / 150)) sample.push_back(k);
  double worst = 0;
  for (std::size_t a : sample) {
    for (std::size_t i = 0; i < n; i += (a == sample.front() ? 1 : std::max<std::size_t>(1, n / 150))) {
      worst = std::max(worst, std::abs((original[a] - original[i]).norm() -
                                       (copy[a] - copy[i]).norm()));
    }
  }
  return worst;
}

TEST_F(KitPlateTest, EveryJointOnceMovedRigidlyBaseDownInsideTheBed) {
  const auto rows = read_plates_csv(*dir_ / "kit" / "plates.csv");
  const kit::KitFrame frame = kit::read_kit_frame(*dir_ / "design");
  kit::KitOptions options;
  const auto hubs = kit::plan_hubs(frame, options);
  int with_stl = 0;
  for (const auto& h : hubs) with_stl += h.sockets.empty() ? 0 : 1;
  ASSERT_EQ(static_cast<int>(rows.size()), with_stl);
  std::map<int, int> seen;
  int plates = 0;
  for (const Row& r : rows) ++seen[r.joint], plates = std::max(plates, r.plate + 1);
  for (const auto& [joint, count] : seen) EXPECT_EQ(count, 1) << "joint " << joint;
  ASSERT_GT(plates, 1) << "the test's small bed should need several plates";
  EXPECT_FALSE(std::filesystem::exists(*dir_ / "kit" / "plates" / fmt::format("plate_{}.stl", plates)));

  std::size_t triangles_joints = 0, triangles_plates = 0;
  double worst_rigid = 0, worst_low = 0, flat_parts = 0, footprint_area = 0;
  for (int k = 0; k < plates; ++k) {
    const Corners plate = read_corners(*dir_ / "kit" / "plates" / fmt::format("plate_{}.stl", k));
    triangles_plates += plate.size() / 3;
    std::size_t at = 0;
    struct Box {
      Eigen::Vector2d lo, hi;
    };
    std::vector<Box> boxes;
    for (const Row& r : rows) {  // the plate's parts in plates.csv's order (joint id rising)
      if (r.plate != k) continue;
      const Corners joint = read_corners(*dir_ / "kit" / "joints" / fmt::format("J{}.stl", r.joint));
      triangles_joints += joint.size() / 3;
      ASSERT_LE(at + joint.size(), plate.size()) << "plate " << k;
      const Corners copy(plate.begin() + static_cast<long>(at),
                         plate.begin() + static_cast<long>(at + joint.size()));
      at += joint.size();
      const std::string what = fmt::format("joint {} on plate {}", r.joint, k);
      const double rigid = rigid_motion_error(joint, copy);
      EXPECT_LT(rigid, 1e-4) << what;
      worst_rigid = std::max(worst_rigid, rigid);
      EXPECT_NEAR(signed_volume(copy), signed_volume(joint), 1e-5 * signed_volume(joint)) << what;
      Box b{Eigen::Vector2d::Constant(1e300), Eigen::Vector2d::Constant(-1e300)};
      double low = 1e300;
      for (const Vec3& p : copy) {
        b.lo = b.lo.cwiseMin(p.head<2>()), b.hi = b.hi.cwiseMax(p.head<2>());
        low = std::min(low, p.z());
      }
      EXPECT_NEAR(low, 0, 1e-4) << what;
      worst_low = std::max(worst_low, std::abs(low));
      // The joint's centre (its frame's origin) lies over the part.
      EXPECT_TRUE(r.x > b.lo.x() && r.x < b.hi.x() && r.y > b.lo.y() && r.y < b.hi.y()) << what;
      // The base: the faces on the base plane facing out of it lie on z = 0 facing down.
      const kit::PartBase base = kit::part_base(hubs[r.joint]);
      if (base.flat) {
        const double original = area_on_plane(joint, base.normal, base.distance);
        EXPECT_GT(original, 1.0) << what;
        EXPECT_NEAR(area_on_plane(copy, -Vec3::UnitZ(), 0), original, 1e-3 * original) << what;
        ++flat_parts;
      }
      // Inside the bed, its margin kept.
      EXPECT_GE(b.lo.x(), kMargin - 1e-3) << what;
      EXPECT_GE(b.lo.y(), kMargin - 1e-3) << what;
      EXPECT_LE(b.hi.x(), kBed - kMargin + 1e-3) << what;
      EXPECT_LE(b.hi.y(), kBed - kMargin + 1e-3) << what;
      footprint_area += (b.hi - b.lo).prod();
      boxes.push_back(b);
    }
    EXPECT_EQ(at, plate.size()) << "plate " << k << " holds more than its joints";
    // No two footprints closer than the gap.
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      for (std::size_t j = i + 1; j < boxes.size(); ++j) {
        const double apart = std::max({boxes[j].lo.x() - boxes[i].hi.x(), boxes[i].lo.x() - boxes[j].hi.x(),
                                       boxes[j].lo.y() - boxes[i].hi.y(), boxes[i].lo.y() - boxes[j].hi.y()});
        EXPECT_GE(apart, kGap - 1e-3) << "plate " << k << ": parts " << i << " and " << j;
      }
    }
  }
  EXPECT_EQ(triangles_plates, triangles_joints);
  EXPECT_GT(flat_parts, 0);
  const double usable = (kBed - 2 * kMargin) * (kBed - 2 * kMargin);
  std::cout << fmt::format(
      "plates: {} joints ({} flat bases) on {} plates of {} mm, footprints {:.0f}% of the "
      "usable beds; rigid-motion error {:.1e} mm, lowest z {:.1e} mm\n",
      rows.size(), flat_parts, plates, kBed, 100 * footprint_area / (plates * usable),
      worst_rigid, worst_low);
}

TEST_F(KitPlateTest, BadPrintBedIsOneLineAndExitTwo) {
  const std::string design = (*dir_ / "design").string();
  const auto out = test::temp_dir("kit_plate_bad");
  for (const auto& [bed, word] : std::vector<std::pair<std::string, std::string>>{
           {"10x10mm", "--print-bed"}, {"200", "--print-bed"}, {"25x25mm", "does not fit"}}) {
    const auto r = test::run_gridshell(fmt::format("kit {} -o {} --print-bed {}", design,
                                                   (out / bed).string(), bed));
    EXPECT_EQ(r.status, 2) << bed;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << bed << ": " << r.err;
    EXPECT_NE(r.err.find(word), std::string::npos) << bed << ": " << r.err;
  }
}

}  // namespace
}  // namespace gridshell
