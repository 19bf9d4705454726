#include "gridshell/kit/label.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include <Eigen/Eigenvalues>

namespace gridshell::kit {

namespace {

/// Centre-lines of the segments a–g in a digit's cell, in strokes (cell 4 × 7, origin at its
/// lower left): from (x0, y0) to (x1, y1).
constexpr std::array<std::array<double, 4>, 7> kSegments = {{
    {0.5, 6.5, 3.5, 6.5},  // a: top
    {3.5, 3.5, 3.5, 6.5},  // b: upper right
    {3.5, 0.5, 3.5, 3.5},  // c: lower right
    {0.5, 0.5, 3.5, 0.5},  // d: bottom
    {0.5, 0.5, 0.5, 3.5},  // e: lower left
    {0.5, 3.5, 0.5, 6.5},  // f: upper left
    {0.5, 3.5, 3.5, 3.5},  // g: middle
}};
constexpr double kCellWidth = 4, kCellHeight = 7, kDigitAdvance = 5;  // strokes

/// The mitred hexagon of a stroke s wide along p → q, tips drawn back by kStrokeGap·s.
Polygon2 stroke_hexagon(const Eigen::Vector2d& p, const Eigen::Vector2d& q, double s) {
  const Eigen::Vector2d t = (q - p).normalized(), n(-t.y(), t.x());
  const Eigen::Vector2d a = p + kStrokeGap * s * t, b = q - kStrokeGap * s * t;
  const double h = s / 2;
  return {a, a + h * t - h * n, b - h * t - h * n, b, b - h * t + h * n, a + h * t + h * n};
}

}  // namespace

int digit_segments(int digit) {
  // Bits a..g = 1, 2, 4, ..., 64.
  constexpr std::array<int, 10> kLit = {0x3F, 0x06, 0x5B, 0x4F, 0x66, 0x6D, 0x7D, 0x07, 0x7F, 0x6F};
  return kLit.at(static_cast<std::size_t>(digit));
}

Eigen::Vector2d label_half_size(int id, double stroke) {
  const auto digits = static_cast<double>(std::to_string(id).size());
  return 0.5 * stroke * Eigen::Vector2d(kDigitAdvance * digits - 1, kCellHeight);
}

std::vector<Polygon2> label_strokes(int id, double stroke) {
  const std::string text = std::to_string(id);
  const Eigen::Vector2d half = label_half_size(id, stroke);
  std::vector<Polygon2> strokes;
  for (std::size_t k = 0; k < text.size(); ++k) {
    const Eigen::Vector2d origin(stroke * kDigitAdvance * static_cast<double>(k) - half.x(),
                                 -half.y());
    const int lit = digit_segments(text[k] - '0');
    for (int seg = 0; seg < 7; ++seg) {
      if (!(lit & (1 << seg))) continue;
      const auto& c = kSegments[static_cast<std::size_t>(seg)];
      strokes.push_back(stroke_hexagon(origin + stroke * Eigen::Vector2d(c[0], c[1]),
                                       origin + stroke * Eigen::Vector2d(c[2], c[3]), stroke));
    }
  }
  static_assert(kCellWidth < kDigitAdvance);
  return strokes;
}

Vec3 joint_normal(const std::vector<Vec3>& axes) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (const Vec3& a : axes) m += a * a.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m);  // ascending eigenvalues
  Vec3 n = es.eigenvectors().col(0);
  if (axes.size() < 2 || es.eigenvalues()(1) < 0.05 * es.eigenvalues()(2)) {
    // One beam or collinear beams: the plane is not defined; the direction ⟂ to them nearest
    // to up (or to +x under a vertical beam).
    const Vec3 a = es.eigenvectors().col(2);
    n = Vec3::UnitZ() - a.z() * a;
    if (n.norm() < 1e-6) n = Vec3::UnitX() - a.x() * a;
  }
  n.normalize();
  return n.z() < 0 ? Vec3(-n) : n;
}

namespace {

/// The farthest any part of the hub but its base reaches along the unit direction d.
double reach_along(const HubPlan& hub, const Vec3& d, const KitOptions& o) {
  double reach = hub.hub_radius;
  for (const Socket& s : hub.sockets) {
    const double c = s.axis.dot(d), side = std::sqrt(std::max(0.0, 1 - c * c));
    // The hole runs a rod past the mouth (kit_mesh.cpp); a bridge's stub a wall past the cut.
    const double end = s.bridge ? s.mid + o.wall : s.seat + s.depth + o.rod_diameter;
    const double start = 0.5 * hub.sleeve_radius;
    reach = std::max(reach, std::max(start * c, end * c) + hub.sleeve_radius * side);
  }
  return reach;
}

/// A unit vector ⟂ d: the projection of x (or y) onto d's plane.
Vec3 in_plane(const Vec3& d) {
  Vec3 p = Vec3::UnitX() - d.x() * d;
  if (p.norm() < 0.1) p = Vec3::UnitY() - d.y() * d;
  return p.normalized();
}

}  // namespace

void plan_base(HubPlan& hub, bool supported, const KitOptions& o) {
  std::vector<Vec3> axes;
  for (const Socket& s : hub.sockets) axes.push_back(s.axis);
  const Vec3 n = joint_normal(axes);
  std::vector<Vec3> candidates = {-n, n, -Vec3::UnitZ()};
  if (supported) candidates.insert(candidates.begin(), -Vec3::UnitZ());
  // The first direction no beam comes within 45° of, else the one beams come least close to.
  const auto closest = [&axes](const Vec3& d) {
    double c = -1;
    for (const Vec3& a : axes) c = std::max(c, a.dot(d));
    return c;
  };
  Vec3 d = candidates.front();
  for (const Vec3& c : candidates) {
    if (closest(c) <= std::sqrt(0.5)) {
      d = c;
      break;
    }
    if (closest(c) < closest(d)) d = c;
  }
  hub.base_normal = d;
  hub.foot = supported && d.z() < -0.5;
  hub.base = reach_along(hub, d, o) + o.wall;
  const double s = o.label_stroke;
  const Eigen::Vector2d half = label_half_size(hub.joint, s);
  // Wider than the stem (the sleeves' radius) in any case: a plate of the stem's own radius
  // would be a lathe with two coincident rings, degenerate faces that CGAL's corefinement does
  // not come back from (a 1-digit id with rods of 3.5 mm or more).
  hub.base_radius = std::max((hub.foot ? 2 : 1.25) * hub.sleeve_radius, half.norm() + s);
  // The text's turn in the base plane: the one keeping it farthest inside every bridge's cut
  // (the relief plane less a stroke of margin), among 36 steps of 5°.
  const Vec3 p = in_plane(d), q = d.cross(p);
  const double relief = kReliefWalls * o.wall;
  double best = -1e300;
  for (int k = 0; k < 36; ++k) {
    const double phi = std::numbers::pi * k / 36;
    const Vec3 ex = std::cos(phi) * p + std::sin(phi) * q, ey = d.cross(ex);
    double slack = 1e300;
    for (const Socket& sk : hub.sockets) {
      if (!sk.bridge) continue;
      const double reach = hub.base * d.dot(sk.axis) + half.x() * std::abs(ex.dot(sk.axis)) +
                           half.y() * std::abs(ey.dot(sk.axis));
      slack = std::min(slack, sk.mid - relief - s - reach);
    }
    if (slack > best + 1e-9) {
      best = slack;
      hub.label_x = ex;
      hub.label_y = ey;
    }
  }
  hub.plate_cut = best >= 0;
}

}  // namespace gridshell::kit
