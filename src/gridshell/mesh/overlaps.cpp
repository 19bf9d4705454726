#include "gridshell/mesh/overlaps.h"

#include <CGAL/Bbox_3.h>
#include <CGAL/Box_intersection_d/Box_with_handle_d.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "gridshell/mesh/geometry.h"

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

double distance_to_segment(const Eigen::Vector2d& x, const Eigen::Vector2d& a,
                           const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((x - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (x - (a + t * ab)).norm();
}

/// Whether beams (a, b) and (c, d), seen along the mean of their ends' normals, cross — not at a
/// shared joint, and at points closer in space than a quarter of their mean length.
bool beams_cross(const PolyMesh& mesh, const std::vector<Vec3>& normal, int a, int b, int c,
                 int d) {
  if (a == c || a == d || b == c || b == d) return false;
  const Vec3 n = normal[a] + normal[b] + normal[c] + normal[d];
  if (!(n.norm() > 0)) return false;
  // Plain variables, not a structured binding: the lambda below captures them (Clang before 16
  // cannot capture a binding).
  const std::pair<Vec3, Vec3> axes = plane_axes(n.normalized());
  const Vec3 r = axes.first, s = axes.second;
  auto view = [&](int v) {
    const Vec3 p = mesh.vertex(v);
    return Eigen::Vector2d(p.dot(r), p.dot(s));
  };
  const Eigen::Vector2d pa = view(a), pb = view(b), pc = view(c), pd = view(d);
  const double eps = 1e-9 * (pb - pa).norm() * (pd - pc).norm();
  const double o1 = orient_2d(pa, pb, pc), o2 = orient_2d(pa, pb, pd);
  const double o3 = orient_2d(pc, pd, pa), o4 = orient_2d(pc, pd, pb);
  if (!((o1 > eps && o2 < -eps) || (o1 < -eps && o2 > eps))) return false;
  if (!((o3 > eps && o4 < -eps) || (o3 < -eps && o4 > eps))) return false;
  const double t = o3 / (o3 - o4), u = o1 / (o1 - o2);
  const Vec3 x = mesh.vertex(a) + t * (mesh.vertex(b) - mesh.vertex(a));
  const Vec3 y = mesh.vertex(c) + u * (mesh.vertex(d) - mesh.vertex(c));
  const double mean_length =
      0.5 * ((mesh.vertex(b) - mesh.vertex(a)).norm() + (mesh.vertex(d) - mesh.vertex(c)).norm());
  return (x - y).norm() <= 0.25 * mean_length;
}

/// Whether joint v, not a corner of face f, lies inside f seen along f's normal: farther than a
/// thousandth of f's mean side from its sides, within half of it from f's mean plane.
bool joint_inside_panel(const PolyMesh& mesh, const Vec3& face_area, double mean_side, int v,
                        int f) {
  const auto& poly = mesh.faces[f];
  if (std::find(poly.begin(), poly.end(), v) != poly.end()) return false;
  if (!(face_area.norm() > 0)) return false;
  const Vec3 n = face_area.normalized();
  Vec3 centre = Vec3::Zero();
  for (int w : poly) centre += mesh.vertex(w);
  centre /= static_cast<double>(poly.size());
  const Vec3 p = mesh.vertex(v);
  if (std::abs((p - centre).dot(n)) > 0.5 * mean_side) return false;
  const auto [r, s] = plane_axes(n);
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
  return inside && nearest > 1e-3 * mean_side;
}

std::vector<int> numbers(int n) {
  std::vector<int> ids(n);
  std::iota(ids.begin(), ids.end(), 0);
  return ids;
}

}  // namespace

Overlaps find_overlaps(const PolyMesh& mesh, const Topology& topo) {
  Overlaps out;
  const int nv = mesh.num_vertices(), nf = mesh.num_faces(), ne = topo.num_edges();
  if (nf == 0) return out;
  std::vector<Vec3> face_area(nf), normal(nv, Vec3::Zero());
  std::vector<double> mean_side(nf, 0);
  for (int f = 0; f < nf; ++f) {
    face_area[f] = vector_area(mesh, f);
    const auto& poly = mesh.faces[f];
    for (size_t k = 0; k < poly.size(); ++k) {
      normal[poly[k]] += face_area[f];
      mean_side[f] +=
          (mesh.vertex(poly[k]) - mesh.vertex(poly[(k + 1) % poly.size()])).norm() / poly.size();
    }
  }
  // CGAL takes two boxes with one id for one box: vertices, edges and faces each have their own
  // ids (pointers into separate arrays). Candidates are tested as CGAL reports them (there are
  // about a dozen per element: kept, they cost more than the tests); the hits are sorted after.
  const std::vector<int> edge_ids = numbers(ne), face_ids = numbers(nf), vertex_ids = numbers(nv);

  // Beams that cross.
  std::vector<Box> edge_boxes;
  edge_boxes.reserve(ne);
  for (int e = 0; e < ne; ++e) {
    const Vec3 a = mesh.vertex(topo.edges[e][0]), b = mesh.vertex(topo.edges[e][1]);
    // Two beams that cross meet within a quarter of their mean length (beams_cross): margins of
    // an eighth of each beam's length make their boxes meet.
    edge_boxes.push_back(box_around({a, b}, 0.125 * (b - a).norm(), &edge_ids[e]));
  }
  CGAL::box_self_intersection_d(
      edge_boxes.begin(), edge_boxes.end(), [&](const Box& x, const Box& y) {
        const int i = std::min(*x.handle(), *y.handle()), j = std::max(*x.handle(), *y.handle());
        if (beams_cross(mesh, normal, topo.edges[i][0], topo.edges[i][1], topo.edges[j][0],
                        topo.edges[j][1]))
          out.crossing_edges.push_back({i, j});
      });
  std::sort(out.crossing_edges.begin(), out.crossing_edges.end());

  // Joints inside panels that do not use them.
  std::vector<Box> face_boxes, vertex_boxes;
  face_boxes.reserve(nf);
  for (int f = 0; f < nf; ++f) {
    std::vector<Vec3> corners;
    for (int v : mesh.faces[f]) corners.push_back(mesh.vertex(v));
    face_boxes.push_back(box_around(corners, 0.5 * mean_side[f], &face_ids[f]));
  }
  for (int v = 0; v < nv; ++v)
    if (!topo.vertex_faces[v].empty())
      vertex_boxes.push_back(box_around({mesh.vertex(v)}, 0, &vertex_ids[v]));
  CGAL::box_intersection_d(vertex_boxes.begin(), vertex_boxes.end(), face_boxes.begin(),
                           face_boxes.end(), [&](const Box& x, const Box& y) {
                             const int v = *x.handle(), f = *y.handle();
                             if (joint_inside_panel(mesh, face_area[f], mean_side[f], v, f))
                               out.covered_vertices.push_back({v, f});
                           });
  std::sort(out.covered_vertices.begin(), out.covered_vertices.end());
  return out;
}

}  // namespace gridshell
