#include "gridshell/grids/recover_quads.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <vector>

#include "gridshell/mesh/topology.h"

namespace gridshell {

namespace {

/// The quad (a, d, b, c) of triangle t = (a, b, c) (local edge k = a → b) and its neighbour
/// across that edge (corner d opposite).
std::vector<int> pair_quad(const TriMesh& m, int t, int k, int d) {
  return {m.F(t, k), d, m.F(t, (k + 1) % 3), m.F(t, (k + 2) % 3)};
}

bool convex(const TriMesh& m, const std::vector<int>& q) {
  Vec3 normal = Vec3::Zero();
  for (int k = 0; k < 4; ++k) normal += m.vertex(q[k]).cross(m.vertex(q[(k + 1) % 4]));
  for (int k = 0; k < 4; ++k) {
    const Vec3 a = m.vertex(q[k]), b = m.vertex(q[(k + 1) % 4]), c = m.vertex(q[(k + 2) % 4]);
    if ((b - a).cross(c - b).dot(normal) <= 0) return false;
  }
  return true;
}

Vec3 normal_of(const TriMesh& m, int t) {
  return (m.vertex(m.F(t, 1)) - m.vertex(m.F(t, 0)))
      .cross(m.vertex(m.F(t, 2)) - m.vertex(m.F(t, 0)))
      .normalized();
}

/// Σ over the four corners of |angle − 90°| (radians).
double right_angle_defect(const TriMesh& m, const std::vector<int>& q) {
  double sum = 0;
  for (int k = 0; k < 4; ++k) {
    const Vec3 p = m.vertex(q[k]);
    const Vec3 a = m.vertex(q[(k + 3) % 4]) - p, b = m.vertex(q[(k + 1) % 4]) - p;
    sum += std::abs(std::atan2(a.cross(b).norm(), a.dot(b)) - 1.5707963267948966);
  }
  return sum;
}

}  // namespace

RecoveredQuads recover_quads(const TriMesh& m) {
  const TriangleAdjacency adj = build_triangle_adjacency(m.F, m.num_vertices());
  const int nf = m.num_faces();
  auto opposite = [&](int t, int k) {
    const int g = adj.neighbor[t][k];
    return m.F(g, (adj.neighbor_edge[t][k] + 2) % 3);
  };
  std::vector<int> partner(nf, -1);
  RecoveredQuads r;
  std::vector<std::pair<double, std::array<int, 2>>> candidates;
  for (int t = 0; t < nf; ++t)
    for (int k = 0; k < 3; ++k) {
      const int g = adj.neighbor[t][k];
      if (partner[t] >= 0 || g < t || partner[g] >= 0) continue;
      const std::vector<int> q = pair_quad(m, t, k, opposite(t, k));
      const double fold = std::acos(std::clamp(normal_of(m, t).dot(normal_of(m, g)), -1.0, 1.0));
      if (convex(m, q)) candidates.push_back({fold + 0.01 * right_angle_defect(m, q), {t, k}});
    }
  std::sort(candidates.begin(), candidates.end());
  for (const auto& [score, tk] : candidates) {
    const int t = tk[0], g = adj.neighbor[t][tk[1]];
    if (partner[t] >= 0 || partner[g] >= 0) continue;
    partner[t] = g, partner[g] = t;
    ++r.greedy;
  }
  // Augmenting paths (breadth-first, alternating unpaired / paired adjacencies) from each
  // triangle still alone: a wrong greedy pair that isolated a triangle is re-paired along the
  // shortest such path. No blossom shrinking: a path found is checked to visit no triangle twice
  // before it is applied.
  std::vector<int> from(nf), odd_stamp(nf, -1), even_stamp(nf, -1);
  for (int pass = 0, tag = 0; pass < 4; ++pass)
    for (int t = 0; t < nf; ++t) {
      if (partner[t] >= 0) continue;
      ++tag;
      std::deque<int> queue{t};
      even_stamp[t] = tag;
      int free_end = -1;
      while (!queue.empty() && free_end < 0) {
        const int x = queue.front();
        queue.pop_front();
        for (int k = 0; k < 3 && free_end < 0; ++k) {
          const int y = adj.neighbor[x][k];
          if (y < 0 || y == t || odd_stamp[y] == tag || partner[x] == y) continue;
          odd_stamp[y] = tag;
          from[y] = x;
          if (partner[y] < 0) {
            free_end = y;
          } else if (even_stamp[partner[y]] != tag) {
            even_stamp[partner[y]] = tag;
            queue.push_back(partner[y]);
          }
        }
      }
      if (free_end < 0) continue;
      std::vector<std::array<int, 2>> path;  // new pairs (even, odd)
      std::vector<int> on_path{free_end};
      bool simple = true;
      for (int y = free_end;;) {
        const int x = from[y];
        path.push_back({x, y});
        on_path.push_back(x);
        if (x == t) break;
        y = partner[x];
        on_path.push_back(y);
        if (on_path.size() > static_cast<size_t>(nf)) break;
      }
      std::sort(on_path.begin(), on_path.end());
      simple = std::adjacent_find(on_path.begin(), on_path.end()) == on_path.end() &&
               path.back()[0] == t;
      if (!simple) continue;
      for (const auto& [x, y] : path) partner[x] = y, partner[y] = x;
      ++r.augmented;
    }
  r.mesh.V = m.V;
  for (int t = 0; t < nf; ++t) {
    const int g = partner[t];
    if (g < 0) {
      r.mesh.faces.push_back({m.F(t, 0), m.F(t, 1), m.F(t, 2)});
      ++r.triangles;
    } else if (t < g) {
      int k = 0;
      while (adj.neighbor[t][k] != g) ++k;
      r.mesh.faces.push_back(pair_quad(m, t, k, opposite(t, k)));
    }
  }
  return r;
}

}  // namespace gridshell
