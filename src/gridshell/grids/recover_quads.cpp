#include "gridshell/grids/recover_quads.h"

#include <algorithm>
#include <array>
#include <cmath>
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

}  // namespace

RecoveredQuads recover_quads(const TriMesh& m) {
  const TriangleAdjacency adj = build_triangle_adjacency(m.F, m.num_vertices());
  const int nf = m.num_faces();
  // The local edge opposite the largest angle: edge k runs from corner k to corner k + 1, so it
  // faces corner k + 2.
  std::vector<int> named(nf, 0);
  for (int t = 0; t < nf; ++t) {
    double best = -1;
    for (int k = 0; k < 3; ++k) {
      const Vec3 c = m.vertex(m.F(t, (k + 2) % 3));
      const Vec3 a = m.vertex(m.F(t, k)) - c, b = m.vertex(m.F(t, (k + 1) % 3)) - c;
      const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
      if (angle > best) best = angle, named[t] = k;
    }
  }
  RecoveredQuads r;
  r.mesh.V = m.V;
  std::vector<char> done(nf, 0);
  auto opposite = [&](int t, int k) {
    const int g = adj.neighbor[t][k];
    return m.F(g, (adj.neighbor_edge[t][k] + 2) % 3);
  };
  for (int t = 0; t < nf; ++t) {
    const int k = named[t], g = adj.neighbor[t][k];
    if (done[t] || g < 0 || done[g] || named[g] != adj.neighbor_edge[t][k]) continue;
    r.mesh.faces.push_back(pair_quad(m, t, k, opposite(t, k)));
    done[t] = done[g] = 1;
    ++r.mutual;
  }
  std::vector<std::pair<double, std::array<int, 2>>> candidates;
  for (int t = 0; t < nf; ++t)
    for (int k = 0; k < 3; ++k) {
      const int g = adj.neighbor[t][k];
      if (done[t] || g < t || done[g]) continue;
      if (!convex(m, pair_quad(m, t, k, opposite(t, k)))) continue;
      candidates.push_back({-normal_of(m, t).dot(normal_of(m, g)), {t, k}});
    }
  std::sort(candidates.begin(), candidates.end());
  for (const auto& [score, tk] : candidates) {
    const int t = tk[0], k = tk[1], g = adj.neighbor[t][k];
    if (done[t] || done[g]) continue;
    r.mesh.faces.push_back(pair_quad(m, t, k, opposite(t, k)));
    done[t] = done[g] = 1;
    ++r.greedy;
  }
  for (int t = 0; t < nf; ++t)
    if (!done[t]) {
      r.mesh.faces.push_back({m.F(t, 0), m.F(t, 1), m.F(t, 2)});
      ++r.triangles;
    }
  return r;
}

}  // namespace gridshell
