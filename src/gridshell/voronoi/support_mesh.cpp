#include "gridshell/voronoi/support_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

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
  m.original = rest.F;
  m.parent.resize(rest.num_faces());
  for (int f = 0; f < rest.num_faces(); ++f) m.parent[f] = f;
  m.origin.resize(n);
  for (int v = 0; v < n; ++v) m.origin[v] = {v, v};
  m.origin_weights.assign(n, Vec3(1, 0, 0));
  m.origin_face.assign(n, -1);
  m.split_end.assign(n, -1);
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

namespace {

/// Barycentric coordinates of refined vertex v in original triangle f (which must hold it).
/// Exact: the entries are the vertex's dyadic weights placed at their corners.
Vec3 weights_in(const SupportMesh& m, int v, int f) {
  const auto [a, b] = m.origin[v];
  if (a < 0) return m.origin_weights[v];  // inside a triangle: f itself
  Vec3 w = Vec3::Zero();
  bool put_a = false, put_b = a == b;  // each weight at one corner (a corner id repeated: the first)
  for (int k = 0; k < 3; ++k) {
    const int c = m.original(f, k);
    if (c == a && !put_a) {
      w(k) = a == b ? 1.0 : m.origin_weights[v](0);
      put_a = true;
    } else if (c == b && !put_b) {
      w(k) = m.origin_weights[v](1);
      put_b = true;
    }
  }
  return w;
}

/// The new vertex v's place on the original mesh: the midpoint of a and b, which lie in original
/// triangle f (v's entries of origin, origin_weights and origin_face are set).
void set_midpoint_origin(SupportMesh& m, int v, int a, int b, int f) {
  const std::array<int, 2> o = midpoint_origin(m.origin[a], m.origin[b]);
  const Vec3 w = 0.5 * (weights_in(m, a, f) + weights_in(m, b, f));
  Vec3 ow(1, 0, 0);
  if (o[0] < 0) {
    ow = w;
  } else {
    for (int k = 0; k < 3; ++k) {
      if (m.original(f, k) == o[0]) ow(0) = w(k);
      if (m.original(f, k) == o[1]) ow(1) = w(k);
    }
  }
  m.origin[v] = o;
  m.origin_weights[v] = ow;
  m.origin_face[v] = o[0] < 0 ? f : -1;
}

/// Sub-triangles (corner slots 0–2, midpoints 3 + k of side k) of a triangle by its split sides.
int split_pattern(const int id[6], const SupportMesh& m, int out[4][3]) {
  int marked = 0;
  for (int k = 0; k < 3; ++k)
    if (id[3 + k] >= 0) ++marked;
  const auto put = [&](int i, int p, int q, int r) {
    out[i][0] = p;
    out[i][1] = q;
    out[i][2] = r;
  };
  if (marked == 0) {
    put(0, 0, 1, 2);
    return 1;
  }
  if (marked == 3) {
    put(0, 0, 3, 5);
    put(1, 3, 1, 4);
    put(2, 5, 4, 2);
    put(3, 3, 4, 5);
    return 4;
  }
  if (marked == 1) {
    int k = 0;
    while (id[3 + k] < 0) ++k;
    const int c0 = k, c1 = (k + 1) % 3, c2 = (k + 2) % 3, mk = 3 + k;
    put(0, c0, mk, c2);
    put(1, mk, c1, c2);
    return 2;
  }
  // Two marked edges: rotate so that the unmarked one is (c1, c2); marked (c0,c1), (c2,c0).
  int u = 0;
  while (id[3 + u] >= 0) ++u;
  const int c1 = u, c2 = (u + 1) % 3, c0 = (u + 2) % 3;
  const int m01 = 3 + c0, m20 = 3 + c2;
  put(0, c0, m01, m20);
  const double d1 = (m.deformed.vertex(id[m01]) - m.deformed.vertex(id[c2])).squaredNorm();
  const double d2 = (m.deformed.vertex(id[c1]) - m.deformed.vertex(id[m20])).squaredNorm();
  if (d1 <= d2) {
    put(1, m01, c1, c2);
    put(2, m01, c2, m20);
  } else {
    put(1, m01, c1, m20);
    put(2, m20, c1, c2);
  }
  return 3;
}

}  // namespace

int refine_support_mesh(SupportMesh& m, const std::function<bool(int, int)>& split,
                        std::vector<int>* source) {
  const int nf = m.rest.num_faces();
  // The edges to split, sorted by key (the midpoints are numbered in that order), each with the
  // face sides (3 f + k) it is on, so that every side finds its midpoint without a search (a
  // binary search per side was half of this function). Only the split edges are sorted: a pass
  // that splits few edges (the extraction's border refinement) stays cheap. The (key, side)
  // pairs are distinct, so their sorted order, and so every number below, does not depend on the
  // threads that found them.
  using Side = std::pair<std::uint64_t, int>;
  tbb::enumerable_thread_specific<std::vector<Side>> found;
  tbb::parallel_for(tbb::blocked_range<int>(0, nf, 4096), [&](const tbb::blocked_range<int>& r) {
    std::vector<Side>& mine = found.local();
    for (int f = r.begin(); f < r.end(); ++f)
      for (int k = 0; k < 3; ++k) {
        int a = m.rest.F(f, k), b = m.rest.F(f, (k + 1) % 3);
        if (a > b) std::swap(a, b);
        if (split(a, b)) mine.emplace_back(edge_key(a, b), 3 * f + k);
      }
  });
  std::vector<Side> sides;
  for (const auto& mine : found) sides.insert(sides.end(), mine.begin(), mine.end());
  if (sides.empty()) {
    if (source) {
      source->resize(nf);
      for (int f = 0; f < nf; ++f) (*source)[f] = f;
    }
    return 0;
  }
  tbb::parallel_sort(sides.begin(), sides.end());
  // The midpoint of each side's edge: new vertices numbered in key order.
  const int nv0 = m.rest.num_vertices();
  std::vector<int> mid(sides.size());
  int added = 0;
  for (std::size_t i = 0; i < sides.size(); ++i) {
    if (i == 0 || sides[i].first != sides[i - 1].first) ++added;
    mid[i] = nv0 + added - 1;
  }
  m.rest.V.conservativeResize(nv0 + added, 3);
  m.deformed.V.conservativeResize(nv0 + added, 3);
  m.origin.resize(nv0 + added);
  m.origin_weights.resize(nv0 + added);
  m.origin_face.resize(nv0 + added);
  m.split_end.resize(nv0 + added);
  std::vector<int> side_mid(3 * static_cast<std::size_t>(nf), -1);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, sides.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        side_mid[sides[i].second] = mid[i];
                        if (i > 0 && sides[i].first == sides[i - 1].first) continue;
                        const std::uint64_t key = sides[i].first;
                        const int a = static_cast<int>(key >> 32),
                                  b = static_cast<int>(key & 0xFFFFFFFFu), v = mid[i];
                        m.rest.V.row(v) = 0.5 * (m.rest.V.row(a) + m.rest.V.row(b));
                        m.deformed.V.row(v) = 0.5 * (m.deformed.V.row(a) + m.deformed.V.row(b));
                        set_midpoint_origin(m, v, a, b, m.parent[sides[i].second / 3]);
                        m.split_end[v] = a;
                      }
                    });
  // Sub-triangles, counted first so that the new arrays are allocated once.
  const auto corners = [&](int f, int id[6]) {
    for (int k = 0; k < 3; ++k) {
      id[k] = m.rest.F(f, k);
      id[3 + k] = side_mid[3 * static_cast<std::size_t>(f) + k];
    }
  };
  std::vector<int> first(nf + 1, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, nf, 4096), [&](const tbb::blocked_range<int>& r) {
    int id[6], pattern[4][3];
    for (int f = r.begin(); f < r.end(); ++f) {
      corners(f, id);
      first[f + 1] = split_pattern(id, m, pattern);
    }
  });
  for (int f = 0; f < nf; ++f) first[f + 1] += first[f];
  Triangles F(first[nf], 3);
  std::vector<int> parent(first[nf]);
  if (source) source->resize(first[nf]);
  tbb::parallel_for(tbb::blocked_range<int>(0, nf, 4096), [&](const tbb::blocked_range<int>& r) {
    int id[6], pattern[4][3];
    for (int f = r.begin(); f < r.end(); ++f) {
      corners(f, id);
      const int n = split_pattern(id, m, pattern);
      for (int i = 0; i < n; ++i) {
        const int t = first[f] + i;
        for (int k = 0; k < 3; ++k) F(t, k) = id[pattern[i][k]];
        parent[t] = m.parent[f];
        if (source) (*source)[t] = f;
      }
    }
  });
  m.rest.F = std::move(F);
  m.deformed.F = m.rest.F;
  m.parent = std::move(parent);
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
  const int f = m.parent[t];
  Eigen::Matrix3d B;
  for (int k = 0; k < 3; ++k) B.row(k) = weights_in(m, m.rest.F(t, k), f).transpose();
  Vec3 w = B.transpose() * b;
  w = w.cwiseMax(0.0);
  const double s = w.sum();
  if (s > 0) w /= s;
  return {m.parent[t], w};
}

}  // namespace gridshell
