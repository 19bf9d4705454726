#include "gridshell/mesh/geometry.h"

#include <algorithm>
#include <numbers>

namespace gridshell {

int Plane::axis() const {
  const Vec3& n = normal;
  for (int k = 0; k < 3; ++k)
    if (std::abs(n[k]) == 1.0 && n[(k + 1) % 3] == 0.0 && n[(k + 2) % 3] == 0.0) return k;
  return -1;
}

Vec3 Plane::reflect(const Vec3& p) const {
  const int k = axis();
  if (k >= 0) {
    Vec3 q = p;
    q[k] = 2 * point[k] - p[k];
    return q;
  }
  return p - 2 * signed_distance(p) * normal;
}

Vec3 Plane::project(const Vec3& p) const {
  const int k = axis();
  if (k >= 0) {
    Vec3 q = p;
    q[k] = point[k];
    return q;
  }
  return p - signed_distance(p) * normal;
}

std::vector<char> boundary_corners(const Points& V, const std::vector<std::vector<int>>& loops,
                                   double angle_deg) {
  std::vector<char> corner(V.rows(), 0);
  const double cos_limit = std::cos(angle_deg * std::numbers::pi / 180.0);
  for (const auto& loop : loops) {
    const std::size_t n = loop.size();
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3 p = V.row(loop[(k + n - 1) % n]).transpose(), v = V.row(loop[k]).transpose(),
                 q = V.row(loop[(k + 1) % n]).transpose();
      const Vec3 d1 = (v - p).normalized(), d2 = (q - v).normalized();  // zero stays zero
      if (d1.squaredNorm() > 0 && d2.squaredNorm() > 0 && d1.dot(d2) < cos_limit)
        corner[loop[k]] = 1;
    }
  }
  return corner;
}

double signed_area_2d(const std::vector<Eigen::Vector2d>& polygon) {
  double a = 0;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Eigen::Vector2d& u = polygon[k];
    const Eigen::Vector2d& v = polygon[(k + 1) % polygon.size()];
    a += u.x() * v.y() - u.y() * v.x();
  }
  return 0.5 * a;
}

namespace {
/// The vector area of polygon `face`, corner v at point(v).
template <class Point>
Vec3 vector_area_of(const std::vector<int>& face, Point point) {
  Vec3 a = Vec3::Zero();
  for (std::size_t k = 0; k < face.size(); ++k)
    a += point(face[k]).cross(point(face[(k + 1) % face.size()]));
  return 0.5 * a;  // halving is exact: the norm below is bit for bit 0.5 × |Σ|
}
}  // namespace

Vec3 vector_area(const PolyMesh& mesh, int face) {
  return vector_area_of(mesh.faces[face], [&](int v) { return Vec3(mesh.vertex(v)); });
}

double polygon_area(const PolyMesh& mesh, int face) { return vector_area(mesh, face).norm(); }

double polygon_area(const std::vector<Vec3>& pos, const std::vector<int>& face) {
  return vector_area_of(face, [&](int v) { return pos[v]; }).norm();
}

double surface_area(const TriMesh& mesh) {
  double area = 0;
  for (int f = 0; f < mesh.num_faces(); ++f)
    area += triangle_area(mesh.vertex(mesh.F(f, 0)), mesh.vertex(mesh.F(f, 1)),
                          mesh.vertex(mesh.F(f, 2)));
  return area;
}

double bbox_diagonal(const Points& V) {
  if (V.rows() == 0) return 0;
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

std::pair<Vec3, Vec3> plane_axes(const Vec3& n) {
  const Vec3 r = n.cross(std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY()).normalized();
  return {r, n.cross(r)};
}

namespace {

bool segments_cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                    const Eigen::Vector2d& d) {
  auto orient = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
    const double v = orient_2d(p, q, r);
    return (v > 0) - (v < 0);
  };
  return orient(a, b, c) * orient(a, b, d) < 0 && orient(c, d, a) * orient(c, d, b) < 0;
}

}  // namespace

bool is_simple_polygon(const PolyMesh& mesh, const std::vector<int>& f) {
  const int n = static_cast<int>(f.size());
  std::vector<int> sorted = f;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return false;
  Vec3 normal = Vec3::Zero(), centre = Vec3::Zero();
  for (int k = 0; k < n; ++k) {
    normal += mesh.vertex(f[k]).cross(mesh.vertex(f[(k + 1) % n]));
    centre += mesh.vertex(f[k]);
  }
  if (normal.norm() == 0) return false;
  normal.normalize();
  const auto [r, s] = plane_axes(normal);
  std::vector<Eigen::Vector2d> p(n);
  for (int k = 0; k < n; ++k) {
    const Vec3 d = mesh.vertex(f[k]) - centre / n;
    p[k] = Eigen::Vector2d(d.dot(r), d.dot(s));
  }
  for (int i = 0; i < n; ++i)
    for (int j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;
      if (segments_cross(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n])) return false;
    }
  return true;
}

}  // namespace gridshell
