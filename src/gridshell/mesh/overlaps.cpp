#include "gridshell/mesh/overlaps.h"

#include <CGAL/Bbox_3.h>
#include <CGAL/Box_intersection_d/Box_with_handle_d.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace gridshell {

namespace {

// Boxes carry a pointer to their element's id: the id is stable when CGAL copies the boxes.
using Box = CGAL::Box_intersection_d::Box_with_handle_d<double, 3, const int*>;

Box box_around(const std::vector<Vec3>& points, double margin, const int* id) {
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return Box(CGAL::Bbox_3(lo.x() - margin, lo.y() - margin, lo.z() - margin, hi.x() + margin,
                          hi.y() + margin, hi.z() + margin),
             id);
}

/// A frame of the plane normal to n: (r, s).
std::pair<Vec3, Vec3> plane_axes(const Vec3& n) {
  const Vec3 r =
      n.cross(std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY()).normalized();
  return {r, n.cross(r)};
}

double orient(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
  return (q - p).x() * (r - p).y() - (q - p).y() * (r - p).x();
}

double distance_to_segment(const Eigen::Vector2d& x, const Eigen::Vector2d& a,
                           const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((x - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (x - (a + t * ab)).norm();
}

}  // namespace

Overlaps find_overlaps(const PolyMesh& mesh, const Topology& topo) {
  Overlaps out;
  const int nv = mesh.num_vertices(), nf = mesh.num_faces(), ne = topo.num_edges();
  if (nf == 0) return out;
  std::vector<Vec3> face_area(nf, Vec3::Zero()), normal(nv, Vec3::Zero());
  for (int f = 0; f < nf; ++f) {
    const auto& poly = mesh.faces[f];
    for (size_t k = 0; k < poly.size(); ++k)
      face_area[f] += mesh.vertex(poly[k]).cross(mesh.vertex(poly[(k + 1) % poly.size()]));
    face_area[f] *= 0.5;
    for (int v : poly) normal[v] += face_area[f];
  }
  // CGAL takes two boxes with one id for one box: vertices, edges and faces each have their own
  // ids (pointers into separate arrays).
  auto numbers = [](int n) {
    std::vector<int> ids(n);
    std::iota(ids.begin(), ids.end(), 0);
    return ids;
  };
  const std::vector<int> edge_ids = numbers(ne), face_ids = numbers(nf), vertex_ids = numbers(nv);

  // Beams that cross.
  std::vector<Box> edge_boxes;
  edge_boxes.reserve(ne);
  for (int e = 0; e < ne; ++e) {
    const Vec3 a = mesh.vertex(topo.edges[e][0]), b = mesh.vertex(topo.edges[e][1]);
    edge_boxes.push_back(box_around({a, b}, 0.25 * (b - a).norm(), &edge_ids[e]));
  }
  std::vector<std::array<int, 2>> edge_pairs;
  CGAL::box_self_intersection_d(edge_boxes.begin(), edge_boxes.end(),
                                [&](const Box& x, const Box& y) {
                                  const int i = *x.handle(), j = *y.handle();
                                  edge_pairs.push_back({std::min(i, j), std::max(i, j)});
                                });
  std::sort(edge_pairs.begin(), edge_pairs.end());
  for (const auto& [i, j] : edge_pairs) {
    const int a = topo.edges[i][0], b = topo.edges[i][1];
    const int c = topo.edges[j][0], d = topo.edges[j][1];
    if (a == c || a == d || b == c || b == d) continue;
    const Vec3 n = normal[a] + normal[b] + normal[c] + normal[d];
    if (!(n.norm() > 0)) continue;
    // Plain variables, not a structured binding: the lambda below captures them (Clang before
    // 16 cannot capture a binding).
    const std::pair<Vec3, Vec3> axes = plane_axes(n.normalized());
    const Vec3 r = axes.first, s = axes.second;
    auto view = [&](int v) {
      const Vec3 p = mesh.vertex(v);
      return Eigen::Vector2d(p.dot(r), p.dot(s));
    };
    const Eigen::Vector2d pa = view(a), pb = view(b), pc = view(c), pd = view(d);
    const double scale = (pb - pa).norm() * (pd - pc).norm();
    const double o1 = orient(pa, pb, pc), o2 = orient(pa, pb, pd);
    const double o3 = orient(pc, pd, pa), o4 = orient(pc, pd, pb);
    const double eps = 1e-9 * scale;
    if (!((o1 > eps && o2 < -eps) || (o1 < -eps && o2 > eps))) continue;
    if (!((o3 > eps && o4 < -eps) || (o3 < -eps && o4 > eps))) continue;
    const double t = o3 / (o3 - o4), u = o1 / (o1 - o2);
    const Vec3 x = mesh.vertex(a) + t * (mesh.vertex(b) - mesh.vertex(a));
    const Vec3 y = mesh.vertex(c) + u * (mesh.vertex(d) - mesh.vertex(c));
    const double mean_length =
        0.5 * ((mesh.vertex(b) - mesh.vertex(a)).norm() + (mesh.vertex(d) - mesh.vertex(c)).norm());
    if ((x - y).norm() <= 0.25 * mean_length) out.crossing_edges.push_back({i, j});
  }

  // Joints inside panels that do not use them.
  std::vector<double> mean_side(nf, 0);
  std::vector<Box> face_boxes, vertex_boxes;
  for (int f = 0; f < nf; ++f) {
    const auto& poly = mesh.faces[f];
    std::vector<Vec3> corners;
    for (size_t k = 0; k < poly.size(); ++k) {
      corners.push_back(mesh.vertex(poly[k]));
      mean_side[f] +=
          (mesh.vertex(poly[k]) - mesh.vertex(poly[(k + 1) % poly.size()])).norm() / poly.size();
    }
    face_boxes.push_back(box_around(corners, 0.5 * mean_side[f], &face_ids[f]));
  }
  for (int v = 0; v < nv; ++v)
    if (!topo.vertex_faces[v].empty()) vertex_boxes.push_back(box_around({mesh.vertex(v)}, 0, &vertex_ids[v]));
  std::vector<std::array<int, 2>> vertex_face;
  CGAL::box_intersection_d(vertex_boxes.begin(), vertex_boxes.end(), face_boxes.begin(),
                           face_boxes.end(), [&](const Box& x, const Box& y) {
                             vertex_face.push_back({*x.handle(), *y.handle()});
                           });
  std::sort(vertex_face.begin(), vertex_face.end());
  for (const auto& [v, f] : vertex_face) {
    const auto& poly = mesh.faces[f];
    if (std::find(poly.begin(), poly.end(), v) != poly.end()) continue;
    if (!(face_area[f].norm() > 0)) continue;
    const Vec3 n = face_area[f].normalized();
    Vec3 centre = Vec3::Zero();
    for (int w : poly) centre += mesh.vertex(w);
    centre /= static_cast<double>(poly.size());
    const Vec3 p = mesh.vertex(v);
    if (std::abs((p - centre).dot(n)) > 0.5 * mean_side[f]) continue;
    const std::pair<Vec3, Vec3> axes = plane_axes(n);
    const Vec3 r = axes.first, s = axes.second;
    const Eigen::Vector2d x(p.dot(r), p.dot(s));
    std::vector<Eigen::Vector2d> q;
    for (int w : poly) q.emplace_back(mesh.vertex(w).dot(r), mesh.vertex(w).dot(s));
    bool inside = false;
    double nearest = std::numeric_limits<double>::infinity();
    for (size_t k = 0, m = q.size(); k < m; ++k) {
      const Eigen::Vector2d &a = q[k], &b = q[(k + 1) % m];
      if ((a.y() > x.y()) != (b.y() > x.y()) &&
          x.x() < a.x() + (x.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
        inside = !inside;
      nearest = std::min(nearest, distance_to_segment(x, a, b));
    }
    if (inside && nearest > 1e-3 * mean_side[f]) out.covered_vertices.push_back({v, f});
  }
  return out;
}

}  // namespace gridshell
