#include "gridshell/grids/quad_aniso.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <deque>
#include <map>
#include <numbers>
#include <numeric>
#include <set>
#include <tuple>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>
#include <Eigen/Sparse>

#include "gridshell/core/error.h"
#include "gridshell/core/rng.h"
#include "gridshell/grids/supports.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/nearest.h"
#include "gridshell/mesh/overlaps.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/projector.h"

namespace gridshell {

namespace {

/// A unit vector perpendicular to n (deterministic).
Vec3 any_perpendicular(const Vec3& n) { return plane_axes(n).first; }

/// The one of ±q, ±n×q closest to `target`: q's cross brought to agree with target's.
Vec3 match_cross(const Vec3& q, const Vec3& n, const Vec3& target) {
  const Vec3 t = n.cross(q);
  const std::array<Vec3, 4> c = {q, t, Vec3(-q), Vec3(-t)};
  int best = 0;
  for (int k = 1; k < 4; ++k)
    if (c[k].dot(target) > c[best].dot(target)) best = k;
  return c[best];
}

/// The lattice point (origin o, axes q, t, spacing h) nearest p, or the one below-left of p.
Vec3 lattice_round(const Vec3& o, const Vec3& q, const Vec3& t, const Vec3& p, double h) {
  const Vec3 d = p - o;
  return o + q * (h * std::round(q.dot(d) / h)) + t * (h * std::round(t.dot(d) / h));
}
Vec3 lattice_floor(const Vec3& o, const Vec3& q, const Vec3& t, const Vec3& p, double h) {
  const Vec3 d = p - o;
  return o + q * (h * std::floor(q.dot(d) / h)) + t * (h * std::floor(t.dot(d) / h));
}

/// The two lattice points, one of each side's lattice, nearest each other near the middle of
/// the edge v0 v1 (the 4 corners of the cell around the middle compared on each side).
std::pair<Vec3, Vec3> compat_position(const Vec3& v0, const Vec3& q0, const Vec3& t0,
                                      const Vec3& o0, double h0, const Vec3& v1, const Vec3& q1,
                                      const Vec3& t1, const Vec3& o1, double h1) {
  const Vec3 m = 0.5 * (v0 + v1);
  const Vec3 a = lattice_floor(o0, q0, t0, m, h0), b = lattice_floor(o1, q1, t1, m, h1);
  std::array<Vec3, 4> as, bs;  // the 4 corners of the cell around m, on each side
  for (int i = 0; i < 4; ++i) {
    as[i] = a + h0 * ((i & 1) * q0 + (i >> 1) * t0);
    bs[i] = b + h1 * ((i & 1) * q1 + (i >> 1) * t1);
  }
  int best_i = 0, best_j = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const double d = (as[i] - bs[j]).squaredNorm();
      if (d < best_d) best_d = d, best_i = i, best_j = j;
    }
  return {as[best_i], bs[best_j]};
}

/// Per vertex of a triangle mesh (M′ or M): unit normal, area-weighted over its triangles.
std::vector<Vec3> vertex_normals(const TriMesh& m) {
  std::vector<Vec3> n(m.num_vertices(), Vec3::Zero());
  for (int f = 0; f < m.num_faces(); ++f) {
    const Vec3 a = m.vertex(m.F(f, 0)), b = m.vertex(m.F(f, 1)), c = m.vertex(m.F(f, 2));
    const Vec3 fn = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) n[m.F(f, k)] += fn;
  }
  for (Vec3& v : n) v = v.norm() > 0 ? Vec3(v.normalized()) : Vec3(Vec3::UnitZ());
  return n;
}

/// J_t u_t: the field direction of each face of `rest` carried onto `deformed` (unit), and the
/// area of the face in M′.
void pushed_directions(const TriMesh& rest, const TriMesh& def, const Field& field,
                       std::vector<Vec3>& w, std::vector<double>& area) {
  w.assign(rest.num_faces(), Vec3::Zero());
  area.assign(rest.num_faces(), 0);
  for (int f = 0; f < rest.num_faces(); ++f) {
    const Vec3 a = rest.vertex(rest.F(f, 0));
    const Vec3 e1 = rest.vertex(rest.F(f, 1)) - a, e2 = rest.vertex(rest.F(f, 2)) - a;
    const Vec3 a2 = def.vertex(def.F(f, 0));
    const Vec3 d1 = def.vertex(def.F(f, 1)) - a2, d2 = def.vertex(def.F(f, 2)) - a2;
    Eigen::Matrix2d G;
    G << e1.dot(e1), e1.dot(e2), e1.dot(e2), e2.dot(e2);
    const Eigen::Vector2d ab =
        G.ldlt().solve(Eigen::Vector2d(e1.dot(field.u[f]), e2.dot(field.u[f])));
    const Vec3 j = ab(0) * d1 + ab(1) * d2;
    area[f] = 0.5 * d1.cross(d2).norm();
    if (j.norm() > 0 && std::isfinite(j.norm())) w[f] = j.normalized();
  }
}

/// Two triangles sharing an edge are a quad cut by a diagonal (a lattice step taken across a
/// seam of the position field): the edge is removed, longest shared edges first.
void merge_triangle_pairs(std::vector<std::vector<int>>& faces, const std::vector<Vec3>& p) {
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    if (faces[f].size() != 3) continue;
    for (int k = 0; k < 3; ++k) {
      const int a = faces[f][k], b = faces[f][(k + 1) % 3];
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  }
  std::vector<std::pair<double, std::pair<int, int>>> shared;
  for (const auto& [e, fs] : edge_faces)
    if (fs.size() == 2) shared.push_back({-(p[e.first] - p[e.second]).norm(), e});
  std::sort(shared.begin(), shared.end());
  std::vector<char> merged(faces.size(), 0);
  for (const auto& [neg_length, e] : shared) {
    const int f = edge_faces[e][0], g = edge_faces[e][1];
    if (merged[f] || merged[g]) continue;
    int k = 0;
    while (!((faces[f][k] == e.first || faces[f][k] == e.second) &&
             (faces[f][(k + 1) % 3] == e.first || faces[f][(k + 1) % 3] == e.second)))
      ++k;
    const int a = faces[f][k], b = faces[f][(k + 1) % 3], c = faces[f][(k + 2) % 3];
    int d = -1;
    for (int v : faces[g])
      if (v != a && v != b) d = v;
    if (d == c) continue;
    faces[f] = {a, d, b, c};
    faces[g].clear();
    merged[f] = merged[g] = 1;
  }
  faces.erase(std::remove_if(faces.begin(), faces.end(),
                             [](const std::vector<int>& f) { return f.empty(); }),
              faces.end());
}

/// A triangle left among quads is a lattice defect with two joints of valence ≥ 5 on one of its
/// edges: that edge (the longest such one with a quad on its other side) is removed, leaving a
/// pentagon and two joints of valence 4 (the share of quads is unchanged but for one face).
void absorb_lone_triangles(std::vector<std::vector<int>>& faces, const std::vector<Vec3>& p) {
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  std::map<int, int> degree;
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    const int n = static_cast<int>(faces[f].size());
    for (int k = 0; k < n; ++k) {
      const int a = faces[f][k], b = faces[f][(k + 1) % n];
      auto& fs = edge_faces[{std::min(a, b), std::max(a, b)}];
      if (fs.empty()) ++degree[a], ++degree[b];
      fs.push_back(f);
    }
  }
  std::vector<char> changed(faces.size(), 0);
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    if (faces[f].size() != 3 || changed[f]) continue;
    int best_k = -1, best_g = -1;
    double best_length = 0;
    for (int k = 0; k < 3; ++k) {
      const int a = faces[f][k], b = faces[f][(k + 1) % 3];
      const auto& fs = edge_faces[{std::min(a, b), std::max(a, b)}];
      if (fs.size() != 2 || degree[a] < 5 || degree[b] < 5) continue;
      const int g = fs[0] == f ? fs[1] : fs[0];
      if (faces[g].size() != 4 || changed[g]) continue;
      const double length = (p[a] - p[b]).norm();
      if (length > best_length) best_length = length, best_k = k, best_g = g;
    }
    if (best_k < 0) continue;
    const int a = faces[f][best_k], b = faces[f][(best_k + 1) % 3], c = faces[f][(best_k + 2) % 3];
    // The quad walks b → a; splice c in between.
    std::vector<int>& q = faces[best_g];
    int j = 0;
    while (!(q[j] == b && q[(j + 1) % 4] == a)) ++j;
    std::vector<int> pent;
    for (int i = 0; i < 4; ++i) {
      pent.push_back(q[(j + 1 + i) % 4]);  // a, …, b
    }
    pent.push_back(c);
    q = pent;
    faces[f].clear();
    changed[f] = changed[best_g] = 1;
    --degree[a], --degree[b];
  }
  faces.erase(std::remove_if(faces.begin(), faces.end(),
                             [](const std::vector<int>& f) { return f.empty(); }),
              faces.end());
}

/// Badness of the quad (a, b, c, d) on M′ about the normal n: Σ cos² of its corner angles (0 for
/// a rectangle); infinite when a corner is not convex (turns the wrong way about n).
double quad_badness(const std::array<Vec3, 4>& p, const Vec3& n) {
  double bad = 0;
  for (int k = 0; k < 4; ++k) {
    const Vec3 e0 = p[k] - p[(k + 3) % 4], e1 = p[(k + 1) % 4] - p[k];
    if (e0.cross(e1).dot(n) <= 0) return std::numeric_limits<double>::infinity();
    const double c = e0.dot(e1) / (e0.norm() * e1.norm());
    bad += c * c;
  }
  return bad;
}

/// The best split of the polygon `poly` (an even number of corners, counter-clockwise about n)
/// into quads by diagonals (i, i + 3): the lowest Σ badness + `valence_weight` × Σ over the
/// diagonals' ends of the change in |valence − 4| + Σ over the diagonals of (length / h − 1)²
/// (a new beam should be one lattice step long, not a cell's diagonal). Diagonals that are beams
/// already are not used. Returns the cost (infinite when there is no admissible split) and fills
/// `quads`.
double best_quad_split(const std::vector<int>& poly, const std::vector<Vec3>& p, const Vec3& n,
                       std::map<int, int>& degree, const std::set<std::pair<int, int>>& beams,
                       double valence_weight, double h, std::vector<std::array<int, 4>>& quads) {
  const int m = static_cast<int>(poly.size());
  if (m == 4) {
    quads = {{poly[0], poly[1], poly[2], poly[3]}};
    return quad_badness({p[poly[0]], p[poly[1]], p[poly[2]], p[poly[3]]}, n);
  }
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < m; ++i) {
    const int a = poly[i], b = poly[(i + 1) % m], c = poly[(i + 2) % m], d = poly[(i + 3) % m];
    if (beams.count({std::min(a, d), std::max(a, d)})) continue;
    const double q = quad_badness({p[a], p[b], p[c], p[d]}, n);
    if (!std::isfinite(q) || q >= best) continue;
    auto change = [&](int v) { return std::abs(degree[v] + 1 - 4) - std::abs(degree[v] - 4); };
    const double stretch = (p[a] - p[d]).norm() / h - 1;
    const double val = valence_weight * (change(a) + change(d)) + stretch * stretch;
    ++degree[a], ++degree[d];
    std::vector<int> rest;
    for (int k = 0; k < m; ++k)
      if (k != (i + 1) % m && k != (i + 2) % m) rest.push_back(poly[k]);
    std::vector<std::array<int, 4>> sub;
    const double r = best_quad_split(rest, p, n, degree, beams, valence_weight, h, sub);
    --degree[a], --degree[d];
    if (q + val + r < best) {
      best = q + val + r;
      quads = {{a, b, c, d}};
      quads.insert(quads.end(), sub.begin(), sub.end());
    }
  }
  return best;
}

/// `poly` joined with `face` across their common beam e (poly walks it one way, face the other):
/// the boundary of the union, or empty when e is not on both or a joint would appear twice.
std::vector<int> join_across(const std::vector<int>& poly, const std::vector<int>& face,
                             const std::pair<int, int>& e) {
  const int m = static_cast<int>(poly.size()), mg = static_cast<int>(face.size());
  int i = 0;
  while (i < m && !((poly[i] == e.first && poly[(i + 1) % m] == e.second) ||
                    (poly[i] == e.second && poly[(i + 1) % m] == e.first)))
    ++i;
  if (i == m) return {};
  const int a = poly[i], b = poly[(i + 1) % m];
  std::vector<int> out;
  for (int k = 0; k < m; ++k) out.push_back(poly[(i + 1 + k) % m]);  // b … a
  int j = 0;
  while (j < mg && face[j] != a) ++j;
  if (j == mg || face[(j + mg - 1) % mg] != b) return {};              // face does not walk b → a
  for (int k = 1; k + 1 < mg; ++k) out.push_back(face[(j + k) % mg]);  // after a … before b
  std::vector<int> sorted = out;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return {};
  return out;
}

/// Quad-dominant clean-up on M′. Where the position field has a seam (a row of cells that starts
/// or ends, a half-step shift between two lattices) the extraction leaves faces of an odd number
/// of sides: two triangles (a quad cut by its diagonal), a triangle and a pentagon (a
/// T-junction), a wedge-shaped triangle where a row of cells begins. Two odd faces joined by a
/// path of at most `max_quads_between` quads (sharing one beam each step) make a polygon of an
/// even number of sides (≤ 10); it is re-split into quads by diagonals chosen for the squarest
/// quads and valences nearest 4 (faces of 6 or 8 sides alone likewise). Cheapest first, each
/// face used once; a split whose quads are far from square (badness > 4 × 0.4² per quad: a
/// corner outside about 50°–130°) is not made.
///
/// `h` is the length a new beam should have; h = 0 takes each polygon's mean side instead (on M,
/// where cells vary in size and shape). With `on_rim` (one flag per face) non-empty, only pairs
/// with a face on the rim are made (and faces of 6 or 8 sides on the rim alone).
void pair_odd_faces(std::vector<std::vector<int>>& faces, const std::vector<Vec3>& p,
                    const std::vector<Vec3>& normal, double h, int max_quads_between = 2,
                    const std::vector<char>& on_rim = {}) {
  const int nf = static_cast<int>(faces.size());
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  std::map<int, int> degree;
  std::set<std::pair<int, int>> beams;
  for (int f = 0; f < nf; ++f) {
    const int m = static_cast<int>(faces[f].size());
    for (int k = 0; k < m; ++k) {
      const int a = faces[f][k], b = faces[f][(k + 1) % m];
      const std::pair<int, int> e{std::min(a, b), std::max(a, b)};
      if (beams.insert(e).second) ++degree[a], ++degree[b];
      edge_faces[e].push_back(f);
    }
  }
  // Face adjacency through interior beams: (neighbour, shared beam).
  std::vector<std::vector<std::pair<int, std::pair<int, int>>>> adjacent(nf);
  for (const auto& [e, fs] : edge_faces)
    if (fs.size() == 2 && fs[0] != fs[1]) {
      adjacent[fs[0]].push_back({fs[1], e});
      adjacent[fs[1]].push_back({fs[0], e});
    }
  const double max_badness = 4 * 0.4 * 0.4;
  constexpr double kValenceWeight = 0.3;
  constexpr int kMaxSides = 10;
  struct Candidate {
    double cost;
    std::vector<int> faces;
    std::vector<std::array<int, 4>> quads;
  };
  std::vector<Candidate> cands;
  auto face_normal = [&](const std::vector<int>& poly) {
    Vec3 s = Vec3::Zero();
    for (int v : poly) s += normal[v];
    return Vec3(s.normalized());
  };
  // Evaluates the union `poly` of `path` (whose interior beams `removed` are taken out).
  auto consider = [&](const std::vector<int>& poly, const std::vector<int>& path,
                      const std::vector<std::pair<int, int>>& removed) {
    for (const auto& e : removed) --degree[e.first], --degree[e.second], beams.erase(e);
    std::vector<std::array<int, 4>> quads;
    double step = h;
    if (!(step > 0)) {
      step = 0;
      for (size_t k = 0; k < poly.size(); ++k)
        step += (p[poly[k]] - p[poly[(k + 1) % poly.size()]]).norm() / poly.size();
    }
    const double c =
        best_quad_split(poly, p, face_normal(poly), degree, beams, kValenceWeight, step, quads);
    for (const auto& e : removed) ++degree[e.first], ++degree[e.second], beams.insert(e);
    const int nq = static_cast<int>(poly.size() - 2) / 2;
    if (c <= max_badness * nq) cands.push_back({c / nq, path, quads});
  };
  for (int f = 0; f < nf; ++f) {
    const int m = static_cast<int>(faces[f].size());
    const bool rim = on_rim.empty() || on_rim[f];
    if ((m == 6 || m == 8) && rim) consider(faces[f], {f}, {});
    if (m % 2 == 0) continue;
    // Depth-first over paths f, quad, …, quad, g with g odd (g > f: each pair once).
    struct State {
      std::vector<int> path, poly;
      std::vector<std::pair<int, int>> removed;
    };
    std::vector<State> stack{{{f}, faces[f], {}}};
    while (!stack.empty()) {
      const State s = stack.back();
      stack.pop_back();
      for (const auto& [g, e] : adjacent[s.path.back()]) {
        if (std::find(s.path.begin(), s.path.end(), g) != s.path.end()) continue;
        const int mg = static_cast<int>(faces[g].size());
        if (mg % 2 == 0 && mg != 4) continue;
        if (static_cast<int>(s.poly.size()) + mg - 2 > kMaxSides) continue;
        State t{s.path, join_across(s.poly, faces[g], e), s.removed};
        if (t.poly.empty()) continue;
        t.path.push_back(g);
        t.removed.push_back(e);
        if (mg % 2 == 1) {
          if (g > f && (rim || on_rim[g])) consider(t.poly, t.path, t.removed);
        } else if (static_cast<int>(t.path.size()) <= max_quads_between) {
          stack.push_back(std::move(t));
        }
      }
    }
  }
  std::stable_sort(cands.begin(), cands.end(),
                   [](const Candidate& x, const Candidate& y) { return x.cost < y.cost; });
  std::vector<char> used(nf, 0);
  std::vector<std::vector<int>> added;
  for (const Candidate& c : cands) {
    bool free = true;
    for (int f : c.faces) free = free && !used[f];
    if (!free) continue;
    // A diagonal chosen by an earlier candidate may coincide with one of this candidate's.
    bool clash = false;
    for (const auto& q : c.quads)
      for (int k = 0; k < 4; ++k) {
        const int u = q[k], v = q[(k + 1) % 4];
        const std::pair<int, int> e{std::min(u, v), std::max(u, v)};
        if (!edge_faces.count(e) && beams.count(e)) clash = true;
      }
    if (clash) continue;
    for (int f : c.faces) used[f] = 1;
    for (const auto& q : c.quads) {
      added.push_back({q[0], q[1], q[2], q[3]});
      for (int k = 0; k < 4; ++k) {
        const int u = q[k], v = q[(k + 1) % 4];
        beams.insert({std::min(u, v), std::max(u, v)});
      }
    }
  }
  std::vector<std::vector<int>> out;
  for (int f = 0; f < nf; ++f)
    if (!used[f]) out.push_back(std::move(faces[f]));
  for (auto& q : added) out.push_back(std::move(q));
  faces = std::move(out);
}

}  // namespace

namespace {

/// A cross field on M′'s vertices: normal n, the cross's first arm q and t = n × q.
struct CrossField {
  std::vector<Vec3> n, q, t;
};

/// One level of the multiresolution hierarchy on M′ (level 0: M′'s vertices; each coarser level
/// pairs neighbouring vertices of the finer one, as Jakob et al. 2015 do): position, normal,
/// area, neighbours, and per vertex its parent on the next coarser level.
struct Level {
  std::vector<Vec3> p, n;
  std::vector<double> area;
  std::vector<std::vector<int>> nbr;
  std::vector<int> parent;
  int size() const { return static_cast<int>(p.size()); }
};

/// Levels from M′ down to ≤ `coarsest` vertices (or until pairing stops shrinking the level):
/// neighbours are paired greedily, most similar first (normals alike, areas alike); a vertex left
/// without a partner goes up alone. Deterministic (ties broken by vertex ids).
std::vector<Level> build_hierarchy(const TriMesh& def, const Topology& topo, int coarsest) {
  std::vector<Level> levels(1);
  {
    Level& l = levels[0];
    const int nv = def.num_vertices();
    l.p.resize(nv);
    for (int v = 0; v < nv; ++v) l.p[v] = def.vertex(v);
    l.n = vertex_normals(def);
    l.area.assign(nv, 0);
    for (int f = 0; f < def.num_faces(); ++f) {
      const double a =
          triangle_area(def.vertex(def.F(f, 0)), def.vertex(def.F(f, 1)), def.vertex(def.F(f, 2)));
      for (int k = 0; k < 3; ++k) l.area[def.F(f, k)] += a / 3;
    }
    for (double& a : l.area) a = std::max(a, 1e-300);
    l.nbr = topo.vertex_neighbors;
  }
  while (coarsest > 0 && levels.back().size() > coarsest && levels.size() < 40) {
    const Level& f = levels.back();
    const int nv = f.size();
    std::vector<std::tuple<double, int, int>> pairs;
    for (int i = 0; i < nv; ++i)
      for (int j : f.nbr[i])
        if (i < j)
          pairs.emplace_back(
              -f.n[i].dot(f.n[j]) * std::min(f.area[i] / f.area[j], f.area[j] / f.area[i]), i, j);
    std::sort(pairs.begin(), pairs.end());
    std::vector<int> parent(nv, -1);
    int count = 0;
    for (const auto& [score, i, j] : pairs)
      if (parent[i] < 0 && parent[j] < 0) parent[i] = parent[j] = count++;
    for (int v = 0; v < nv; ++v)
      if (parent[v] < 0) parent[v] = count++;
    if (count > 0.95 * nv) break;  // nothing left to pair (e.g. isolated vertices)
    Level c;
    c.p.assign(count, Vec3::Zero());
    c.n.assign(count, Vec3::Zero());
    c.area.assign(count, 0);
    c.nbr.resize(count);
    std::vector<std::set<int>> nbr(count);
    for (int v = 0; v < nv; ++v) {
      const int P = parent[v];
      c.p[P] += f.area[v] * f.p[v];
      c.n[P] += f.area[v] * f.n[v];
      c.area[P] += f.area[v];
      for (int j : f.nbr[v])
        if (parent[j] != P) nbr[P].insert(parent[j]);
    }
    for (int P = 0; P < count; ++P) {
      c.p[P] /= c.area[P];
      c.n[P] = c.n[P].norm() > 0 ? Vec3(c.n[P].normalized()) : Vec3(Vec3::UnitZ());
      c.nbr[P].assign(nbr[P].begin(), nbr[P].end());
    }
    levels.back().parent = std::move(parent);
    levels.push_back(std::move(c));
  }
  return levels;
}

/// Gauss–Seidel sweeps of the cross field on one level, with the data term q_data weighted by
/// λ × the vertex's neighbour count.
void smooth_cross(const Level& l, const std::vector<Vec3>& q_data,
                  const std::vector<double>& lambda, std::vector<Vec3>& q, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    for (int v = 0; v < l.size(); ++v) {
      const auto& nb = l.nbr[v];
      Vec3 sum = lambda[v] * static_cast<double>(nb.size()) * match_cross(q_data[v], l.n[v], q[v]);
      for (int j : nb) sum += match_cross(q[j], l.n[j], q[v]);
      sum -= l.n[v] * l.n[v].dot(sum);
      if (sum.norm() > 1e-12) q[v] = sum.normalized();
    }
  }
}

/// `x` in the tangent plane of normal n, unit; any perpendicular of n when x is along n.
Vec3 tangent_unit(const Vec3& x, const Vec3& n) {
  const Vec3 y = x - n * n.dot(x);
  return y.norm() > 1e-12 ? Vec3(y.normalized()) : any_perpendicular(n);
}

/// Per face, how much the field's direction counts in the cross field's data (0 … 1): where the
/// metric is isotropic (a = 1) any cross gives square cells, so u there is no constraint; the
/// weight grows linearly with a − 1 up to 1 at a = min(a_full, the field's largest a). A field
/// without anisotropy (A = 1) keeps weight 1 everywhere: its directions are then the only ones
/// there are (the isotropic, stress-aligned baseline). a_full ≤ 1: weight 1 everywhere.
std::vector<double> direction_strength(const Field& field, double a_full) {
  const int nf = static_cast<int>(field.a.size());
  const double a_max = nf > 0 ? *std::max_element(field.a.begin(), field.a.end()) : 1;
  const double a_top = std::min(a_full, a_max);
  std::vector<double> strength(nf, 1.0);
  if (a_full <= 1 || a_top <= 1 + 1e-9) return strength;
  for (int f = 0; f < nf; ++f) strength[f] = std::clamp((field.a[f] - 1) / (a_top - 1), 0.0, 1.0);
  return strength;
}

/// Step 1: the 4-fold average of J u per vertex of M′ (each triangle weighted by its area and
/// direction_strength: the data), carried down the hierarchy
/// (area × coherence weighted), solved on the coarsest level and refined level by level with the
/// data term on each: where the stress field has a clear direction the data holds, where it
/// cancels (a singularity of the stress directions) the coarse levels fill in a smooth cross.
/// Returns the cross field of every level.
std::vector<CrossField> cross_field(const TriMesh& rest, const TriMesh& def, const Field& field,
                                    const Topology& topo, const std::vector<Level>& levels,
                                    double h, const QuadAnisoOptions& o) {
  const int nv = def.num_vertices();
  const std::vector<Vec3>& n = levels[0].n;
  std::vector<Vec3> w;
  std::vector<double> warea;
  pushed_directions(rest, def, field, w, warea);
  const int nl = static_cast<int>(levels.size());
  std::vector<std::vector<Vec3>> q_data(nl);
  std::vector<std::vector<double>> lambda(nl);
  q_data[0].resize(nv);
  lambda[0].assign(nv, 0);
  const std::vector<double> strength = direction_strength(field, o.full_alignment_anisotropy);
  for (int v = 0; v < nv; ++v) {
    const Vec3 r = any_perpendicular(n[v]), s = n[v].cross(r);
    std::complex<double> z = 0;
    double total = 0;
    for (int f : topo.vertex_faces[v]) {
      const double theta = std::atan2(w[f].dot(s), w[f].dot(r));
      z += strength[f] * warea[f] * std::polar(1.0, 4 * theta);
      total += warea[f];
    }
    const double phi = std::abs(z) > 0 ? std::arg(z) / 4 : 0;
    q_data[0][v] = std::cos(phi) * r + std::sin(phi) * s;
    // Data weight per neighbour for a smoothing length ℓ = direction_smoothing × h: on a mesh of
    // edge e the balance of the two terms is ℓ ≈ e / (2 √weight), so weight = (e / 2ℓ)².
    double edge = 0;
    for (int j : levels[0].nbr[v]) edge += (levels[0].p[j] - levels[0].p[v]).norm();
    edge /= std::max<size_t>(1, levels[0].nbr[v].size());
    const double per_neighbour = std::pow(edge / (2 * o.direction_smoothing * h), 2);
    lambda[0][v] = total > 0 ? per_neighbour * std::abs(z) / total : 0;
  }
  for (int k = 0; k + 1 < nl; ++k) {  // restriction: weighted sums of the crosses matched
    const Level &f = levels[k], &c = levels[k + 1];
    std::vector<Vec3> sum(c.size(), Vec3::Zero()), ref(c.size(), Vec3::Zero());
    std::vector<double> weight(c.size(), 0);
    for (int v = 0; v < f.size(); ++v) {
      const int P = f.parent[v];
      const double wv = f.area[v] * lambda[k][v];
      if (ref[P].squaredNorm() == 0) ref[P] = q_data[k][v];
      sum[P] += wv * match_cross(q_data[k][v], f.n[v], ref[P]);
      weight[P] += f.area[v];
    }
    q_data[k + 1].resize(c.size());
    lambda[k + 1].resize(c.size());
    for (int P = 0; P < c.size(); ++P) {
      q_data[k + 1][P] = tangent_unit(sum[P], c.n[P]);
      lambda[k + 1][P] = sum[P].norm() / weight[P];
    }
  }
  std::vector<CrossField> cf(nl);
  for (int k = nl - 1; k >= 0; --k) {
    const Level& l = levels[k];
    std::vector<Vec3> q(l.size());
    if (k == nl - 1)
      q = q_data[k];
    else
      for (int v = 0; v < l.size(); ++v) q[v] = tangent_unit(cf[k + 1].q[l.parent[v]], l.n[v]);
    smooth_cross(l, q_data[k], lambda[k], q, o.orientation_iterations);
    cf[k].n = l.n;
    cf[k].t.resize(l.size());
    for (int v = 0; v < l.size(); ++v) cf[k].t[v] = l.n[v].cross(q[v]);
    cf[k].q = std::move(q);
  }
  return cf;
}

/// Per vertex of a level, per neighbour (in `nbr` order, flattened from `offset[v]`): the
/// neighbour's cross arms matched to the vertex's. The cross field does not change while the
/// position field is smoothed, so this is computed once per level and M′.
struct MatchedFrames {
  std::vector<int> offset;
  std::vector<Vec3> q, t;
};

MatchedFrames matched_frames(const Level& l, const CrossField& cf) {
  MatchedFrames m;
  m.offset.assign(l.size() + 1, 0);
  for (int i = 0; i < l.size(); ++i)
    m.offset[i + 1] = m.offset[i] + static_cast<int>(l.nbr[i].size());
  m.q.resize(m.offset.back());
  m.t.resize(m.offset.back());
  for (int i = 0; i < l.size(); ++i)
    for (size_t k = 0; k < l.nbr[i].size(); ++k) {
      const int j = l.nbr[i][k];
      const Vec3 qj = match_cross(cf.q[j], cf.n[j], cf.q[i]);
      m.q[m.offset[i] + k] = qj;
      m.t[m.offset[i] + k] = cf.n[j].cross(qj);
    }
  return m;
}

/// Gauss–Seidel sweeps of the position field on one level: each vertex's lattice origin is the
/// average of its neighbours' lattices compared at the edges' middles, rounded back to the
/// lattice point nearest the vertex.
void smooth_position(const Level& l, const CrossField& cf, const MatchedFrames& mf,
                     const std::vector<double>& hs, std::vector<Vec3>& org, int iterations) {
  const std::vector<Vec3>&n = cf.n, &q = cf.q, &t = cf.t, &pos = l.p;
  for (int it = 0; it < iterations; ++it) {
    for (int i = 0; i < l.size(); ++i) {
      Vec3 sum = org[i];
      double weight = 0;
      const int k0 = mf.offset[i];
      for (size_t k = 0; k < l.nbr[i].size(); ++k) {
        const int j = l.nbr[i][k];
        const auto [a, b] = compat_position(pos[i], q[i], t[i], sum, hs[i], pos[j], mf.q[k0 + k],
                                            mf.t[k0 + k], org[j], hs[j]);
        sum = (a * weight + b) / (weight + 1);
        weight += 1;
        sum -= n[i] * n[i].dot(sum - pos[i]);
      }
      org[i] = lattice_round(sum, q[i], t[i], pos[i], hs[i]);
    }
  }
}

/// Step 2: the position field (a lattice origin per vertex): on the coarsest level one lattice
/// propagated breadth-first from a seeded random origin, then smoothing; each finer level starts
/// from its parents' origins (brought into its tangent plane, rounded) and is smoothed again.
/// Returns level 0's origins.
std::vector<Vec3> position_field(const std::vector<Level>& levels,
                                 const std::vector<CrossField>& cfs,
                                 const std::vector<MatchedFrames>& matched,
                                 const std::vector<std::vector<double>>& scale, double h,
                                 const QuadAnisoOptions& o) {
  const int nl = static_cast<int>(levels.size());
  std::vector<Vec3> org;
  for (int k = nl - 1; k >= 0; --k) {
    const Level& l = levels[k];
    const std::vector<Vec3>&n = cfs[k].n, &q = cfs[k].q, &t = cfs[k].t, &pos = l.p;
    std::vector<double> hs(l.size());
    for (int v = 0; v < l.size(); ++v) hs[v] = h * scale[k][v];
    std::vector<Vec3> next(l.size());
    if (k == nl - 1) {
      std::vector<char> seen(l.size(), 0);
      Rng rng(o.seed);
      for (int root = 0; root < l.size(); ++root) {
        if (seen[root]) continue;
        next[root] = pos[root] + hs[root] * (rng.uniform(-0.5, 0.5) * q[root] +
                                             rng.uniform(-0.5, 0.5) * t[root]);
        seen[root] = 1;
        std::deque<int> queue{root};
        while (!queue.empty()) {
          const int i = queue.front();
          queue.pop_front();
          for (int j : l.nbr[i]) {
            if (seen[j]) continue;
            seen[j] = 1;
            const Vec3 oj = next[i] - n[j] * n[j].dot(next[i] - pos[j]);
            next[j] = lattice_round(oj, q[j], t[j], pos[j], hs[j]);
            queue.push_back(j);
          }
        }
      }
    } else {
      for (int v = 0; v < l.size(); ++v) {
        const Vec3& op = org[l.parent[v]];
        next[v] = lattice_round(op - n[v] * n[v].dot(op - pos[v]), q[v], t[v], pos[v], hs[v]);
      }
    }
    org = std::move(next);
    smooth_position(l, cfs[k], matched[k], hs, org,
                    k == 0 ? o.position_iterations : o.coarse_position_iterations);
  }
  return org;
}

/// The joints: vertices of M′ collapsed to their lattice points (cluster per vertex, mean
/// position and normal, vertex count), and the edges of M′ that cross one lattice step.
struct LatticeJoints {
  int count = 0;
  std::vector<int> cluster;
  std::vector<Vec3> pos, normal;
  std::vector<int> vertices;
  std::vector<std::array<int, 2>> steps;
};

/// Step 3a: edges within one lattice point are collapsed, edges across one lattice step kept;
/// then joints closer than 0.3 h are merged once more (one lattice point split in two where the
/// lattices of a seam disagree slightly).
LatticeJoints collapse_to_joints(const std::vector<Vec3>& pos, const Topology& topo,
                                 const CrossField& cf, const std::vector<Vec3>& org,
                                 const std::vector<double>& scale, double h) {
  const int nv = static_cast<int>(pos.size());
  const std::vector<Vec3>&n = cf.n, &q = cf.q, &t = cf.t;
  DisjointSets sets(nv);
  LatticeJoints J;
  for (const auto& e : topo.edges) {
    const int i = e[0], j = e[1];
    const Vec3 qj = match_cross(q[j], n[j], q[i]), tj = n[j].cross(qj);
    const double hi = h * scale[i], hj = h * scale[j];
    const auto [a, b] = compat_position(pos[i], q[i], t[i], org[i], hi, pos[j], qj, tj, org[j], hj);
    if ((a - b).norm() > 0.25 * (hi + hj)) continue;  // the two lattices disagree here
    const int di0 = static_cast<int>(std::lround((a - org[i]).dot(q[i]) / hi));
    const int di1 = static_cast<int>(std::lround((a - org[i]).dot(t[i]) / hi));
    const int dj0 = static_cast<int>(std::lround((b - org[j]).dot(qj) / hj));
    const int dj1 = static_cast<int>(std::lround((b - org[j]).dot(tj) / hj));
    const int d0 = di0 - dj0, d1 = di1 - dj1;
    if (d0 == 0 && d1 == 0)
      sets.unite(i, j);
    else if (std::abs(d0) + std::abs(d1) == 1)
      J.steps.push_back({i, j});
  }
  J.cluster.assign(nv, -1);
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1)
      for (const auto& s : J.steps)
        if ((J.pos[J.cluster[s[0]]] - J.pos[J.cluster[s[1]]]).norm() < 0.3 * h)
          sets.unite(s[0], s[1]);
    std::fill(J.cluster.begin(), J.cluster.end(), -1);
    int& nc = J.count;
    nc = 0;
    for (int v = 0; v < nv; ++v) {
      const int r = sets.find(v);
      if (J.cluster[r] < 0) J.cluster[r] = nc++;
      J.cluster[v] = J.cluster[r];
    }
    J.pos.assign(nc, Vec3::Zero());
    J.normal.assign(nc, Vec3::Zero());
    J.vertices.assign(nc, 0);
    for (int v = 0; v < nv; ++v) {
      J.pos[J.cluster[v]] += org[v];
      J.normal[J.cluster[v]] += n[v];
      ++J.vertices[J.cluster[v]];
    }
    for (int c = 0; c < nc; ++c) {
      J.pos[c] /= J.vertices[c];
      J.normal[c] = J.normal[c].norm() > 0 ? Vec3(J.normal[c].normalized()) : Vec3(Vec3::UnitZ());
    }
  }
  return J;
}

/// Step 3b: each joint's beams (dangling ones pruned), ordered counter-clockwise about its
/// normal, starting from the cross's axis q at the joint's first vertex.
std::vector<std::vector<int>> joint_rings(const LatticeJoints& J, const CrossField& cf) {
  const int nc = J.count;
  std::vector<int> first(nc, -1);
  for (int v = 0; v < static_cast<int>(J.cluster.size()); ++v)
    if (first[J.cluster[v]] < 0) first[J.cluster[v]] = v;
  std::vector<std::set<int>> adj(nc);
  for (const auto& s : J.steps) {
    const int a = J.cluster[s[0]], b = J.cluster[s[1]];
    if (a != b) adj[a].insert(b), adj[b].insert(a);
  }
  std::deque<int> prune;
  for (int c = 0; c < nc; ++c)
    if (adj[c].size() == 1) prune.push_back(c);
  while (!prune.empty()) {
    const int c = prune.front();
    prune.pop_front();
    if (adj[c].size() != 1) continue;
    const int other = *adj[c].begin();
    adj[c].clear();
    adj[other].erase(c);
    if (adj[other].size() == 1) prune.push_back(other);
  }
  std::vector<std::vector<int>> ring(nc);
  for (int c = 0; c < nc; ++c) {
    const Vec3 n = J.normal[c], q = cf.q[first[c]];
    const Vec3 along = q - q.dot(n) * n;
    const Vec3 r = along.norm() > 1e-12 ? Vec3(along.normalized()) : any_perpendicular(n);
    const Vec3 s = n.cross(r);
    std::vector<std::pair<double, int>> by_angle;
    for (int b : adj[c]) {
      const Vec3 d = J.pos[b] - J.pos[c];
      by_angle.emplace_back(std::atan2(d.dot(s), d.dot(r)), b);
    }
    std::sort(by_angle.begin(), by_angle.end());
    for (const auto& [angle, b] : by_angle) ring[c].push_back(b);
  }
  return ring;
}

/// Step 3c: faces traced by turning at each joint to the previous beam of its ring; kept when
/// closed, not too many sides, no joint twice and facing along the joints' normals.
std::vector<std::vector<int>> trace_faces(const std::vector<std::vector<int>>& ring,
                                          const LatticeJoints& J, int max_face_sides) {
  std::map<std::pair<int, int>, char> used;
  std::vector<std::vector<int>> faces;
  for (int a0 = 0; a0 < J.count; ++a0) {
    for (int b0 : ring[a0]) {
      if (used.count({a0, b0})) continue;
      std::vector<int> face{a0};
      int a = a0, b = b0;
      bool closed = false;
      for (int step = 0; step < 4 * max_face_sides; ++step) {
        used[{a, b}] = 1;
        if (b == a0) {
          closed = true;
          break;
        }
        face.push_back(b);
        const auto& rb = ring[b];
        const int k = static_cast<int>(std::find(rb.begin(), rb.end(), a) - rb.begin());
        const int deg = static_cast<int>(rb.size());
        const int next = rb[(k - 1 + deg) % deg];
        a = b, b = next;
      }
      if (!closed || static_cast<int>(face.size()) > max_face_sides || face.size() < 3) continue;
      std::vector<int> sorted = face;
      std::sort(sorted.begin(), sorted.end());
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) continue;
      Vec3 area = Vec3::Zero(), normal = Vec3::Zero();
      for (size_t k = 0; k < face.size(); ++k) {
        area += J.pos[face[k]].cross(J.pos[face[(k + 1) % face.size()]]);
        normal += J.normal[face[k]];
      }
      if (area.dot(normal) <= 0) continue;  // the outer boundary, or a folded face
      faces.push_back(std::move(face));
    }
  }
  return faces;
}

/// The joints `J` of M′ carried to M (not yet projected on it): each joint's position is its
/// vertices' lattice points through the affine map of the incident triangle that contains each
/// best, averaged; its normal is the mean of its vertices' normals on M (`rest_normal`).
LatticeJoints joints_on_rest(const TriMesh& rest, const TriMesh& def, const Topology& topo,
                             const std::vector<Vec3>& org, const LatticeJoints& J,
                             const std::vector<Vec3>& rest_normal) {
  const int nv = def.num_vertices(), nc = J.count;
  LatticeJoints on_m = J;
  std::vector<Vec3>&cm = on_m.pos, &normal = on_m.normal;
  std::fill(cm.begin(), cm.end(), Vec3::Zero());
  std::fill(normal.begin(), normal.end(), Vec3::Zero());
  for (int v = 0; v < nv; ++v) {
    double best = -std::numeric_limits<double>::infinity();
    Vec3 mapped = rest.vertex(v);
    for (int f : topo.vertex_faces[v]) {
      const Vec3 a = def.vertex(def.F(f, 0)), b = def.vertex(def.F(f, 1)),
                 c = def.vertex(def.F(f, 2));
      const Vec3 e1 = b - a, e2 = c - a, d = org[v] - a;
      Eigen::Matrix2d G;
      G << e1.dot(e1), e1.dot(e2), e1.dot(e2), e2.dot(e2);
      const Eigen::Vector2d st = G.ldlt().solve(Eigen::Vector2d(e1.dot(d), e2.dot(d)));
      const double score = std::min({1 - st(0) - st(1), st(0), st(1)});
      if (!std::isfinite(score) || score <= best) continue;
      best = score;
      const Vec3 ra = rest.vertex(rest.F(f, 0));
      mapped =
          ra + st(0) * (rest.vertex(rest.F(f, 1)) - ra) + st(1) * (rest.vertex(rest.F(f, 2)) - ra);
    }
    cm[J.cluster[v]] += mapped;
    normal[J.cluster[v]] += rest_normal[v];
  }
  for (int c = 0; c < nc; ++c) {
    cm[c] /= J.vertices[c];
    normal[c] = normal[c].norm() > 0 ? Vec3(normal[c].normalized()) : J.normal[c];
  }
  return on_m;
}

/// The total area of polygons `faces` with corners `pos`.
double faces_area(const std::vector<std::vector<int>>& faces, const std::vector<Vec3>& pos) {
  double total = 0;
  for (const auto& f : faces) total += polygon_area(pos, f);
  return total;
}

/// Step 4: the joints carried to M (`joints_on_rest`) projected on it; joints renumbered in the
/// order the faces use them.
PolyMesh joints_on_surface(const TriMesh& rest, const std::vector<Vec3>& cm,
                           std::vector<std::vector<int>> faces) {
  const int nc = static_cast<int>(cm.size());
  std::vector<int> index(nc, -1);
  PolyMesh out;
  int count = 0;
  for (auto& f : faces)
    for (int& c : f) {
      if (index[c] < 0) index[c] = count++;
      c = index[c];
    }
  out.V.resize(count, 3);
  const SurfaceProjector proj(rest);
  for (int c = 0; c < nc; ++c)
    if (index[c] >= 0) out.V.row(index[c]) = proj.closest_point(cm[c]).transpose();
  out.faces = std::move(faces);
  return out;
}

}  // namespace

namespace {

/// What does not depend on the spacing or the lattice's start, computed once per M′: topology,
/// hierarchy, cross field per level and the matched neighbour frames of each level.
/// The lattice spacing's factor e^s per vertex of M′ (and of each coarser level) that lets the
/// lattice follow the cross field with fewer rows of cells starting. A cross field that turns
/// (∇θ, on M′ with its curvature) is the frame of a grid without such defects only if the
/// spacing varies with ∇s = −J ∇θ — a conformal grid: lines along hoops and meridians need
/// cells ∝ r. At a constant spacing every turn is paid in dislocations. s is the least-squares
/// solution of ∇s = −J ∇θ (P1 gradients, cotangent Laplacian; triangles where the cross's
/// matchings do not close — its singularities — are left out). Part of it is the field's own
/// grading: M′ is M scaled by about d / √a, and a lattice that is regular on M (a constant u on
/// a plane, any d) has spacing ∝ d / √a on M′; that part, log(d / √a), is subtracted, so the
/// cells keep the sizes d asks for and only the directions' turning and M's own curvature are
/// absorbed. The rest is shifted to area-weighted mean 0,
/// multiplied by `integrable_scale`, and clamped to ± log `max_scale_change`; coarser levels
/// take the area-weighted mean of log scale over their children.
std::vector<std::vector<double>> integrable_scale(const TriMesh& def, const Field& field,
                                                  const std::vector<Level>& levels,
                                                  const CrossField& cf, const QuadAnisoOptions& o) {
  const int nv = def.num_vertices(), nf = def.num_faces();
  std::vector<std::vector<double>> scale(levels.size());
  for (size_t k = 0; k < levels.size(); ++k) scale[k].assign(levels[k].size(), 1.0);
  if (o.integrable_scale == 0 || o.max_scale_change == 1) return scale;
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nv), mass = Eigen::VectorXd::Zero(nv),
                  asked = Eigen::VectorXd::Zero(nv);
  for (int f = 0; f < nf; ++f) {
    const int id[3] = {def.F(f, 0), def.F(f, 1), def.F(f, 2)};
    const Vec3 p[3] = {def.vertex(id[0]), def.vertex(id[1]), def.vertex(id[2])};
    Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
    const double area2 = n.norm();
    if (!(area2 > 0)) continue;
    n /= area2;
    const double area = 0.5 * area2;
    // ∇ of the hat functions: n × (opposite edge) / (2 area).
    Vec3 grad[3];
    for (int c = 0; c < 3; ++c) grad[c] = n.cross(p[(c + 2) % 3] - p[(c + 1) % 3]) / area2;
    // M′ is M scaled by d/a along u and d across: its conformal part, log(d / √a), is grading the
    // field asks for, not turning to absorb.
    const double graded = std::log(field.d[f] / std::sqrt(field.a[f]));
    for (int a = 0; a < 3; ++a) {
      mass[id[a]] += area / 3;
      asked[id[a]] += area / 3 * graded;
      for (int b = 0; b < 3; ++b) trip.emplace_back(id[a], id[b], area * grad[a].dot(grad[b]));
    }
    // The cross's angle at the three corners, matched to corner 0's and measured in the
    // triangle's plane; a singular triangle (the matchings around it do not close) is skipped.
    const Vec3 r = tangent_unit(cf.q[id[0]], n), rs = n.cross(r);
    double theta[3] = {0, 0, 0};
    Vec3 prev = cf.q[id[0]];
    for (int c = 1; c < 3; ++c) {
      prev = match_cross(cf.q[id[c]], cf.n[id[c]], prev);
      const Vec3 qc = tangent_unit(prev, n);
      theta[c] = std::atan2(qc.dot(rs), qc.dot(r));
    }
    const Vec3 back = match_cross(cf.q[id[0]], cf.n[id[0]], prev);
    if (back.dot(cf.q[id[0]]) < 0.5) continue;
    Vec3 grad_theta = Vec3::Zero();
    for (int c = 0; c < 3; ++c) grad_theta += theta[c] * grad[c];
    const Vec3 g = -n.cross(grad_theta);  // −J ∇θ
    for (int a = 0; a < 3; ++a) rhs[id[a]] += area * g.dot(grad[a]);
  }
  Eigen::SparseMatrix<double> L(nv, nv);
  L.setFromTriplets(trip.begin(), trip.end());
  double total = mass.sum(), diag = 0;
  for (int v = 0; v < nv; ++v) diag += L.coeff(v, v);
  // A weak pull to 0 fixes the free constant (the solve is otherwise singular).
  const double eps = 1e-8 * diag / std::max(1.0, total);
  for (int v = 0; v < nv; ++v) L.coeffRef(v, v) += eps * mass[v];
  // One small 2D Laplacian per M′: Eigen's simplicial factorisation, without CHOLMOD's
  // supernodal BLAS blocks and symbolic-analysis lock (core/cholmod_support.h), which pay off on
  // the frame and shell systems, not here.
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(L);
  if (solver.info() != Eigen::Success) return scale;
  Eigen::VectorXd sv = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !sv.allFinite()) return scale;
  for (int v = 0; v < nv; ++v) sv[v] -= mass[v] > 0 ? asked[v] / mass[v] : 0;
  const double mean = sv.dot(mass) / total, cap = std::log(o.max_scale_change);
  for (int v = 0; v < nv; ++v)
    scale[0][v] = std::exp(std::clamp(o.integrable_scale * (sv[v] - mean), -cap, cap));
  for (size_t k = 1; k < levels.size(); ++k) {
    std::vector<double> sum(levels[k].size(), 0), w(levels[k].size(), 0);
    for (int v = 0; v < levels[k - 1].size(); ++v) {
      const int pa = levels[k - 1].parent[v];
      sum[pa] += levels[k - 1].area[v] * std::log(scale[k - 1][v]);
      w[pa] += levels[k - 1].area[v];
    }
    for (int v = 0; v < levels[k].size(); ++v)
      scale[k][v] = w[v] > 0 ? std::exp(sum[v] / w[v]) : 1.0;
  }
  return scale;
}

struct MetricFrames {
  Topology topo;
  std::vector<Vec3> pos;
  std::vector<Level> levels;
  std::vector<CrossField> cfs;
  std::vector<MatchedFrames> matched;
  std::vector<std::vector<double>> scale;  ///< per level and vertex: the lattice spacing / h
  std::vector<Vec3> rest_normal;           ///< per vertex of M (refined as M′): unit normal
  double scale_p10 = 1, scale_p90 = 1;     ///< of scale[0], weighted by M′'s vertex areas
};

MetricFrames metric_frames(const TriMesh& rest, const TriMesh& def, const Field& field, double h,
                           const QuadAnisoOptions& o) {
  if (rest.num_faces() != def.num_faces() || rest.num_vertices() != def.num_vertices() ||
      field.size() != rest.num_faces())
    throw Error("quad-aniso", "M, M' and the field do not match");
  MetricFrames m;
  m.topo = build_topology(def);
  m.pos.resize(def.num_vertices());
  for (int v = 0; v < def.num_vertices(); ++v) m.pos[v] = def.vertex(v);
  m.levels = build_hierarchy(def, m.topo, o.coarsest);
  m.cfs = cross_field(rest, def, field, m.topo, m.levels, h, o);
  for (size_t k = 0; k < m.levels.size(); ++k)
    m.matched.push_back(matched_frames(m.levels[k], m.cfs[k]));
  m.scale = integrable_scale(def, field, m.levels, m.cfs[0], o);
  m.rest_normal = vertex_normals(rest);
  std::vector<std::pair<double, double>> sw;
  for (int v = 0; v < m.levels[0].size(); ++v) sw.emplace_back(m.scale[0][v], m.levels[0].area[v]);
  std::sort(sw.begin(), sw.end());
  double total = 0, acc = 0;
  for (const auto& [x, w] : sw) total += w;
  for (const auto& [x, w] : sw) {
    if (acc <= 0.1 * total) m.scale_p10 = x;
    if (acc <= 0.9 * total) m.scale_p90 = x;
    acc += w;
  }
  return m;
}

/// Steps 2–4 for one spacing and one lattice start (o.seed).
PolyMesh quad_mesh_from_frames(const MetricFrames& m, const TriMesh& rest, const TriMesh& def,
                               double h, const QuadAnisoOptions& o) {
  if (!(h > 0) || !std::isfinite(h)) throw Error("quad-aniso", "spacing must be positive");
  const CrossField& cf = m.cfs[0];
  const std::vector<Vec3> org = position_field(m.levels, m.cfs, m.matched, m.scale, h, o);
  const LatticeJoints joints = collapse_to_joints(m.pos, m.topo, cf, org, m.scale[0], h);
  // Faces are traced twice: with the beams ordered about each joint on M′, and on M, and the
  // tracing whose faces cover more of M is kept (M′'s on a tie). M′ is where the lattice is
  // square, but it can be crushed where the metric changes fast (the rim of a lobe of large cells
  // next to small ones): there neighbours' angles about a joint on M′ are not their order on the
  // surface, faces are walked across cells, and a whole lobe was left without faces. On M, the
  // roof, the order is right there; near M′'s boundary a joint's point on M is extrapolated and
  // its order can be the worse one.
  const LatticeJoints on_m = joints_on_rest(rest, def, m.topo, org, joints, m.rest_normal);
  std::vector<std::vector<int>> faces =
      trace_faces(joint_rings(joints, cf), joints, o.max_face_sides);
  std::vector<std::vector<int>> faces_m =
      trace_faces(joint_rings(on_m, cf), on_m, o.max_face_sides);
  if (faces_area(faces_m, on_m.pos) > faces_area(faces, on_m.pos) * (1 + 1e-9))
    faces = std::move(faces_m);
  if (faces.empty()) throw Error("quad-aniso", "extraction found no faces (spacing too large?)");
  pair_odd_faces(faces, joints.pos, joints.normal, h);
  merge_triangle_pairs(faces, joints.pos);
  absorb_lone_triangles(faces, joints.pos);
  return joints_on_surface(rest, on_m.pos, std::move(faces));
}

}  // namespace

PolyMesh quad_mesh_on_metric(const TriMesh& rest, const TriMesh& def, const Field& field, double h,
                             const QuadAnisoOptions& o) {
  if (!(h > 0) || !std::isfinite(h)) throw Error("quad-aniso", "spacing must be positive");
  return quad_mesh_from_frames(metric_frames(rest, def, field, h, o), rest, def, h, o);
}

namespace {

/// Whether a face of the grid spans a hole (or a notch) of M: at least a third of the sample
/// points inside it (its centroid, and the points halfway from it to each corner and to each
/// side's middle) lie over the void — closer to M's boundary than to any interior point of M,
/// and off M by more than 2 % of the face's mean side. The extraction walks faces around M′'s
/// holes like any other loop of beams; a hole smaller than a few cells would otherwise get a
/// panel over it. (A face along a boundary that curves into M has the void only between its
/// side and the boundary, outside the samples.)
bool spans_void(const std::vector<Vec3>& p, const std::vector<int>& face,
                const SurfaceProjector& proj) {
  if (!proj.has_boundary()) return false;
  const size_t n = face.size();
  Vec3 c = Vec3::Zero();
  double side = 0;
  for (size_t k = 0; k < n; ++k) {
    c += p[face[k]];
    side += (p[face[k]] - p[face[(k + 1) % n]]).norm();
  }
  c /= static_cast<double>(n);
  side /= static_cast<double>(n);
  std::vector<Vec3> samples{c};
  for (size_t k = 0; k < n; ++k) {
    samples.push_back(0.5 * (c + p[face[k]]));
    samples.push_back(0.5 * c + 0.25 * (p[face[k]] + p[face[(k + 1) % n]]));
  }
  int void_samples = 0;
  for (const Vec3& x : samples) {
    const double to_surface = (proj.closest_point(x) - x).norm();
    if (to_surface > 0.02 * side &&
        (proj.closest_boundary_point(x) - x).norm() <= to_surface + 1e-9 * proj.diagonal())
      ++void_samples;
  }
  return 3 * void_samples >= static_cast<int>(samples.size());
}

/// The same for face `face` of `g`.
bool spans_void(const PolyMesh& g, const std::vector<int>& face, const SurfaceProjector& proj) {
  std::vector<Vec3> corners;
  for (int v : face) corners.push_back(g.vertex(v));
  std::vector<int> local(face.size());
  std::iota(local.begin(), local.end(), 0);
  return spans_void(corners, local, proj);
}

/// The area of each face of `g`, and their median (0 without faces).
std::vector<double> face_areas(const PolyMesh& g) {
  std::vector<double> areas;
  for (int f = 0; f < g.num_faces(); ++f) areas.push_back(polygon_area(g, f));
  return areas;
}
double median_area(std::vector<double> areas) {
  if (areas.empty()) return 0;
  std::nth_element(areas.begin(), areas.begin() + areas.size() / 2, areas.end());
  return areas[areas.size() / 2];
}

/// The point of segment [a, b] nearest x, as the parameter along it (0 at a, 1 at b).
double segment_parameter(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double l2 = d.squaredNorm();
  return l2 > 0 ? std::clamp((x - a).dot(d) / l2, 0.0, 1.0) : 0.0;
}

/// Douglas–Peucker: the points of the polyline `path` (ends excluded) that stay when it is
/// simplified to within `tolerance`, in order.
void simplify_path(const std::vector<Vec3>& path, int first, int last, double tolerance,
                   std::vector<int>& kept) {
  if (last - first < 2) return;
  int worst = -1;
  double worst_d = tolerance;
  for (int i = first + 1; i < last; ++i) {
    const double t = segment_parameter(path[i], path[first], path[last]);
    const double d = (path[i] - (path[first] + t * (path[last] - path[first]))).norm();
    if (d > worst_d) worst_d = d, worst = i;
  }
  if (worst < 0) return;
  simplify_path(path, first, worst, tolerance, kept);
  kept.push_back(worst);
  simplify_path(path, worst, last, tolerance, kept);
}

/// Gaps between the grid's boundary and M's: where the grid's boundary runs from a joint on M's
/// boundary (s0) through at most `max_inner` joints off it to the next joint on M's boundary
/// (s1) while M's boundary between them (s0 to s1 in the same sense) bends away from the
/// grid's — a corner of M cut off by one beam, or a notch of a few cells where the lattice's
/// seam meets the boundary — the gap becomes a face: M's boundary from s0 to s1, simplified to
/// within a quarter of the gap's chord (Douglas–Peucker; its corners become joints), then the
/// grid's boundary back. Gaps whose face would have more than `max_sides` sides, would not be a
/// simple polygon or would lie over the void are left open.
void fill_boundary_gaps(PolyMesh& g, const Points& mv, const std::vector<std::vector<int>>& m_loops,
                        int max_inner, int max_sides, const SurfaceProjector& proj) {
  struct Spot {
    int loop = -1, edge = 0;
    double t = 0, distance = std::numeric_limits<double>::infinity();
  };
  auto locate = [&](const Vec3& x) {
    Spot best;
    for (int l = 0; l < static_cast<int>(m_loops.size()); ++l) {
      const auto& loop = m_loops[l];
      for (int e = 0; e < static_cast<int>(loop.size()); ++e) {
        const Vec3 a = mv.row(loop[e]).transpose();
        const Vec3 b = mv.row(loop[(e + 1) % loop.size()]).transpose();
        const double t = segment_parameter(x, a, b);
        const double d = (x - (a + t * (b - a))).norm();
        if (d < best.distance) best = {l, e, t, d};
      }
    }
    return best;
  };
  const double tol = 1e-6 * proj.diagonal();
  const Topology topo = build_topology(g);
  double mean_beam = 0;
  for (const auto& e : topo.edges) mean_beam += (g.vertex(e[0]) - g.vertex(e[1])).norm();
  mean_beam /= std::max(1, topo.num_edges());
  // A gap is a corner or a notch, about a cell: a face of more than twice the median face's
  // area would be a panel across a region the extraction left empty (a trapezoid's end, 40 % of
  // its roof, in one pentagon), not a gap.
  const double max_area = 2 * median_area(face_areas(g));
  std::vector<char> on_m_boundary(g.num_vertices(), 0);
  for (const auto& loop : topo.boundary_loops)
    for (int v : loop) on_m_boundary[v] = locate(g.vertex(v)).distance <= tol;
  for (const auto& loop : topo.boundary_loops) {
    const int n = static_cast<int>(loop.size());
    for (int i = 0; i < n; ++i) {
      if (!on_m_boundary[loop[i]]) continue;
      int j = (i + 1) % n, inner = 0;
      while (!on_m_boundary[loop[j]] && j != i) j = (j + 1) % n, ++inner;
      if (j == i || inner > max_inner) continue;
      bool regular = true;  // the joints off M's boundary become interior: valence 4 only
      for (int k = (i + 1) % n; k != j; k = (k + 1) % n)
        regular = regular && topo.vertex_neighbors[loop[k]].size() == 4;
      if (!regular) continue;
      const int s0 = loop[i], s1 = loop[j];
      const Spot a = locate(g.vertex(s0)), b = locate(g.vertex(s1));
      if (a.loop < 0 || a.loop != b.loop || a.distance > tol || b.distance > tol) continue;
      // M's boundary from s0 to s1, forward (M and the grid are oriented alike).
      const auto& ml = m_loops[a.loop];
      const int mn = static_cast<int>(ml.size());
      std::vector<Vec3> path{g.vertex(s0)};
      if (!(a.edge == b.edge && b.t >= a.t)) {
        for (int e = (a.edge + 1) % mn, steps = 0; steps < mn; e = (e + 1) % mn, ++steps) {
          path.push_back(mv.row(ml[e]).transpose());
          if (e == b.edge) break;
        }
      }
      path.push_back(g.vertex(s1));
      double m_length = 0, grid_length = 0;
      for (size_t k = 1; k < path.size(); ++k) m_length += (path[k] - path[k - 1]).norm();
      for (int k = i; k != j; k = (k + 1) % n)
        grid_length += (g.vertex(loop[(k + 1) % n]) - g.vertex(loop[k])).norm();
      if (m_length > 4 * grid_length) continue;  // the long way round: not this gap
      const double chord = (g.vertex(s1) - g.vertex(s0)).norm();
      std::vector<int> kept;  // new beams are at least a quarter of the mean beam long
      simplify_path(path, 0, static_cast<int>(path.size()) - 1, 0.25 * std::max(chord, mean_beam),
                    kept);
      if (inner == 0 && kept.empty()) continue;  // a beam along M's boundary
      const int sides = 2 + inner + static_cast<int>(kept.size());
      if (sides > max_sides || (kept.empty() && chord < 0.25 * mean_beam)) continue;
      const int first_new = g.num_vertices();
      std::vector<int> face{s0};
      g.V.conservativeResize(first_new + static_cast<int>(kept.size()), 3);
      for (size_t k = 0; k < kept.size(); ++k) {
        g.V.row(first_new + static_cast<int>(k)) = path[kept[k]].transpose();
        face.push_back(first_new + static_cast<int>(k));
      }
      face.push_back(s1);
      for (int k = (j - 1 + n) % n; k != i; k = (k - 1 + n) % n) face.push_back(loop[k]);
      g.faces.push_back(face);
      const double area = polygon_area(g, g.num_faces() - 1);
      g.faces.pop_back();
      if (area > max_area || !is_simple_polygon(g, face) || spans_void(g, face, proj)) {
        g.V.conservativeResize(first_new, 3);
        continue;
      }
      g.faces.push_back(std::move(face));
    }
  }
}

/// Faces that cover part of the roof twice (mesh/overlaps.h: beams that cross, a joint inside a
/// panel not its own) are left out, one overlap at a time: of the two sides of an overlap — the
/// faces on either crossing beam, or the panel over a joint — the side of the thinner faces
/// (lower mean 4π·area / perimeter²) goes. Folds come from a walk that went round the wrong way
/// where M′ is crushed, or from joints snapped onto M's boundary past their neighbours; the face
/// walked across cells is the long thin one over the others. A grid with two panels one over
/// the other, or two beams through one point without a joint, cannot be built: the hole left is
/// the lesser defect. Each round leaves out at least one face, so this ends.
void remove_overlaps(PolyMesh& g) {
  while (g.num_faces() > 0) {
    const Topology topo = build_topology(g);
    const Overlaps ov = find_overlaps(g, topo);
    if (ov.count() == 0) return;
    auto compactness = [&](int f) {
      const auto& poly = g.faces[f];
      double perimeter = 0;
      for (size_t k = 0; k < poly.size(); ++k)
        perimeter += (g.vertex(poly[k]) - g.vertex(poly[(k + 1) % poly.size()])).norm();
      return perimeter > 0 ? 4 * std::numbers::pi * polygon_area(g, f) / (perimeter * perimeter)
                           : 0.0;
    };
    auto mean_compactness = [&](const std::vector<int>& faces) {
      double sum = 0;
      for (int f : faces) sum += compactness(f);
      return faces.empty() ? std::numeric_limits<double>::infinity() : sum / faces.size();
    };
    std::vector<int> drop;
    double worst = std::numeric_limits<double>::infinity();
    auto propose = [&](const std::vector<int>& faces) {
      const double c = mean_compactness(faces);
      if (drop.empty() || c < worst) worst = c, drop = faces;
    };
    for (const auto& [e1, e2] : ov.crossing_edges) {
      const std::vector<int> side1 = topo.edge_faces[e1], side2 = topo.edge_faces[e2];
      propose(mean_compactness(side1) <= mean_compactness(side2) ? side1 : side2);
    }
    for (const auto& [v, f] : ov.covered_vertices) propose({f});
    std::sort(drop.begin(), drop.end());
    drop.erase(std::unique(drop.begin(), drop.end()), drop.end());
    for (auto it = drop.rbegin(); it != drop.rend(); ++it) g.faces.erase(g.faces.begin() + *it);
  }
}

/// A row of cells that ends inside the grid leaves an odd face there (a triangle, a pentagon) with
/// no odd partner inside: its partner is across the rim, where the boundary cut the lattice. On
/// the final grid (on M), odd faces are paired with odd faces of the rim (faces with a joint on
/// the boundary) by `pair_odd_faces`, so the defect moves to the rim.
void pair_with_rim(PolyMesh& g) {
  const Topology topo = build_topology(g);
  const int nv = g.num_vertices(), nf = g.num_faces();
  std::vector<Vec3> p(nv), normal(nv, Vec3::Zero());
  for (int v = 0; v < nv; ++v) p[v] = g.vertex(v);
  std::vector<char> on_rim(nf, 0);
  for (int f = 0; f < nf; ++f) {
    const Vec3 area = vector_area(g, f);
    for (int v : g.faces[f]) normal[v] += area, on_rim[f] |= topo.on_boundary[v];
  }
  for (Vec3& n : normal)
    if (n.norm() > 0) n.normalize();
  pair_odd_faces(g.faces, p, normal, 0, 2, on_rim);
}

/// Leaves out the faces of less than `fraction` of the median face area: slivers where the
/// joints of a boundary cell were all snapped onto a straight piece of M's boundary, or a gap
/// between the grid's boundary and M's was filled by a face of almost no area (without this step
/// 16 of 198 grids of the stats tables had one, Botanic (3, 3) at 2018 m among them). A panel of a
/// fiftieth of the others' area, or of none, is nothing anyone would cut glass for. Vertices are
/// not touched (largest_component drops the unused ones).
void drop_slivers(PolyMesh& g, double fraction) {
  const std::vector<double> areas = face_areas(g);
  const double limit = fraction * median_area(areas);
  std::vector<std::vector<int>> kept;
  for (int f = 0; f < g.num_faces(); ++f)
    if (areas[f] >= limit) kept.push_back(std::move(g.faces[f]));
  g.faces = std::move(kept);
}

/// Moves the grid's outer-boundary joints near M's boundary onto it, collapses the stubs this
/// makes, and drops unused joints, faces that are not simple polygons and faces over M's holes.
PolyMesh snap_to_boundary(const PolyMesh& mesh, const SurfaceProjector& proj, double snap) {
  const Topology topo = build_topology(mesh);
  std::vector<Vec3> p(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) p[v] = mesh.vertex(v);
  std::vector<int> rank(mesh.num_vertices(), 0);
  std::vector<double> lengths;
  for (const auto& e : topo.edges) lengths.push_back((p[e[0]] - p[e[1]]).norm());
  for (const auto& loop : topo.boundary_loops) {
    for (int v : loop) {
      double mean = 0;
      for (int u : topo.vertex_neighbors[v]) mean += (p[u] - p[v]).norm();
      mean /= std::max<size_t>(1, topo.vertex_neighbors[v].size());
      const Vec3 b = proj.closest_boundary_point(mesh.vertex(v));
      if ((b - mesh.vertex(v)).norm() <= snap * mean) p[v] = b, rank[v] = 1;
    }
  }
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  const double median = lengths.empty() ? 0 : lengths[lengths.size() / 2];
  std::vector<std::vector<int>> faces = mesh.faces;
  collapse_boundary_stubs(faces, p, rank, 0.25 * median);
  // Beams still shorter than 0.15 × median (lattice points that nearly coincide): each collapsed
  // into its boundary end, or to its midpoint; a face left with < 3 corners disappears.
  for (int pass = 0; pass < 3; ++pass) {  // a collapse can leave another stub
    std::vector<std::pair<double, std::array<int, 2>>> stubs;
    for (const auto& f : faces)
      for (size_t k = 0; k < f.size(); ++k) {
        const int a = f[k], b = f[(k + 1) % f.size()];
        const double l = (p[a] - p[b]).norm();
        if (l < 0.15 * median) stubs.push_back({l, {std::min(a, b), std::max(a, b)}});
      }
    std::sort(stubs.begin(), stubs.end());
    std::vector<int> into(mesh.num_vertices());
    std::iota(into.begin(), into.end(), 0);
    std::vector<char> touched(mesh.num_vertices(), 0);
    for (const auto& [l, e] : stubs) {
      int a = e[0], b = e[1];
      if (touched[a] || touched[b]) continue;
      if (rank[b] > rank[a]) std::swap(a, b);
      if (rank[a] == rank[b]) p[a] = 0.5 * (p[a] + p[b]);
      into[b] = a;
      touched[a] = touched[b] = 1;
    }
    for (auto& f : faces) {
      std::vector<int> g;
      for (int v : f)
        if (g.empty() || g.back() != into[v]) g.push_back(into[v]);
      while (g.size() > 1 && g.front() == g.back()) g.pop_back();
      f = g.size() >= 3 ? g : std::vector<int>{};
    }
  }
  PolyMesh out;
  std::vector<int> index(mesh.num_vertices(), -1);
  int count = 0;
  PolyMesh moved{mesh.V, {}};
  for (int v = 0; v < mesh.num_vertices(); ++v) moved.V.row(v) = p[v].transpose();
  for (auto& f : faces) {
    if (f.size() < 3 || !is_simple_polygon(moved, f))
      continue;  // a fold at the seam of the lattice
    if (spans_void(p, f, proj)) continue;
    for (int& v : f) {
      if (index[v] < 0) index[v] = count++;
      v = index[v];
    }
    out.faces.push_back(f);
  }
  out.V.resize(count, 3);
  std::vector<char> on_surface_boundary(count, 0);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (index[v] >= 0) {
      out.V.row(index[v]) = p[v].transpose();
      on_surface_boundary[index[v]] = rank[v] > 0;
    }
  // Holes left by the faces that were not kept (more than max_face_sides sides, folded or not
  // simple): a hole away from M's boundary whose loop is a simple polygon of ≤ 12 sides becomes
  // a face again (its beams are there anyway; the panel carries its share of the load).
  const Topology t = build_topology(out);
  for (const auto& loop : t.boundary_loops) {
    if (loop.size() > 12) continue;
    bool inner = true;
    for (int v : loop) inner = inner && !on_surface_boundary[v];
    std::vector<int> face(loop.rbegin(), loop.rend());
    if (inner && is_simple_polygon(out, face) && !spans_void(out, face, proj))
      out.faces.push_back(std::move(face));
  }
  return out;
}

bool is_isotropic(const Field& field) {
  for (int f = 0; f < field.size(); ++f)
    if (field.d[f] != 1 || field.a[f] != 1) return false;
  return true;
}

}  // namespace

double quad_grid_quality(const QuadMeshStats& st) {
  const double aligned = st.strong_beams > 0 ? st.aligned_share : 1.0;
  // Coverage over 1 (faces stacked; remove_overlaps leaves them out before a grid is scored, so
  // this is a guard) counts as much against as the same shortfall.
  const double covered = 1 - std::abs(1 - st.coverage);
  const int short_of_bars =
      (st.valence4_share < 0.85) + (st.quad_share < 0.85) + (aligned < 0.70) + (covered < 0.90);
  // A missed bar weighs more than the sum of the four shares can make up.
  return st.valence4_share + st.quad_share + aligned + covered - 4.0 * short_of_bars;
}

QuadAnisoResult quad_aniso(const Surface& surface, const Field& field, const QuadAnisoOptions& o) {
  const TriMesh& mesh = surface.mesh;
  if (field.size() != mesh.num_faces())
    throw Error("quad-aniso", "the field does not have one entry per triangle");
  if (!(o.length > 0) && !(o.spacing > 0))
    throw Error("--length", "quad-aniso needs --length L (m) or a spacing");
  if (!(o.resolution >= 1)) throw Error("quad-aniso", "resolution must be ≥ 1");
  if (!(o.direction_smoothing > 0) || !std::isfinite(o.direction_smoothing))
    throw Error("quad-aniso", "direction_smoothing must be positive");
  if (!(o.integrable_scale >= 0) || !std::isfinite(o.integrable_scale))
    throw Error("quad-aniso", "integrable_scale must be ≥ 0");
  if (!(o.max_scale_change >= 1) || !std::isfinite(o.max_scale_change))
    throw Error("quad-aniso", "max_scale_change must be ≥ 1");
  if (!(o.start_cells >= 0) || !std::isfinite(o.start_cells))
    throw Error("quad-aniso", "start_cells must be ≥ 0");
  if (o.gap_joints < 0) throw Error("quad-aniso", "gap_joints must be ≥ 0");
  if (!(o.min_face_area >= 0 && o.min_face_area < 1))
    throw Error("quad-aniso", "min_face_area must be in [0, 1)");
  double area_def = 0;
  for (int f = 0; f < mesh.num_faces(); ++f)
    area_def += triangle_area(mesh.vertex(mesh.F(f, 0)), mesh.vertex(mesh.F(f, 1)),
                              mesh.vertex(mesh.F(f, 2))) *
                field.d[f] * field.d[f] / field.a[f];
  // Square cells of side h on M′ have 2/h of beams per m²; lengths on M are about
  // √(area_M / area_M′) of those on M′.
  double h = o.length > 0 ? 2 * std::sqrt(surface_area(mesh) * area_def) / o.length : o.spacing;
  QuadAnisoResult r;
  TriMesh rest, def;
  Field rest_field;
  const double max_edge = h / o.resolution;
  if (is_isotropic(field)) {
    rest = def = mesh;
    std::vector<int> parent(mesh.num_faces());
    std::iota(parent.begin(), parent.end(), 0);
    for (int round = 0; round < 32; ++round) {
      std::vector<int> p;
      if (split_long_edges(rest, def, max_edge, p) == 0) break;
      std::vector<int> composed(p.size());
      for (size_t k = 0; k < p.size(); ++k) composed[k] = parent[p[k]];
      parent = std::move(composed);
    }
    for (int p : parent) {
      rest_field.u.push_back(field.u[p]);
      rest_field.d.push_back(1);
      rest_field.a.push_back(1);
    }
  } else {
    DeformOptions dopt = o.deform;
    dopt.max_edge = max_edge;
    spdlog::info("[metric] deforming {} triangles (edges of M' ≤ {:.3g} m)", mesh.num_faces(),
                 max_edge);
    Deformed d = deform_metric(mesh, field, dopt);
    r.folded_edges = d.folded_edges;
    rest = std::move(d.rest);
    def = std::move(d.deformed);
    rest_field = std::move(d.field);
  }
  r.deformed_triangles = def.num_faces();
  const SurfaceProjector proj(mesh);
  const double tol = 1e-6 * bbox_diagonal(mesh.V);
  // A surface of several pieces (two roofs in one file) gets a grid on each: per piece, the
  // grid's largest component on it is kept.
  std::vector<int> piece_of_triangle(mesh.num_faces(), 0);
  bool several_pieces = false;
  {
    DisjointSets sets(mesh.num_vertices());
    for (int f = 0; f < mesh.num_faces(); ++f)
      for (int k = 1; k < 3; ++k) sets.unite(mesh.F(f, 0), mesh.F(f, k));
    for (int f = 0; f < mesh.num_faces(); ++f) {
      piece_of_triangle[f] = sets.find(mesh.F(f, 0));
      several_pieces |= piece_of_triangle[f] != piece_of_triangle[0];
    }
  }
  auto keep_largest = [&](const PolyMesh& grid) {
    if (!several_pieces) return largest_component(grid);
    std::vector<int> piece(grid.num_vertices());
    for (int v = 0; v < grid.num_vertices(); ++v) {
      int triangle = -1;
      proj.closest_point_walk(grid.vertex(v), triangle);
      piece[v] = piece_of_triangle[triangle];
    }
    return largest_component(grid, piece);
  };
  const MetricFrames frames =
      metric_frames(rest, def, rest_field, h, o);  // the h M′ is refined for
  // One lattice start at spacing h: the grid on M, cleaned up, with its length error and score.
  struct Candidate {
    PolyMesh grid;
    double spacing = 0, length = 0, error = 0, score = 0;
  };
  auto build = [&](double spacing, int start) {
    QuadAnisoOptions so = o;
    so.seed = o.seed + 7919 * static_cast<std::uint64_t>(start);
    Candidate c;
    c.spacing = spacing;
    c.grid = quad_mesh_from_frames(frames, rest, def, spacing, so);
    for (int v = 0; v < c.grid.num_vertices(); ++v)
      c.grid.V.row(v) = proj.closest_point(c.grid.vertex(v)).transpose();
    // Flaps and pieces the extraction left apart (a quad cut off by a hole) would be
    // mechanisms, or nearly, in the analysis.
    c.grid = snap_to_boundary(c.grid, proj, o.boundary_snap);
    drop_slivers(c.grid, o.min_face_area);
    remove_hanging_faces(c.grid);
    c.grid = keep_largest(c.grid);
    fill_boundary_gaps(c.grid, mesh.V, proj.boundary_loops(), o.gap_joints, o.max_face_sides, proj);
    drop_slivers(c.grid, o.min_face_area);  // a gap filled by a face of almost no area
    c.grid = keep_largest(c.grid);
    pair_with_rim(c.grid);
    remove_overlaps(c.grid);
    c.grid = keep_largest(c.grid);
    c.score = quad_grid_quality(quad_mesh_stats(c.grid, mesh, field));
    c.length = total_edge_length(c.grid);
    c.error = o.length > 0 ? c.length / o.length - 1 : 0;
    return c;
  };
  std::vector<Candidate> pool;  // every grid built; the result is chosen from it at the end
  const int starts = std::max(1, o.starts);
  std::set<std::pair<double, int>> built;  // (spacing, start) of every grid in the pool
  // Builds the lattice starts not built yet (each (spacing, start) once), in parallel: every
  // start has its own seed, so the grids and their order in the pool do not depend on threads.
  auto add = [&](const std::vector<std::pair<double, int>>& jobs) {
    std::vector<std::pair<double, int>> todo;
    for (const auto& job : jobs)
      if (built.insert(job).second) todo.push_back(job);
    std::vector<Candidate> made(todo.size());
    tbb::parallel_for(0, static_cast<int>(todo.size()),
                      [&](int k) { made[k] = build(todo[k].first, todo[k].second); });
    for (Candidate& c : made) pool.push_back(std::move(c));
    r.grids += static_cast<int>(todo.size());
  };
  auto starts_at = [](double spacing, int from, int to) {
    std::vector<std::pair<double, int>> jobs;
    for (int start = from; start < to; ++start) jobs.emplace_back(spacing, start);
    return jobs;
  };
  const int fits = o.length > 0 ? o.max_fits : 1;
  double h_long = 0, h_short = std::numeric_limits<double>::infinity();  // see the bracket below
  for (int k = 0; k < fits; ++k) {
    // The secant follows the median length of the starts at this h: one start's grid can lose a
    // piece (only the largest connected part is kept), and its length would send the fit astray.
    ++r.fits;
    const size_t first = pool.size();
    size_t top = first;
    add(starts_at(h, 0, starts));
    if (pool.size() == first) break;  // the fit came back to a spacing it had tried
    for (size_t c = first; c < pool.size(); ++c)
      if (pool[c].score > pool[top].score) top = c;
    std::vector<double> lengths;
    for (size_t c = first; c < pool.size(); ++c) lengths.push_back(pool[c].length);
    std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
    const double length = lengths[lengths.size() / 2];
    spdlog::info(
        "[quad-aniso] h = {:.4g} m on M': {} starts, median {:.1f} m; the best: {} joints, "
        "{} faces, {:.1f} m",
        h, starts, length, pool[top].grid.num_vertices(), pool[top].grid.num_faces(),
        pool[top].length);
    if (std::abs(pool[top].error) <= o.length_tolerance) break;
    // L(h) is a step function (whole cells) and jumps with the lattice's start, so the secant on
    // L ∝ 1/h can oscillate about the target on a small grid: once h is bracketed (one grid too
    // long, one too short) a step that leaves the bracket is replaced by its geometric middle.
    if (length > o.length)
      h_long = std::max(h_long, h);
    else
      h_short = std::min(h_short, h);
    double next = h * length / o.length;
    if (h_long > 0 && std::isfinite(h_short) && h_long < h_short &&
        !(next > h_long && next < h_short))
      next = std::sqrt(h_long * h_short);
    h = next;
  }
  // A grid of a few dozen cells can jump across the ±limit band between two spacings as close as
  // the fit places them (one row of cells is > 10 % of its length); other lattice starts land
  // elsewhere on the step function. They are tried at the spacings of the closest grids above
  // and below the target (or, with one side only, there and at the fit's next step).
  auto within = [&](double limit) {
    return std::any_of(pool.begin(), pool.end(),
                       [&](const Candidate& c) { return std::abs(c.error) <= limit; });
  };
  const double limit = std::max(o.length_tolerance, o.length_limit);
  if (o.length > 0 && !within(limit)) {
    const Candidate *above = nullptr, *below = nullptr;
    for (const Candidate& c : pool) {
      if (c.error > 0 && (!above || c.error < above->error)) above = &c;
      if (c.error < 0 && (!below || c.error > below->error)) below = &c;
    }
    std::vector<double> retry;
    if (above) retry.push_back(above->spacing);
    if (below) retry.push_back(below->spacing);
    if (retry.size() < 2 && std::isfinite(h) && h > 0) retry.push_back(h);
    const int before = r.grids;
    for (int start = starts; start < starts + o.extra_starts && !within(limit); ++start)
      add([&] {
        std::vector<std::pair<double, int>> jobs;
        for (double spacing : retry) jobs.emplace_back(spacing, start);
        return jobs;
      }());
    spdlog::info("[quad-aniso] {} more lattice starts at {} spacings", r.grids - before,
                 retry.size());
  }
  // The result: the grid of the highest quality within length_tolerance (the first on a tie);
  // failing that, the closest.
  auto choose = [&] {
    const Candidate* best = nullptr;
    for (const Candidate& c : pool) {
      const bool in = std::abs(c.error) <= o.length_tolerance;
      const bool best_in = best && std::abs(best->error) <= o.length_tolerance;
      if (!best || (in && (!best_in || c.score > best->score)) ||
          (!in && !best_in && std::abs(c.error) < std::abs(best->error)))
        best = &c;
    }
    return best;
  };
  // More starts at the spacing of that grid: a grid of few cells is cheap to build again, and
  // its shares move most with the start (one defect among 40 joints is 2.5 points).
  const double chosen = choose()->spacing;
  const double cells = area_def / (chosen * chosen);
  r.starts = static_cast<int>(std::clamp(std::floor(o.start_cells / cells), double(starts),
                                         double(std::max(starts, o.max_starts))));
  const int before_more = r.grids;
  add(starts_at(chosen, starts, r.starts));
  if (r.grids > before_more)
    spdlog::info("[quad-aniso] {} more lattice starts at h = {:.4g} m (about {:.0f} cells)",
                 r.grids - before_more, chosen, cells);
  const Candidate* best = choose();
  if (o.length > 0 && std::abs(best->error) > limit)
    throw Error("quad-aniso", fmt::format("total length not within {:.0f}% of {} m after {} grids",
                                          100 * limit, o.length, r.grids));
  r.spacing = best->spacing;
  r.spacing_factor_p10 = frames.scale_p10;
  r.spacing_factor_p90 = frames.scale_p90;
  PolyMesh best_grid = best->grid;
  r.grid.mesh = std::move(best_grid);
  r.grid.supports = transfer_supports(r.grid.mesh.V, surface, tol);
  return r;
}

}  // namespace gridshell
