// The flat stage's last resort (flat_panels_internal.h, split_failing_panels): where the planes
// fail the post-check, the failing panels give up their planes and are glazed as flat triangles.
#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/overlaps.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/flat_panels_internal.h"
#include "gridshell/optimize/metrics.h"
#include "gridshell/optimize/projector.h"

namespace gridshell::flat_detail {

namespace {

/// The point nearest `t` on the k ≤ 3 planes n_i·x = d_i: their intersection when k = 3, else
/// t + Nᵀ (N Nᵀ)⁻¹ (d − N t). False when the planes are nearly parallel.
bool nearest_on_planes(const Vec3 n[3], const double d[3], int k, const Vec3& t, double min_det,
                       Vec3& x) {
  if (k == 3) {
    double det = 0;
    return intersect_planes(n, d, x, det, min_det);
  }
  if (k == 0) {
    x = t;
    return true;
  }
  if (k == 1) {
    x = t + (d[0] - n[0].dot(t)) / n[0].squaredNorm() * n[0];
    return true;
  }
  const double g00 = n[0].squaredNorm(), g01 = n[0].dot(n[1]), g11 = n[1].squaredNorm();
  const double g = g00 * g11 - g01 * g01;
  if (!(g > min_det * g00 * g11)) return false;
  const double r0 = d[0] - n[0].dot(t), r1 = d[1] - n[1].dot(t);
  x = t + (g11 * r0 - g01 * r1) / g * n[0] + (g00 * r1 - g01 * r0) / g * n[1];
  return true;
}

/// Smallest corner angle (radians) of the triangle a, b, c (0 when degenerate).
double smallest_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 p[3] = {a, b, c};
  double smallest = M_PI;
  for (int k = 0; k < 3; ++k) {
    const Vec3 u = p[(k + 1) % 3] - p[k], v = p[(k + 2) % 3] - p[k];
    if (!(u.norm() > 0) || !(v.norm() > 0)) return 0;
    smallest = std::min(smallest, std::atan2(u.cross(v).norm(), u.dot(v)));
  }
  return smallest;
}

/// True when the segment q_i q_j (i, j not neighbours) runs inside the simple polygon q: it
/// crosses no side and its midpoint is inside.
bool diagonal_inside(const std::vector<Eigen::Vector2d>& q, int i, int j) {
  const int n = static_cast<int>(q.size());
  for (int k = 0; k < n; ++k) {
    const int l = (k + 1) % n;
    if (k == i || k == j || l == i || l == j) continue;
    const double o1 = orient_2d(q[i], q[j], q[k]), o2 = orient_2d(q[i], q[j], q[l]);
    const double o3 = orient_2d(q[k], q[l], q[i]), o4 = orient_2d(q[k], q[l], q[j]);
    if ((o1 >= 0) != (o2 >= 0) && (o3 >= 0) != (o4 >= 0)) return false;
    if (o1 == 0 || o2 == 0) return false;  // through a corner
  }
  const Eigen::Vector2d m = 0.5 * (q[i] + q[j]);
  bool inside = false;  // even-odd rule
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d& a = q[k];
    const Eigen::Vector2d& b = q[(k + 1) % n];
    if ((a.y() > m.y()) != (b.y() > m.y()) &&
        m.x() < a.x() + (m.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
      inside = !inside;
  }
  return inside;
}

}  // namespace

}  // namespace gridshell::flat_detail

namespace gridshell {

std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<Vec3>& p, double min_side) {
  using flat_detail::diagonal_inside;
  using flat_detail::smallest_angle;
  const int n = static_cast<int>(p.size());
  if (n < 3) return {};
  // Seen along the best-fit plane's normal, as panel_shape judges whether a panel is simple.
  // A panel folded over itself as seen (a sliver of the design at a steep boundary) is
  // triangulated in space: its triangles turn the way its vector area does.
  const FaceFrame frame = face_frame(p);
  const std::vector<Eigen::Vector2d> q = flat_detail::in_plane(p, frame.normal);
  const bool simple = flat_detail::simple_2d(q);
  const double sign = signed_area_2d(q) > 0 ? 1 : -1;
  const auto turns_right = [&](int i, int m, int j) {
    if (simple) return sign * orient_2d(q[i], q[m], q[j]) > 0;
    return (p[m] - p[i]).cross(p[j] - p[i]).dot(frame.normal) > 0;
  };
  // usable(i, j): a side, or a diagonal no shorter than `min_side` (inside the polygon as seen).
  std::vector<char> usable(static_cast<std::size_t>(n) * n, 0);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const bool side = j == i + 1 || (i == 0 && j == n - 1);
      usable[i * n + j] =
          side || ((p[i] - p[j]).norm() >= min_side && (!simple || diagonal_inside(q, i, j)));
    }
  // best[i][j]: the largest smallest angle of a triangulation of corners i … j (Klincsek's
  // dynamic programme over sub-polygons), −1 when there is none; split[i][j] the apex taken.
  std::vector<double> best(static_cast<std::size_t>(n) * n, -1);
  std::vector<int> split(static_cast<std::size_t>(n) * n, -1);
  for (int i = 0; i + 1 < n; ++i) best[i * n + i + 1] = M_PI;
  for (int len = 2; len < n; ++len)
    for (int i = 0; i + len < n; ++i) {
      const int j = i + len;
      if (!usable[i * n + j]) continue;
      for (int m = i + 1; m < j; ++m) {
        if (best[i * n + m] < 0 || best[m * n + j] < 0) continue;
        if (!turns_right(i, m, j)) continue;
        const double v =
            std::min({best[i * n + m], best[m * n + j], smallest_angle(p[i], p[m], p[j])});
        if (v > best[i * n + j]) {
          best[i * n + j] = v;
          split[i * n + j] = m;
        }
      }
    }
  if (!(best[n - 1] > 0)) return {};
  std::vector<std::array<int, 3>> out;
  std::vector<std::pair<int, int>> todo{{0, n - 1}};
  while (!todo.empty()) {
    const auto [i, j] = todo.back();
    todo.pop_back();
    if (j - i < 2) continue;
    const int m = split[i * n + j];
    out.push_back({i, m, j});
    todo.emplace_back(i, m);
    todo.emplace_back(m, j);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace gridshell

namespace gridshell::flat_detail {

namespace {

/// The grid-shell with the dropped panels glazed as their triangles: a dropped panel's first
/// triangle keeps its id, the others follow all panels.
SplitPanels glazed(const Layout& L, const Planes& pl, const std::vector<Vec3>& x,
                   const std::vector<char>& dropped,
                   const std::vector<std::vector<std::array<int, 3>>>& triangles) {
  SplitPanels out;
  out.x = x;
  const int nf = static_cast<int>(L.faces.size());
  const auto add = [&](int f, std::vector<int> face, const Vec3& n, double d) {
    out.faces.push_back(std::move(face));
    out.normal.push_back(n);
    out.offset.push_back(d);
    out.owner.push_back(f);
  };
  const auto triangle = [&](int f, const std::array<int, 3>& t) {
    const std::vector<int> tri{L.faces[f][t[0]], L.faces[f][t[1]], L.faces[f][t[2]]};
    const Vec3 n = (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]).normalized();
    add(f, tri, n, n.dot(x[tri[0]]));
  };
  for (int f = 0; f < nf; ++f) {
    if (!dropped[f]) {
      add(f, L.faces[f], pl.n[f], pl.d[f]);
    } else {
      ++out.split;
      triangle(f, triangles[f].front());
    }
  }
  for (int f = 0; f < nf; ++f)
    if (dropped[f])
      for (std::size_t k = 1; k < triangles[f].size(); ++k) triangle(f, triangles[f][k]);
  return out;
}

PolyMesh mesh_of(const std::vector<Vec3>& x, const std::vector<std::vector<int>>& faces) {
  PolyMesh m;
  m.V = to_points(x);
  m.faces = faces;
  return m;
}

/// Two beams by their joints, order-free.
std::array<int, 4> edge_pair(std::array<int, 2> a, std::array<int, 2> b) {
  if (a[0] > a[1]) std::swap(a[0], a[1]);
  if (b[0] > b[1]) std::swap(b[0], b[1]);
  if (b < a) std::swap(a, b);
  return {a[0], a[1], b[0], b[1]};
}

/// The overlaps of the layout at its targets (the design's own), by joints and panels.
struct TargetOverlaps {
  std::set<std::array<int, 4>> crossing;
  std::set<std::pair<int, int>> covered;  ///< (joint, panel)
};
TargetOverlaps target_overlaps(const Layout& L, const std::vector<Vec3>& x0) {
  const PolyMesh m = mesh_of(x0, L.faces);
  const Topology topo = build_topology(m);
  const Overlaps o = find_overlaps(m, topo);
  TargetOverlaps t;
  for (const auto& [e1, e2] : o.crossing_edges)
    t.crossing.insert(edge_pair(topo.edges[e1], topo.edges[e2]));
  for (const auto& [v, g] : o.covered_vertices) t.covered.insert({v, g});
  return t;
}

}  // namespace

bool split_failing_panels(const Problem& P, const Planes& pl, const SurfaceProjector& projector,
                          double far_limit, int max_panels, SplitPanels& out) {
  const Layout& L = *P.L;
  const int nf = static_cast<int>(L.faces.size()), nj = static_cast<int>(L.joints.size());
  std::vector<std::vector<int>> faces_of(nj);
  for (int f = 0; f < nf; ++f)
    for (int j : L.faces[f]) faces_of[j].push_back(f);
  std::vector<char> dropped(nf, 0);
  std::vector<Vec3> x(nj);
  std::vector<std::vector<std::array<int, 3>>> triangles(nf);
  const TargetOverlaps own = target_overlaps(L, P.x0);
  for (int round = 0; round <= max_panels + 1; ++round) {
    // Every joint nearest its target on the planes of its panels that keep theirs.
    std::vector<char> ok(nj, 1), far(nj, 0);
    tbb::parallel_for(0, nj, [&](int j) {
      Vec3 n[3];
      double d[3];
      int k = 0;
      for (int s = 0; s < 3; ++s) {
        const int ref = L.joints[j].plane[s];
        if (ref >= 0 && dropped[ref]) continue;
        plane_of(P, pl, ref, n[k], d[k]);
        ++k;
      }
      ok[j] = nearest_on_planes(n, d, k, P.x0[j], P.o.min_det, x[j]) && x[j].allFinite();
      if (!ok[j]) x[j] = P.x0[j];
      far[j] = !(projector.distance(x[j]) <= far_limit);
    });
    // What fails: a joint (its panels), a short side (the panels on both sides), a kept panel
    // that self-intersects, a dropped one that has no triangulation (its neighbours).
    std::vector<char> bad(nf, 0);
    for (int j = 0; j < nj; ++j)
      if (!ok[j] || far[j])
        for (int f : faces_of[j]) bad[f] = 1;
    for (int f = 0; f < nf; ++f) {
      const auto& face = L.faces[f];
      std::vector<Vec3> p;
      for (std::size_t k = 0; k < face.size(); ++k) {
        const int a = face[k], b = face[(k + 1) % face.size()];
        p.push_back(x[a]);
        if ((x[a] - x[b]).norm() >= P.shortest_allowed) continue;
        for (int g : faces_of[a])
          if (std::find(L.faces[g].begin(), L.faces[g].end(), b) != L.faces[g].end()) bad[g] = 1;
      }
      if (!dropped[f]) {
        bad[f] |= !simple_2d(in_plane(p, pl.n[f]));
      } else {
        triangles[f] = triangulate_polygon(p, P.shortest_allowed);
        bad[f] |= triangles[f].empty();
      }
    }
    bool any = std::find(bad.begin(), bad.end(), 1) != bad.end();
    if (!any) {
      // Beams that cross or a joint inside a panel, other than the targets' own (the design's):
      // the panels involved.
      out = glazed(L, pl, x, dropped, triangles);
      const std::vector<int>& owner = out.owner;
      const PolyMesh m = mesh_of(x, out.faces);
      const Topology topo = build_topology(m);
      const Overlaps o = find_overlaps(m, topo);
      for (const auto& [e1, e2] : o.crossing_edges) {
        if (own.crossing.count(edge_pair(topo.edges[e1], topo.edges[e2]))) continue;
        for (int e : {e1, e2})
          for (int g : topo.edge_faces[e]) bad[owner[g]] = any = true;
      }
      for (const auto& [v, g] : o.covered_vertices) {
        if (own.covered.count({v, owner[g]})) continue;
        bad[owner[g]] = any = true;
        for (int f : faces_of[v]) bad[f] = 1;
      }
      if (!any) return true;
    }
    bool grew = false;
    for (int f = 0; f < nf; ++f) {
      if (!bad[f]) continue;
      if (!dropped[f]) {
        dropped[f] = grew = true;
      } else {
        for (int g : P.face_neighbours[f])
          if (!dropped[g]) dropped[g] = grew = true;
      }
    }
    const long n_dropped = std::count(dropped.begin(), dropped.end(), 1);
    if (!grew || n_dropped > max_panels) {
      spdlog::debug("[flat panels] triangulating the failing panels stops at round {}: {}", round,
                    grew ? fmt::format("{} panels would split (at most {})", n_dropped, max_panels)
                         : "nothing left to split");
      return false;
    }
  }
  return false;
}

}  // namespace gridshell::flat_detail
