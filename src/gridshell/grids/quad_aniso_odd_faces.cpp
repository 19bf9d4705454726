#include "gridshell/grids/quad_aniso_internal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

namespace gridshell::quad_aniso_internal {

namespace {

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

}  // namespace

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

void pair_odd_faces(std::vector<std::vector<int>>& faces, const std::vector<Vec3>& p,
                    const std::vector<Vec3>& normal, double h, int max_quads_between,
                    const std::vector<char>& on_rim) {
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

}  // namespace gridshell::quad_aniso_internal
