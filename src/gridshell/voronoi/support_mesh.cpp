#include "gridshell/voronoi/support_mesh.h"

#include <algorithm>
#include <cmath>

#include "gridshell/core/error.h"

namespace gridshell {

SupportMesh make_support_mesh(const TriMesh& rest, const TriMesh& deformed) {
  if (rest.num_vertices() != deformed.num_vertices() || rest.num_faces() != deformed.num_faces() ||
      rest.F != deformed.F)
    throw Error("tessellation", "the deformed surface must have the connectivity of the rest one");
  if (!rest.V.allFinite() || !deformed.V.allFinite())
    throw Error("tessellation", "surface has non-finite coordinates");
  if (rest.num_faces() == 0) throw Error("tessellation", "surface has no triangles");
  const int n = rest.num_vertices();
  for (int f = 0; f < rest.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (rest.F(f, k) < 0 || rest.F(f, k) >= n)
        throw Error("tessellation", "triangle index out of range");
  SupportMesh m;
  m.rest = rest;
  m.deformed = deformed;
  m.parent.resize(rest.num_faces());
  m.parent_bary.assign(rest.num_faces(), Eigen::Matrix3d::Identity());
  for (int f = 0; f < rest.num_faces(); ++f) m.parent[f] = f;
  m.origin.resize(n);
  for (int v = 0; v < n; ++v) m.origin[v] = {v, v};
  return m;
}

namespace {
std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

std::array<int, 2> midpoint_origin(const std::array<int, 2>& a, const std::array<int, 2>& b) {
  if (a[0] < 0 || b[0] < 0) return {-1, -1};
  int u[4] = {a[0], a[1], b[0], b[1]};
  std::sort(u, u + 4);
  int* e = std::unique(u, u + 4);
  const long k = e - u;
  if (k == 2) return {u[0], u[1]};
  return {-1, -1};  // k == 1 cannot happen for distinct vertices; k >= 3: inside a triangle
}
}  // namespace

int refine_support_mesh(SupportMesh& m, const std::function<bool(int, int)>& split,
                        std::vector<int>* source) {
  const int nf = m.rest.num_faces();
  // The edges to split, sorted by key (the midpoints are numbered in that order), each with the
  // face sides (3 f + k) it is on, so that every side finds its midpoint without a search (a
  // binary search per side was half of this function). Only the split edges are sorted: a pass
  // that splits few edges (the extraction's border refinement) stays cheap.
  std::vector<std::pair<std::uint64_t, int>> sides;
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      int a = m.rest.F(f, k), b = m.rest.F(f, (k + 1) % 3);
      if (a > b) std::swap(a, b);
      if (split(a, b)) sides.emplace_back(edge_key(a, b), 3 * f + k);
    }
  std::sort(sides.begin(), sides.end());
  std::vector<int> side_mid(sides.empty() ? 0 : 3 * static_cast<std::size_t>(nf), -1);
  std::vector<Vec3> new_rest, new_def;
  int nv = m.rest.num_vertices();
  const int nv0 = nv;
  for (std::size_t i = 0; i < sides.size(); ++i) {
    const std::uint64_t key = sides[i].first;
    if (i == 0 || key != sides[i - 1].first) {
      const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xFFFFFFFFu);
      ++nv;
      new_rest.push_back(0.5 * (m.rest.vertex(a) + m.rest.vertex(b)));
      new_def.push_back(0.5 * (m.deformed.vertex(a) + m.deformed.vertex(b)));
      m.origin.push_back(midpoint_origin(m.origin[a], m.origin[b]));
    }
    side_mid[sides[i].second] = nv - 1;
  }
  const int added = nv - nv0;
  if (added == 0) {
    if (source) {
      source->resize(nf);
      for (int f = 0; f < nf; ++f) (*source)[f] = f;
    }
    return 0;
  }
  if (source) source->clear();
  m.rest.V.conservativeResize(nv, 3);
  m.deformed.V.conservativeResize(nv, 3);
  for (int i = 0; i < added; ++i) {
    m.rest.V.row(nv0 + i) = new_rest[i].transpose();
    m.deformed.V.row(nv0 + i) = new_def[i].transpose();
  }
  std::vector<std::array<int, 3>> tris;
  std::vector<int> parent;
  std::vector<Eigen::Matrix3d> pbary;
  tris.reserve(static_cast<std::size_t>(nf) * 2);
  for (int f = 0; f < nf; ++f) {
    int id[6];
    Vec3 bary[6];
    for (int k = 0; k < 3; ++k) {
      id[k] = m.rest.F(f, k);
      bary[k] = m.parent_bary[f].row(k).transpose();
    }
    int marked = 0;
    for (int k = 0; k < 3; ++k) {
      id[3 + k] = side_mid[3 * static_cast<std::size_t>(f) + k];
      bary[3 + k] = 0.5 * (bary[k] + bary[(k + 1) % 3]);
      if (id[3 + k] >= 0) ++marked;
    }
    auto emit = [&](int p, int q, int r) {
      tris.push_back({id[p], id[q], id[r]});
      parent.push_back(m.parent[f]);
      if (source) source->push_back(f);
      Eigen::Matrix3d B;
      B.row(0) = bary[p].transpose();
      B.row(1) = bary[q].transpose();
      B.row(2) = bary[r].transpose();
      pbary.push_back(B);
    };
    if (marked == 0) {
      emit(0, 1, 2);
    } else if (marked == 3) {
      emit(0, 3, 5);
      emit(3, 1, 4);
      emit(5, 4, 2);
      emit(3, 4, 5);
    } else if (marked == 1) {
      int k = 0;
      while (id[3 + k] < 0) ++k;
      const int c0 = k, c1 = (k + 1) % 3, c2 = (k + 2) % 3, mk = 3 + k;
      emit(c0, mk, c2);
      emit(mk, c1, c2);
    } else {
      // Two marked edges: rotate so that the unmarked one is (c1, c2); marked (c0,c1), (c2,c0).
      int u = 0;
      while (id[3 + u] >= 0) ++u;
      const int c1 = u, c2 = (u + 1) % 3, c0 = (u + 2) % 3;
      const int m01 = 3 + c0, m20 = 3 + c2;
      emit(c0, m01, m20);
      const double d1 = (m.deformed.vertex(id[m01]) - m.deformed.vertex(id[c2])).squaredNorm();
      const double d2 = (m.deformed.vertex(id[c1]) - m.deformed.vertex(id[m20])).squaredNorm();
      if (d1 <= d2) {
        emit(m01, c1, c2);
        emit(m01, c2, m20);
      } else {
        emit(m01, c1, m20);
        emit(m20, c1, c2);
      }
    }
  }
  m.rest.F.resize(static_cast<int>(tris.size()), 3);
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) m.rest.F(static_cast<int>(t), k) = tris[t][k];
  m.deformed.F = m.rest.F;
  m.parent = std::move(parent);
  m.parent_bary = std::move(pbary);
  return added;
}

int refine_to_length(SupportMesh& m, double max_edge, std::vector<int>* source) {
  if (!(max_edge > 0) || !std::isfinite(max_edge))
    throw Error("tessellation", "support edge length must be positive");
  const double h2 = max_edge * max_edge;
  int passes = 0;
  if (source) {
    source->resize(m.rest.num_faces());
    for (int f = 0; f < m.rest.num_faces(); ++f) (*source)[f] = f;
  }
  std::vector<int> step;
  for (; passes < 40; ++passes) {
    const int n = refine_support_mesh(
        m,
        [&](int a, int b) {
          return (m.deformed.vertex(a) - m.deformed.vertex(b)).squaredNorm() > h2;
        },
        source ? &step : nullptr);
    if (n == 0) break;
    if (source) {
      std::vector<int> composed(step.size());
      for (std::size_t f = 0; f < step.size(); ++f) composed[f] = (*source)[step[f]];
      *source = std::move(composed);
    }
  }
  return passes;
}

std::pair<int, Vec3> to_original(const SupportMesh& m, int t, const Vec3& b) {
  Vec3 w = m.parent_bary[t].transpose() * b;
  w = w.cwiseMax(0.0);
  const double s = w.sum();
  if (s > 0) w /= s;
  return {m.parent[t], w};
}

}  // namespace gridshell
