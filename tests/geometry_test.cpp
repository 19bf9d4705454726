// The shared geometric helpers of mesh/geometry.h on hand-made cases.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "gridshell/mesh/geometry.h"
#include "gridshell/surfaces/grid.h"

using namespace gridshell;

namespace {

/// The closest point of triangle (a, b, c) to p by brute force over a fine barycentric grid.
double brute_force_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  double best = std::numeric_limits<double>::infinity();
  const int n = 400;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const Vec3 w(double(n - i - j) / n, double(i) / n, double(j) / n);
      best = std::min(best, (barycentric_point(w, a, b, c) - p).norm());
    }
  return best;
}

}  // namespace

TEST(Geometry, TriangleAreaAndBarycentricPoint) {
  const Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 3, 0);
  EXPECT_DOUBLE_EQ(triangle_area(a, b, c), 3.0);
  EXPECT_DOUBLE_EQ(triangle_area(a, c, b), 3.0);  // unsigned
  EXPECT_EQ(triangle_area(a, b, 2 * b), 0.0);
  EXPECT_EQ(barycentric_point(Vec3(1, 0, 0), a, b, c), a);
  EXPECT_TRUE(barycentric_point(Vec3(0.25, 0.25, 0.5), a, b, c).isApprox(Vec3(0.5, 1.5, 0)));
}

TEST(Geometry, ClosestPointOnTriangleRegions) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  struct Case {
    Vec3 p, point;
    int region;
  };
  const Case cases[] = {
      {Vec3(0.2, 0.3, 5), Vec3(0.2, 0.3, 0), 0},   // above the inside
      {Vec3(0.5, -1, 1), Vec3(0.5, 0, 0), 1},      // beyond edge ab
      {Vec3(1, 1, -2), Vec3(0.5, 0.5, 0), 2},      // beyond edge bc
      {Vec3(-1, 0.25, 0), Vec3(0, 0.25, 0), 3},    // beyond edge ca
      {Vec3(-1, -1, 3), a, 4},                     // beyond corner a
      {Vec3(2, -0.5, 0), b, 5},                    // beyond corner b
      {Vec3(-0.5, 2, 1), c, 6},                    // beyond corner c
  };
  for (const Case& k : cases) {
    const TrianglePoint t = closest_point_on_triangle(k.p, a, b, c);
    EXPECT_EQ(t.region, k.region) << k.p.transpose();
    EXPECT_TRUE(t.point.isApprox(k.point, 1e-15) || (t.point - k.point).norm() < 1e-15)
        << k.p.transpose();
    EXPECT_NEAR(t.bary.sum(), 1.0, 1e-15);
    EXPECT_LT((barycentric_point(t.bary, a, b, c) - t.point).norm(), 1e-15);
  }
}

TEST(Geometry, ClosestPointOnTriangleMatchesBruteForce) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> N;
  for (int it = 0; it < 200; ++it) {
    const Vec3 a(N(rng), N(rng), N(rng)), b(N(rng), N(rng), N(rng)), c(N(rng), N(rng), N(rng));
    const Vec3 p(2 * N(rng), 2 * N(rng), 2 * N(rng));
    const TrianglePoint t = closest_point_on_triangle(p, a, b, c);
    const double d = (t.point - p).norm();
    // The exact answer is never farther than the best grid point, and the grid point is within
    // the grid spacing of it.
    const double scale = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
    const double brute = brute_force_distance(p, a, b, c);
    EXPECT_LE(d, brute + 1e-12);
    EXPECT_GE(d, brute - 2 * scale / 400);
    EXPECT_GE(t.bary.minCoeff(), 0.0);
    EXPECT_LT((barycentric_point(t.bary, a, b, c) - t.point).norm(), 1e-12 * (1 + scale));
  }
}

TEST(Geometry, ClosestPointGuardGivesTheCentroidWhenTheInteriorCaseOverflows) {
  // Coordinates of 1e77: the products of the interior case overflow (∞ − ∞ = NaN). The guard
  // gives the centroid instead of a NaN point (the tessellation's copy always had it; the
  // projector's did not).
  const double s = 1e77;
  const Vec3 a = s * Vec3(2, 4, -1), b = s * Vec3(-3, -4, 4), c = s * Vec3(-3, 4, -2);
  const TrianglePoint t = closest_point_on_triangle(s * Vec3(-1, -4, -2), a, b, c);
  EXPECT_EQ(t.region, 0);
  EXPECT_EQ(t.bary, Vec3(1.0 / 3, 1.0 / 3, 1.0 / 3));
  EXPECT_TRUE(t.point.allFinite());
  EXPECT_TRUE(t.point.isApprox((a + b + c) / 3.0));
}

TEST(Geometry, SurfaceAreaAndBoundingBox) {
  const TriMesh m = flat_grid(7, 5, 20, 20);
  double sum = 0;
  for (int f = 0; f < m.num_faces(); ++f)
    sum += triangle_area(m.vertex(m.F(f, 0)), m.vertex(m.F(f, 1)), m.vertex(m.F(f, 2)));
  EXPECT_EQ(surface_area(m), sum);
  EXPECT_NEAR(surface_area(m), 400.0, 1e-9);
  EXPECT_NEAR(bbox_diagonal(m.V), std::sqrt(800.0), 1e-12);
  PolyMesh square;
  square.V.resize(4, 3);
  square.V << 0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0;
  square.faces = {{0, 1, 2, 3}};
  EXPECT_DOUBLE_EQ(polygon_area(square, 0), 4.0);
  // The same square as points and corner ids, listed from another corner: the same area.
  const std::vector<Vec3> pos = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 2, 0), Vec3(0, 2, 0)};
  EXPECT_DOUBLE_EQ(polygon_area(pos, {2, 3, 0, 1}), 4.0);
  // A square bent along its diagonal (corners 1 and 3 raised by 1): the vector area's norm is
  // its plan area, 4, less than the area of its two triangles, 2 · 2√1.5.
  const std::vector<Vec3> bent = {Vec3(0, 0, 0), Vec3(2, 0, 1), Vec3(2, 2, 0), Vec3(0, 2, 1)};
  EXPECT_NEAR(polygon_area(bent, {0, 1, 2, 3}), 4.0, 1e-12);
}

TEST(Geometry, PlaneSignedDistanceReflectionAndProjection) {
  const Plane x{Vec3(1.5, 0, 0), Vec3::UnitX()};
  EXPECT_EQ(x.axis(), 0);
  EXPECT_EQ(x.signed_distance(Vec3(4, 7, -2)), 2.5);
  EXPECT_EQ(x.reflect(Vec3(4, 7, -2)), Vec3(-1, 7, -2));  // coordinate-wise: exact
  EXPECT_EQ(x.project(Vec3(4, 7, -2)), Vec3(1.5, 7, -2));
  const Vec3 p(0.1, 0.7, 0.3);
  EXPECT_NEAR((x.reflect(x.reflect(p)) - p).norm(), 0.0, 1e-15);  // up to one rounding
  EXPECT_EQ(Plane({Vec3::Zero(), -Vec3::UnitY()}).axis(), 1);

  const Plane tilted{Vec3(1, 2, 3), Vec3(1, 1, 0).normalized()};
  EXPECT_EQ(tilted.axis(), -1);
  EXPECT_NEAR(tilted.signed_distance(Vec3(2, 3, 3)), std::sqrt(2.0), 1e-15);
  EXPECT_TRUE(tilted.reflect(Vec3(2, 3, 3)).isApprox(Vec3(0, 1, 3)));
  EXPECT_NEAR(tilted.signed_distance(tilted.project(Vec3(5, -1, 2))), 0.0, 1e-15);
  EXPECT_NEAR((tilted.reflect(tilted.reflect(p)) - p).norm(), 0.0, 1e-14);
}

TEST(Geometry, BoundaryCornersTurnByMoreThanTheAngle) {
  // An L-shaped loop with a straight run (0°), a right turn (90°), a 45° turn and a doubled
  // vertex (zero-length edge: no direction, never a corner).
  Points V(7, 3);
  V << 0, 0, 0,  // 0: start of the loop, 90° turn
      1, 0, 0,   // 1: straight
      2, 0, 0,   // 2: 45° turn
      3, 1, 0,   // 3: 45° turn (from (1,1) to (0,1))
      3, 2, 0,   // 4: 90° turn
      3, 2, 0,   // 5: same point as 4
      0, 2, 0;   // 6: 90° turn
  const std::vector<std::vector<int>> loops = {{0, 1, 2, 3, 4, 5, 6}};
  const std::vector<char> at30 = boundary_corners(V, loops, 30);
  EXPECT_EQ(at30, std::vector<char>({1, 0, 1, 1, 0, 0, 1}));
  const std::vector<char> at60 = boundary_corners(V, loops, 60);
  EXPECT_EQ(at60, std::vector<char>({1, 0, 0, 0, 0, 0, 1}));
  // Vertices off every loop are never corners.
  EXPECT_EQ(boundary_corners(V, {{0, 2, 6}}, 30), std::vector<char>({1, 0, 1, 0, 0, 0, 1}));
}

TEST(Geometry, SignedArea2dIsPositiveCounterClockwise) {
  // An L-shaped hexagon of area 3 (a 2×2 square less a unit square), both orientations.
  std::vector<Eigen::Vector2d> p{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  EXPECT_DOUBLE_EQ(signed_area_2d(p), 3.0);
  std::reverse(p.begin(), p.end());
  EXPECT_DOUBLE_EQ(signed_area_2d(p), -3.0);
  EXPECT_DOUBLE_EQ(signed_area_2d({}), 0.0);
}

// The frame of a plane is orthonormal and right-handed about its normal, for normals along and
// near each axis (the frame switches from x̂ to ŷ at |n.x| = 0.6); orient_2d is twice the signed
// area (the unit right triangle: ±1, three points on a line: 0).
TEST(Geometry, PlaneAxesAndOrientation) {
  for (Vec3 n : {Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0.6, 0.8, 0),
                 Vec3(0.59, 0.1, 0.8), Vec3(-1, 2, 3)}) {
    n.normalize();
    const auto [r, s] = plane_axes(n);
    EXPECT_NEAR(r.norm(), 1, 1e-15);
    EXPECT_NEAR(s.norm(), 1, 1e-15);
    EXPECT_NEAR(r.dot(n), 0, 1e-15);
    EXPECT_NEAR(r.dot(s), 0, 1e-15);
    EXPECT_NEAR((r.cross(s) - n).norm(), 0, 1e-15);
  }
  const Eigen::Vector2d o(0, 0), x(1, 0), y(0, 1);
  EXPECT_EQ(orient_2d(o, x, y), 1.0);
  EXPECT_EQ(orient_2d(o, y, x), -1.0);
  EXPECT_EQ(orient_2d(o, x, Eigen::Vector2d(3, 0)), 0.0);
  // The vector area of a unit square in the plane z = 2: ẑ counter-clockwise, −ẑ the other way.
  PolyMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 2, 1, 0, 2, 1, 1, 2, 0, 1, 2;
  m.faces = {{0, 1, 2, 3}, {3, 2, 1, 0}};
  EXPECT_NEAR((vector_area(m, 0) - Vec3(0, 0, 1)).norm(), 0, 1e-15);
  EXPECT_NEAR((vector_area(m, 1) - Vec3(0, 0, -1)).norm(), 0, 1e-15);
}

// A simple polygon: a square in 3D is; a bow-tie (two sides crossing), a face that uses a corner
// twice and a face of zero area are not.
TEST(Geometry, SimplePolygon) {
  gridshell::PolyMesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 1, 0, 0.5, 1, 1, 1, 0, 1, 0.5, 2, 0, 1;  // a tilted unit square and one more
  EXPECT_TRUE(gridshell::is_simple_polygon(m, {0, 1, 2, 3}));
  EXPECT_TRUE(gridshell::is_simple_polygon(m, {3, 2, 1, 0}));
  EXPECT_FALSE(gridshell::is_simple_polygon(m, {0, 2, 1, 3}));  // bow-tie
  EXPECT_FALSE(gridshell::is_simple_polygon(m, {0, 1, 2, 1}));  // a corner twice
  gridshell::PolyMesh line;
  line.V.resize(3, 3);
  line.V << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  EXPECT_FALSE(gridshell::is_simple_polygon(line, {0, 1, 2}));  // no area
}
