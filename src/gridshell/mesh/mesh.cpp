#include "gridshell/mesh/mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

namespace gridshell {

namespace {

/// The Newell normal of a polygon (length: twice its area).
Vec3 newell_normal(const std::vector<Vec3>& p) {
  Vec3 n = Vec3::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) n += p[i].cross(p[(i + 1) % p.size()]);
  return n;
}

/// Whether a fan from any corner gives triangles with area: every corner of the polygon turns
/// the same way about its normal n, by at least about a degree (a corner on a straight side,
/// as a stitched T-junction leaves, would give a fan triangle of no area).
bool strictly_convex(const std::vector<Vec3>& p, const Vec3& n) {
  constexpr double kStraight = 0.02;  // sin of the smallest turn: 1.1°
  const Vec3 unit = n.normalized();
  const std::size_t m = p.size();
  for (std::size_t i = 0; i < m; ++i) {
    const Vec3 in = p[i] - p[(i + m - 1) % m], out = p[(i + 1) % m] - p[i];
    if (in.cross(out).dot(unit) <= kStraight * in.norm() * out.norm()) return false;
  }
  return true;
}

/// Above this many corners a concave polygon is not given CGAL's cubic-time search over all
/// triangulations (64 corners: milliseconds)…
constexpr std::size_t kCubicSearchCorners = 64;
/// …and above this many not the search restricted to the 3D Delaunay triangulation's faces
/// either (512 corners: a third of a second; 2000: six). A nearly planar one still gets the
/// constrained Delaunay triangulation of its outline (20 000 corners: 0.2 s).
constexpr std::size_t kDelaunaySearchCorners = 512;
/// A concave polygon whose corners lie within this fraction of its size (bounding-box diagonal)
/// from its mean plane is triangulated in that plane (when its projection there is simple).
constexpr double kNearlyPlanar = 0.1;

using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;

/// CGAL's hole filling of the closed polyline `points`: in its plane, the constrained Delaunay
/// triangulation (which needs the outline simple there); otherwise the minimum-weight (area and
/// dihedral angles) triangulation, searched among the 3D Delaunay triangulation's faces and then
/// among all, within the corner caps above. Corner triples; fewer than corners − 2 when it found
/// none.
std::vector<CGAL::Triple<int, int, int>> fill_outline(const std::vector<Point>& points,
                                                      bool in_plane) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  std::vector<CGAL::Triple<int, int, int>> triples;
  const std::size_t corners = points.size();
  if (in_plane)
    PMP::triangulate_hole_polyline(points, std::back_inserter(triples),
                                   CGAL::parameters::use_2d_constrained_delaunay_triangulation(true)
                                       .threshold_distance(1.0)
                                       .use_delaunay_triangulation(false)
                                       .do_not_use_cubic_algorithm(true));
  else
    PMP::triangulate_hole_polyline(
        points, std::back_inserter(triples),
        CGAL::parameters::use_2d_constrained_delaunay_triangulation(false)
            .use_delaunay_triangulation(corners <= kDelaunaySearchCorners)
            .do_not_use_cubic_algorithm(corners > kCubicSearchCorners));
  return triples;
}

/// Triangles (corner indices into `face`) of a polygon: a fan from its first corner when it is
/// convex. A concave one is filled by fill_outline, in its mean plane (the Newell normal's,
/// through the centroid) when its corners lie within kNearlyPlanar of its size from that plane
/// and its projection there is simple, else in 3D. Either keeps the triangles inside the outline
/// where a fan would fold one over the others. Falls back to the fan when CGAL finds none (a
/// polygon through a repeated point, or one of over kDelaunaySearchCorners corners that is far
/// from planar).
std::vector<std::array<int, 3>> polygon_triangles(const PolyMesh& poly,
                                                  const std::vector<int>& face) {
  std::vector<std::array<int, 3>> out;
  std::vector<Vec3> p;
  for (int v : face) p.push_back(poly.vertex(v));
  const Vec3 n = newell_normal(p);
  if (face.size() > 3 && n.norm() > 0 && !strictly_convex(p, n)) {
    const Vec3 normal = n.normalized();
    const Vec3 e1 = normal.unitOrthogonal(), e2 = normal.cross(e1);
    Vec3 centre = Vec3::Zero();
    Eigen::AlignedBox3d box;
    for (const Vec3& x : p) {
      centre += x / static_cast<double>(p.size());
      box.extend(x);
    }
    double off_plane = 0;
    std::vector<Point> plane, space;
    for (const Vec3& x : p) {
      const Vec3 d = x - centre;
      off_plane = std::max(off_plane, std::abs(d.dot(normal)));
      plane.emplace_back(d.dot(e1), d.dot(e2), 0.0);
      space.emplace_back(x.x(), x.y(), x.z());
    }
    std::vector<CGAL::Triple<int, int, int>> triples;
    if (off_plane <= kNearlyPlanar * box.diagonal().norm()) triples = fill_outline(plane, true);
    if (triples.size() + 2 != face.size()) triples = fill_outline(space, false);
    if (triples.size() + 2 == face.size()) {
      for (const auto& t : triples) {
        std::array<int, 3> k{t.first, t.second, t.third};
        if ((p[k[1]] - p[k[0]]).cross(p[k[2]] - p[k[0]]).dot(n) < 0) std::swap(k[1], k[2]);
        out.push_back({face[k[0]], face[k[1]], face[k[2]]});
      }
      return out;
    }
  }
  for (std::size_t k = 1; k + 1 < face.size(); ++k) out.push_back({face[0], face[k], face[k + 1]});
  return out;
}

}  // namespace

TriMesh triangulate(const PolyMesh& poly) {
  TriMesh out;
  out.V = poly.V;
  std::vector<std::array<int, 3>> triangles;
  for (const auto& f : poly.faces)
    for (const auto& t : polygon_triangles(poly, f)) triangles.push_back(t);
  out.F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t r = 0; r < triangles.size(); ++r)
    out.F.row(static_cast<Eigen::Index>(r)) << triangles[r][0], triangles[r][1], triangles[r][2];
  return out;
}

PolyMesh to_poly(const TriMesh& tri) {
  PolyMesh out;
  out.V = tri.V;
  out.faces.reserve(tri.F.rows());
  for (int f = 0; f < tri.F.rows(); ++f)
    out.faces.push_back({tri.F(f, 0), tri.F(f, 1), tri.F(f, 2)});
  return out;
}

Points to_points(const std::vector<Vec3>& x) {
  Points V(static_cast<Eigen::Index>(x.size()), 3);
  for (std::size_t j = 0; j < x.size(); ++j) V.row(static_cast<Eigen::Index>(j)) = x[j].transpose();
  return V;
}

}  // namespace gridshell
