#include "gridshell/mesh/topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "gridshell/core/error.h"

namespace gridshell {

int Topology::find_edge(int a, int b) const {
  std::array<int, 2> key{std::min(a, b), std::max(a, b)};
  auto it = std::lower_bound(edges.begin(), edges.end(), key);
  if (it == edges.end() || *it != key) return -1;
  return static_cast<int>(it - edges.begin());
}

namespace {

/// The faces of a polygon mesh, and those of a triangle mesh without a polygon copy: f.size(),
/// f[k] for face fi = faces[fi].
struct PolyFaces {
  const std::vector<std::vector<int>>& faces;
  int size() const { return static_cast<int>(faces.size()); }
  const std::vector<int>& operator[](int f) const { return faces[f]; }
};
struct TriFaces {
  const Triangles& F;
  int size() const { return static_cast<int>(F.rows()); }
  std::array<int, 3> operator[](int f) const { return {F(f, 0), F(f, 1), F(f, 2)}; }
};

template <typename Faces>
bool ids_in_range(const Faces& faces, int nv) {
  for (int fi = 0; fi < faces.size(); ++fi) {
    const auto& f = faces[fi];
    for (std::size_t k = 0; k < f.size(); ++k)
      if (f[k] < 0 || f[k] >= nv) return false;
  }
  return true;
}

/// The boundary half-edges (edges of one face), oriented as in their face, chained into loops.
template <typename Faces>
void add_boundary_loops(const Faces& faces, Topology& t) {
  std::multimap<int, int> next;  // from vertex -> to vertex
  for (int fi = 0; fi < faces.size(); ++fi) {
    const auto& f = faces[fi];
    for (std::size_t k = 0; k < f.size(); ++k) {
      const int e = t.face_edges[fi][k];
      if (t.edge_faces[e].size() == 1) next.emplace(f[k], f[(k + 1) % f.size()]);
    }
  }
  while (!next.empty()) {
    auto it = next.begin();
    const int start = it->first;
    std::vector<int> loop{start};
    int cur = it->second;
    next.erase(it);
    while (cur != start) {
      loop.push_back(cur);
      auto nx = next.find(cur);
      if (nx == next.end()) break;  // open chain (inconsistent orientation): stop here
      cur = nx->second;
      next.erase(nx);
    }
    t.boundary_loops.push_back(std::move(loop));
  }
}

/// Any vertex ids (out-of-range ones included, for `info`'s checks): edges sorted and looked up
/// by binary search.
template <typename Faces>
Topology build_any(const Faces& faces, int nv) {
  Topology t;
  const int nf = faces.size();
  std::vector<std::array<int, 2>> all;
  for (int fi = 0; fi < nf; ++fi) {
    const auto& f = faces[fi];
    for (std::size_t k = 0; k < f.size(); ++k) {
      int a = f[k], b = f[(k + 1) % f.size()];
      all.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  t.edges = std::move(all);
  t.edge_faces.assign(t.edges.size(), {});
  t.face_edges.resize(nf);
  t.vertex_faces.assign(nv, {});
  for (int fi = 0; fi < nf; ++fi) {
    const auto& f = faces[fi];
    t.face_edges[fi].resize(f.size());
    for (std::size_t k = 0; k < f.size(); ++k) {
      int e = t.find_edge(f[k], f[(k + 1) % f.size()]);
      t.face_edges[fi][k] = e;
      auto& ef = t.edge_faces[e];
      if (std::find(ef.begin(), ef.end(), fi) == ef.end()) ef.push_back(fi);
      if (f[k] >= 0 && f[k] < nv) t.vertex_faces[f[k]].push_back(fi);
    }
  }
  t.vertex_neighbors.assign(nv, {});
  t.on_boundary.assign(nv, 0);
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    auto [a, b] = t.edges[e];
    if (a < 0 || b >= nv) continue;
    t.vertex_neighbors[a].push_back(b);
    t.vertex_neighbors[b].push_back(a);
    if (t.edge_faces[e].size() == 1) t.on_boundary[a] = t.on_boundary[b] = 1;
  }
  for (auto& n : t.vertex_neighbors) std::sort(n.begin(), n.end());
  add_boundary_loops(faces, t);
  return t;
}

/// The same result for ids in 0 … nv−1, in linear time but for tiny sorts: the edges grouped by
/// their smaller vertex (counting sort), each group sorted; an edge is found by a scan of its
/// group, and every per-vertex list is sized before it is filled.
template <typename Faces>
Topology build_in_range(const Faces& faces, int nv) {
  Topology t;
  const int nf = faces.size();
  std::vector<int> start(static_cast<std::size_t>(nv) + 1, 0);
  std::vector<int> corners(static_cast<std::size_t>(nv), 0);  // corners per vertex
  for (int fi = 0; fi < nf; ++fi) {
    const auto& f = faces[fi];
    for (std::size_t k = 0; k < f.size(); ++k) {
      ++start[std::min(f[k], f[(k + 1) % f.size()]) + 1];
      ++corners[f[k]];
    }
  }
  for (int v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<int> larger(static_cast<std::size_t>(start[nv]));
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int fi = 0; fi < nf; ++fi) {
      const auto& f = faces[fi];
      for (std::size_t k = 0; k < f.size(); ++k) {
        const int a = f[k], b = f[(k + 1) % f.size()];
        larger[fill[std::min(a, b)]++] = std::max(a, b);
      }
    }
  }
  // Per smaller vertex a: its edges' larger ends sorted, duplicates removed; first[a] is a's
  // first edge.
  std::vector<int> first(static_cast<std::size_t>(nv) + 1, 0);
  t.edges.reserve(static_cast<std::size_t>(start[nv]) / 2 + 1);
  for (int a = 0; a < nv; ++a) {
    first[a] = static_cast<int>(t.edges.size());
    const auto begin = larger.begin() + start[a], end = larger.begin() + start[a + 1];
    std::sort(begin, end);
    for (auto it = begin; it != end; ++it)
      if (it == begin || *it != *(it - 1)) t.edges.push_back({a, *it});
  }
  first[nv] = static_cast<int>(t.edges.size());
  const auto edge = [&](int a, int b) {
    if (a > b) std::swap(a, b);
    int e = first[a];
    while (t.edges[e][1] != b) ++e;
    return e;
  };
  t.edge_faces.assign(t.edges.size(), {});
  for (auto& ef : t.edge_faces) ef.reserve(2);
  t.face_edges.resize(nf);
  t.vertex_faces.assign(nv, {});
  for (int v = 0; v < nv; ++v) t.vertex_faces[v].reserve(corners[v]);
  for (int fi = 0; fi < nf; ++fi) {
    const auto& f = faces[fi];
    t.face_edges[fi].resize(f.size());
    for (std::size_t k = 0; k < f.size(); ++k) {
      const int e = edge(f[k], f[(k + 1) % f.size()]);
      t.face_edges[fi][k] = e;
      auto& ef = t.edge_faces[e];
      if (ef.empty() || ef.back() != fi) ef.push_back(fi);  // faces come in order
      t.vertex_faces[f[k]].push_back(fi);
    }
  }
  std::vector<int> degree(static_cast<std::size_t>(nv), 0);
  for (const auto& [a, b] : t.edges) ++degree[a], ++degree[b];
  t.vertex_neighbors.assign(nv, {});
  for (int v = 0; v < nv; ++v) t.vertex_neighbors[v].reserve(degree[v]);
  t.on_boundary.assign(nv, 0);
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    const auto [a, b] = t.edges[e];
    t.vertex_neighbors[a].push_back(b);
    t.vertex_neighbors[b].push_back(a);
    if (t.edge_faces[e].size() == 1) t.on_boundary[a] = t.on_boundary[b] = 1;
  }
  for (auto& n : t.vertex_neighbors) std::sort(n.begin(), n.end());
  add_boundary_loops(faces, t);
  return t;
}

template <typename Faces>
Topology build(const Faces& faces, int nv) {
  return ids_in_range(faces, nv) ? build_in_range(faces, nv) : build_any(faces, nv);
}

}  // namespace

Topology build_topology(const PolyMesh& mesh) {
  return build(PolyFaces{mesh.faces}, mesh.num_vertices());
}

Topology build_topology(const TriMesh& mesh) {
  return build(TriFaces{mesh.F}, mesh.num_vertices());
}

std::vector<int> boundary_vertices(const Topology& topo) {
  std::vector<int> out;
  for (int v = 0; v < static_cast<int>(topo.on_boundary.size()); ++v)
    if (topo.on_boundary[v]) out.push_back(v);
  return out;
}

TriangleAdjacency build_triangle_adjacency(const Triangles& F, int nv) {
  const int nt = static_cast<int>(F.rows());
  // Half-edges 3t+k (F(t,k) → F(t,k+1)) grouped by their origin vertex (counting sort: linear).
  std::vector<int> start(nv + 1, 0);
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) ++start[F(t, k) + 1];
  for (int v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<int> from(static_cast<std::size_t>(nt) * 3), to(from.size());
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k) {
        const int q = fill[F(t, k)]++;
        from[q] = 3 * t + k;
        to[q] = F(t, (k + 1) % 3);
      }
  }
  TriangleAdjacency adj;
  adj.neighbor.assign(nt, {-1, -1, -1});
  adj.neighbor_edge.assign(nt, {-1, -1, -1});
  // Each half-edge's twin, found in parallel; what a half-edge is (inner, boundary, or a problem)
  // is then read in half-edge order, so the error a bad mesh gets is the serial walk's.
  enum : char { kInner, kBoundary, kNonManifold, kMisoriented };
  std::vector<char> kind(static_cast<std::size_t>(nt) * 3, kInner);
  tbb::parallel_for(tbb::blocked_range<int>(0, nt, 8192), [&](const tbb::blocked_range<int>& r) {
    for (int t = r.begin(); t < r.end(); ++t)
      for (int k = 0; k < 3; ++k) {
        const int a = F(t, k), b = F(t, (k + 1) % 3);
        int same = 0, twin = -1, twins = 0;
        for (int q = start[a]; q < start[a + 1]; ++q) same += to[q] == b;
        for (int q = start[b]; q < start[b + 1]; ++q)
          if (to[q] == a) {
            twin = from[q];
            ++twins;
          }
        char& h = kind[3 * static_cast<std::size_t>(t) + k];
        if (same + twins > 2)
          h = kNonManifold;
        else if (same > 1)
          h = kMisoriented;
        else if (twin >= 0) {
          adj.neighbor[t][k] = twin / 3;
          adj.neighbor_edge[t][k] = twin % 3;
        } else
          h = kBoundary;
      }
  });
  std::vector<int> out(nv, -1);  // boundary half-edge leaving each vertex
  for (int h = 0; h < 3 * nt; ++h) {
    if (kind[h] == kNonManifold)
      throw Error("surface", "non-manifold edge (more than two triangles)");
    if (kind[h] == kMisoriented)
      throw Error("surface", "inconsistently oriented triangles (flip some faces)");
    if (kind[h] != kBoundary) continue;
    const int a = F(h / 3, h % 3);
    if (out[a] >= 0) throw Error("surface", "non-manifold boundary vertex (two boundaries touch)");
    out[a] = h;
  }
  // Boundary loops from the smallest unused vertex with a boundary half-edge leaving it.
  std::vector<char> used(nv, 0);
  for (int v = 0; v < nv; ++v) {
    if (out[v] < 0 || used[v]) continue;
    std::vector<int> loop;
    std::vector<std::array<int, 2>> edges;
    int u = v;
    while (!used[u]) {
      used[u] = 1;
      const int h = out[u];
      if (h < 0) throw Error("surface", "open boundary chain (non-manifold boundary)");
      loop.push_back(u);
      edges.push_back({h / 3, h % 3});
      u = F(h / 3, (h % 3 + 1) % 3);
    }
    if (u != v) throw Error("surface", "non-manifold boundary");
    adj.boundary_loops.push_back(std::move(loop));
    adj.boundary_loop_edges.push_back(std::move(edges));
  }
  return adj;
}

PolyMesh largest_component(const PolyMesh& mesh) {
  return largest_component(mesh, std::vector<int>(mesh.num_vertices(), 0));
}

PolyMesh largest_component(const PolyMesh& mesh, const std::vector<int>& piece) {
  DisjointSets sets(mesh.num_vertices());
  for (const auto& f : mesh.faces)
    for (size_t k = 1; k < f.size(); ++k) sets.unite(f[0], f[k]);
  std::vector<int> faces_of(mesh.num_vertices(), 0);
  for (const auto& f : mesh.faces)
    if (!f.empty()) ++faces_of[sets.find(f[0])];
  // Per piece, the root of its largest component (the smallest root among the largest).
  std::map<int, int> best;
  for (int r = 0; r < mesh.num_vertices(); ++r) {
    if (faces_of[r] == 0) continue;
    auto [it, fresh] = best.emplace(piece[r], r);
    if (!fresh && faces_of[r] > faces_of[it->second]) it->second = r;
  }
  std::vector<char> keep(mesh.num_vertices(), 0);
  for (const auto& [p, r] : best) keep[r] = 1;
  PolyMesh out;
  std::vector<int> index(mesh.num_vertices(), -1);
  for (const auto& f : mesh.faces)
    if (!f.empty() && keep[sets.find(f[0])])
      for (int v : f) index[v] = 0;
  int count = 0;
  for (int& i : index)
    if (i == 0) i = count++;
  out.V.resize(count, 3);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (index[v] >= 0) out.V.row(index[v]) = mesh.V.row(v);
  for (const auto& f : mesh.faces) {
    if (f.empty() || !keep[sets.find(f[0])]) continue;
    std::vector<int> g;
    for (int v : f) g.push_back(index[v]);
    out.faces.push_back(std::move(g));
  }
  return out;
}

void remove_hanging_faces(PolyMesh& mesh) {
  for (bool removed = true; removed && mesh.faces.size() > 1;) {
    const Topology t = build_topology(mesh);
    removed = false;
    std::vector<std::vector<int>> kept;
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
      int shared = 0, held = 0;  // edges shared with other faces; corners other faces use
      for (int e : t.face_edges[f]) shared += t.edge_faces[e].size() > 1;
      for (int v : mesh.faces[f]) held += t.vertex_faces[v].size() > 1;
      if (shared == 1 && held <= 2)  // a flap: only the shared edge's two ends are held
        removed = true;
      else
        kept.push_back(mesh.faces[f]);
    }
    if (kept.empty()) return;  // every face hangs (one face, or two on an edge): kept
    mesh.faces = std::move(kept);
  }
}

int euler_characteristic(const PolyMesh& mesh, const Topology& topo) {
  int referenced = 0;
  for (const auto& vf : topo.vertex_faces) referenced += vf.empty() ? 0 : 1;
  return referenced - topo.num_edges() + mesh.num_faces();
}

std::vector<std::string> MeshProblems::describe() const {
  std::vector<std::string> out;
  auto add = [&](int n, const char* what) {
    if (n > 0) out.push_back(fmt::format("{} {}", n, what));
  };
  add(non_finite_coordinates, "vertices with NaN or infinite coordinates");
  add(bad_indices, "face indices out of range");
  add(small_faces, "faces with fewer than 3 vertices");
  add(repeated_corner_faces, "faces that use a vertex twice");
  add(degenerate_faces, "degenerate (zero-area) faces");
  add(non_manifold_edges, "non-manifold edges");
  add(non_manifold_vertices, "non-manifold vertices");
  add(inconsistent_orientation, "edges with inconsistent face orientation");
  add(duplicate_vertices, "duplicate vertices");
  add(unreferenced_vertices, "unreferenced vertices");
  return out;
}

std::vector<int> pinched_vertices(const PolyMesh& mesh) {
  const int nv = mesh.num_vertices();
  // Per vertex, its corners (one per face at it), each with the two other ends of its edges.
  std::vector<int> start(nv + 1, 0);
  for (const auto& f : mesh.faces)
    for (int v : f) ++start[v + 1];
  for (int v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::array<int, 2>> ends(start[nv]);
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (const auto& f : mesh.faces)
    for (std::size_t k = 0; k < f.size(); ++k)
      ends[fill[f[k]]++] = {f[(k + f.size() - 1) % f.size()], f[(k + 1) % f.size()]};
  std::vector<int> out;
  std::vector<std::pair<int, int>> by_end;  // (other end of an edge, corner), sorted
  std::vector<int> parent;
  for (int v = 0; v < nv; ++v) {
    const int d = start[v + 1] - start[v];
    if (d < 2) continue;
    by_end.clear();
    for (int c = 0; c < d; ++c)
      for (int e : ends[start[v] + c]) by_end.emplace_back(e, c);
    std::sort(by_end.begin(), by_end.end());
    parent.resize(d);
    std::iota(parent.begin(), parent.end(), 0);
    const auto root = [&](int c) {
      while (parent[c] != c) c = parent[c] = parent[parent[c]];
      return c;
    };
    int fans = d;  // corners sharing an edge at v are in one fan
    for (std::size_t i = 1; i < by_end.size(); ++i)
      if (by_end[i].first == by_end[i - 1].first) {
        const int a = root(by_end[i].second), b = root(by_end[i - 1].second);
        if (a != b) {
          parent[a] = b;
          --fans;
        }
      }
    if (fans > 1) out.push_back(v);
  }
  return out;
}

MeshProblems check_mesh(const PolyMesh& mesh, double degenerate_tolerance) {
  MeshProblems p;
  const int nv = mesh.num_vertices();
  for (int v = 0; v < nv; ++v)
    if (!mesh.V.row(v).allFinite()) ++p.non_finite_coordinates;

  // Keep only faces with valid indices for the topological checks.
  PolyMesh clean;
  clean.V = mesh.V;
  std::vector<char> used(nv, 0);
  for (const auto& f : mesh.faces) {
    bool bad = false;
    for (int v : f) bad |= (v < 0 || v >= nv);
    if (bad) {
      ++p.bad_indices;
      continue;
    }
    if (f.size() < 3) {
      ++p.small_faces;
      continue;
    }
    std::vector<int> s = f;
    std::sort(s.begin(), s.end());
    if (std::adjacent_find(s.begin(), s.end()) != s.end()) {
      ++p.repeated_corner_faces;
      continue;
    }
    for (int v : f) used[v] = 1;
    clean.faces.push_back(f);
  }
  for (int v = 0; v < nv; ++v) p.unreferenced_vertices += used[v] ? 0 : 1;

  const double diag = bbox_diagonal(mesh.V);
  const double tol = degenerate_tolerance * diag * diag;
  for (int f = 0; f < clean.num_faces(); ++f)
    if (!(polygon_area(clean, f) > tol)) ++p.degenerate_faces;

  Topology t = build_topology(clean);
  for (std::size_t e = 0; e < t.edges.size(); ++e) {
    const auto& ef = t.edge_faces[e];
    if (ef.size() > 2) ++p.non_manifold_edges;
    if (ef.size() == 2) {
      // Orientation: each face should walk the edge in opposite directions.
      auto dir = [&](int fi) {
        const auto& f = clean.faces[fi];
        for (std::size_t k = 0; k < f.size(); ++k)
          if (f[k] == t.edges[e][0] && f[(k + 1) % f.size()] == t.edges[e][1]) return 1;
        return -1;
      };
      if (dir(ef[0]) == dir(ef[1])) ++p.inconsistent_orientation;
    }
  }
  p.non_manifold_vertices = static_cast<int>(pinched_vertices(clean).size());
  // Exact duplicate positions.
  std::vector<int> order(nv);
  std::iota(order.begin(), order.end(), 0);
  auto less = [&](int a, int b) {
    for (int c = 0; c < 3; ++c)
      if (mesh.V(a, c) != mesh.V(b, c)) return mesh.V(a, c) < mesh.V(b, c);
    return false;
  };
  std::sort(order.begin(), order.end(), less);
  for (int i = 1; i < nv; ++i)
    if (!less(order[i - 1], order[i]) && !less(order[i], order[i - 1]) &&
        mesh.V.row(order[i]).allFinite())
      ++p.duplicate_vertices;
  return p;
}

int collapse_boundary_stubs(std::vector<std::vector<int>>& faces, const std::vector<Vec3>& position,
                            const std::vector<int>& rank, double min_length) {
  std::vector<std::tuple<double, int, int>> stubs;  // (length, removed, kept), shortest first
  for (const auto& f : faces)
    for (std::size_t k = 0; k < f.size(); ++k) {
      int a = f[k], b = f[(k + 1) % f.size()];
      if (rank[a] > rank[b]) std::swap(a, b);  // a goes into b
      if (rank[b] == 0 || rank[a] == 2) continue;
      const double l = (position[a] - position[b]).norm();
      if (l < min_length) stubs.emplace_back(l, a, b);
    }
  std::sort(stubs.begin(), stubs.end());
  std::vector<std::vector<int>> vertex_faces(position.size());
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int v : faces[f]) vertex_faces[v].push_back(static_cast<int>(f));
  std::vector<int> into(position.size(), -1);
  std::vector<char> touched(position.size(), 0);
  int done = 0;
  for (const auto& [l, a, b] : stubs) {
    if (touched[a] || touched[b]) continue;
    bool ok = true;
    for (int f : vertex_faces[a]) {
      const auto& face = faces[f];
      if (face.size() <= 3 && std::find(face.begin(), face.end(), b) != face.end()) ok = false;
    }
    if (!ok) continue;
    into[a] = b;
    touched[a] = touched[b] = 1;
    for (int f : vertex_faces[a]) {
      std::vector<int> out;
      for (int v : faces[f]) {
        const int w = into[v] >= 0 ? into[v] : v;
        if (out.empty() || out.back() != w) out.push_back(w);
      }
      while (out.size() > 1 && out.front() == out.back()) out.pop_back();
      faces[f] = std::move(out);
      vertex_faces[b].push_back(f);
    }
    ++done;
  }
  return done;
}

}  // namespace gridshell
