#pragma once
/// \file geometry.h
/// The small geometric helpers every stage shares: triangle area and barycentric points, the
/// closest point on a triangle, planes, sharp corners of boundary loops, and whole-mesh measures
/// (areas, bounding box). One copy of each, so that two stages measuring the same thing get the
/// same bits.
///
/// The one-line helpers are inline: they run in the inner loops of the tessellation and of the
/// regularizer's reprojection. Connectivity (edges, boundary loops) is in topology.h.

#include <cmath>
#include <utility>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

// ---------------------------------------------------------------------------------------------
// Triangles

/// Area of the triangle (a, b, c).
inline double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

/// The point with barycentric coordinates w in the triangle (a, b, c): w₀a + w₁b + w₂c.
inline Vec3 barycentric_point(const Vec3& w, const Vec3& a, const Vec3& b, const Vec3& c) {
  return w(0) * a + w(1) * b + w(2) * c;
}

/// The closest point of a triangle to a query point, and where on the triangle it lies.
struct TrianglePoint {
  Vec3 point;  ///< the closest point
  Vec3 bary;   ///< its barycentric coordinates in (a, b, c)
  /// 0 = inside; 1, 2, 3 = on edge ab, bc, ca (edge k runs from corner k − 1 to corner k);
  /// 4, 5, 6 = at corner a, b, c.
  int region = 0;
};

/// Closest point to p on the triangle (a, b, c) (Ericson, Real-Time Collision Detection,
/// 5.1.5: Voronoi regions of the corners and edges, then the interior). `point` and `bary` are
/// computed independently (from a corner plus edge vectors, and as weights), so
/// barycentric_point(bary, …) may differ from `point` in the last bit.
/// One guard: when the interior case has no finite denominator (twice the squared area, zero
/// or overflowing), the answer is the centroid, region 0, instead of NaN. Two coincident
/// corners are not handled (0/0 in an edge case): SurfaceProjector skips degenerate triangles.
inline TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                               const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {a, Vec3(1, 0, 0), 4};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {b, Vec3(0, 1, 0), 5};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, Vec3(1 - v, v, 0), 1};
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {c, Vec3(0, 0, 1), 6};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, Vec3(1 - w, 0, w), 3};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), Vec3(0, 1 - w, w), 2};
  }
  const double denom = 1.0 / (va + vb + vc);
  if (!std::isfinite(denom)) return {(a + b + c) / 3.0, Vec3(1.0 / 3, 1.0 / 3, 1.0 / 3), 0};
  const double v = vb * denom, w = vc * denom;
  return {a + ab * v + ac * w, Vec3(1 - v - w, v, w), 0};
}

// ---------------------------------------------------------------------------------------------
// Planes

/// The plane {p : (p − point)·normal = 0}, `normal` of unit length: mirror planes of a symmetric
/// design, the cuts of plane_cut.h, a face's fitted plane. Reflections and projections across
/// axis-aligned planes are computed coordinate-wise (2c − x, c), so they are exact involutions
/// up to one rounding and put points exactly on the plane.
struct Plane {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitX();

  /// (p − point)·normal: positive on the side the normal points to.
  double signed_distance(const Vec3& p) const { return (p - point).dot(normal); }
  /// The mirror image of p.
  Vec3 reflect(const Vec3& p) const;
  /// The orthogonal projection of p onto the plane.
  Vec3 project(const Vec3& p) const;
  /// k when the normal is exactly ±(unit vector of axis k), else −1.
  int axis() const;
};

// ---------------------------------------------------------------------------------------------
// Boundary corners

/// The sharp corners of boundary loops (vertex cycles, e.g. Topology::boundary_loops): the
/// vertices where the loop turns by more than `angle_deg` — the angle between the directions of
/// the edge coming in and the edge going out is above it, i.e. their unit vectors' dot product
/// is below cos(angle_deg). A vertex next to an edge of zero length has no turning angle and is
/// not a corner. Returns one flag per row of V (0 off the loops).
/// Defaults of the callers: 30° (tessellation, regularizer, dual mesh), 28.6° = 0.5 rad (regions
/// of the quad baseline).
std::vector<char> boundary_corners(const Points& V, const std::vector<std::vector<int>>& loops,
                                   double angle_deg);

// ---------------------------------------------------------------------------------------------
// Whole meshes

/// Vector area of a (possibly non-planar) polygon: ½ Σ p_k × p_{k+1}; its direction is the
/// polygon's normal (counter-clockwise about it), its norm the area below.
Vec3 vector_area(const PolyMesh& mesh, int face);
/// Area of a (possibly non-planar) polygon: the norm of its vector area.
double polygon_area(const PolyMesh& mesh, int face);
/// The same for a polygon whose corners `face` index the points `pos`.
double polygon_area(const std::vector<Vec3>& pos, const std::vector<int>& face);
/// Signed area of a polygon in the plane (shoelace formula): positive when counter-clockwise.
double signed_area_2d(const std::vector<Eigen::Vector2d>& polygon);
/// Total area of a triangle mesh: the sum of triangle_area over its triangles, in order.
double surface_area(const TriMesh& mesh);
/// Length of the bounding-box diagonal.
double bbox_diagonal(const Points& V);

// ---------------------------------------------------------------------------------------------
// Planes

/// An orthonormal frame (r, s) of the plane normal to the unit vector n, with r × s = n. The same
/// n always gives the same frame (r is n × x̂, or n × ŷ when n is within about 53° of x̂).
std::pair<Vec3, Vec3> plane_axes(const Vec3& n);

/// Twice the signed area of the triangle (p, q, r) in the plane: positive when it turns
/// counter-clockwise, 0 when the three are on a line.
inline double orient_2d(const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                        const Eigen::Vector2d& r) {
  return (q - p).x() * (r - p).y() - (q - p).y() * (r - p).x();
}

/// True when face `face` of `mesh` (projected on the plane of its vector area) is a simple
/// polygon: no repeated corner, a non-zero area, and no two non-adjacent sides crossing.
bool is_simple_polygon(const PolyMesh& mesh, const std::vector<int>& face);

}  // namespace gridshell
