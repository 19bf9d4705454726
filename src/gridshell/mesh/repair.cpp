#include "gridshell/mesh/repair.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>

#include <fmt/format.h>

#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

namespace {

/// For each vertex, the lowest-numbered vertex it is merged into (itself if none): vertices
/// within `tolerance` of each other are grouped (transitively), each group into its lowest id.
/// A grid of cells of side 2 × tolerance, vertices sorted by cell: each vertex is compared with
/// those of its own cell and of the neighbouring cells it lies within `tolerance` of (on average
/// 3.4 cells). tolerance 0: exactly equal positions only.
std::vector<int> first_within(const Points& V, double tolerance) {
  const int nv = static_cast<int>(V.rows());
  DisjointSets sets(nv);  // a set's root is its lowest id
  using Key = std::array<std::int64_t, 3>;
  const double cell = 2 * tolerance;
  auto key_of = [&](const Vec3& p) {
    Key k{0, 0, 0};
    if (cell > 0)
      for (int c = 0; c < 3; ++c) k[c] = static_cast<std::int64_t>(std::floor(p[c] / cell));
    return k;
  };
  auto position_less = [&](int x, int y) {
    for (int c = 0; c < 3; ++c)
      if (V(x, c) != V(y, c)) return V(x, c) < V(y, c);
    return x < y;
  };
  // Sorted by cell, then by position: equal positions are next to each other in this order.
  std::vector<std::pair<Key, int>> cells(nv);
  for (int v = 0; v < nv; ++v) cells[v] = {key_of(V.row(v).transpose()), v};
  std::sort(cells.begin(), cells.end(), [&](const auto& x, const auto& y) {
    return x.first != y.first ? x.first < y.first : position_less(x.second, y.second);
  });
  for (int i = 1; i < nv; ++i)
    if (V.row(cells[i].second) == V.row(cells[i - 1].second))
      sets.unite(cells[i].second, cells[i - 1].second);
  if (tolerance <= 0) {
    std::vector<int> first(nv);
    for (int v = 0; v < nv; ++v) first[v] = sets.find(v);
    return first;
  }
  const double tol2 = tolerance * tolerance;
  for (int i = 0; i < nv; ++i) {
    const int v = cells[i].second;
    const Vec3 p = V.row(v).transpose();
    const Key& k = cells[i].first;
    // Per axis, the neighbouring cells within reach: the own cell and the one whose face is
    // closer than the tolerance.
    std::array<std::array<int, 2>, 3> reach;
    std::array<int, 3> count{};
    for (int c = 0; c < 3; ++c) {
      reach[c][count[c]++] = 0;
      const double offset = p[c] - static_cast<double>(k[c]) * cell;
      if (offset < tolerance) reach[c][count[c]++] = -1;
      if (offset > cell - tolerance) reach[c][count[c]++] = 1;
    }
    for (int ix = 0; ix < count[0]; ++ix)
      for (int iy = 0; iy < count[1]; ++iy)
        for (int iz = 0; iz < count[2]; ++iz) {
          const Key n{k[0] + reach[0][ix], k[1] + reach[1][iy], k[2] + reach[2][iz]};
          auto it = std::lower_bound(cells.begin(), cells.end(), n,
                                     [](const auto& x, const Key& y) { return x.first < y; });
          for (; it != cells.end() && it->first == n; ++it)
            if (it->second != v && (V.row(it->second) - V.row(v)).squaredNorm() <= tol2)
              sets.unite(it->second, v);
        }
  }
  std::vector<int> first(nv);
  for (int v = 0; v < nv; ++v) first[v] = sets.find(v);
  return first;
}

/// Removes corners equal to the one before them (cyclically).
std::vector<int> without_repeated_neighbours(const std::vector<int>& face) {
  std::vector<int> out;
  for (int v : face)
    if (out.empty() || out.back() != v) out.push_back(v);
  while (out.size() > 1 && out.front() == out.back()) out.pop_back();
  return out;
}

bool has_repeated_vertex(std::vector<int> face) {
  std::sort(face.begin(), face.end());
  return std::adjacent_find(face.begin(), face.end()) != face.end();
}

std::string plural(int n, const char* one, const char* many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

/// A boundary edge of a polygon mesh: an undirected edge of one face only.
struct Side {
  std::uint64_t key;  // the undirected edge (smaller id << 32 | larger id)
  int face, corner;   // the edge runs from corner to corner + 1 of face
};

/// The undirected edge from corner k to corner k + 1 of `face`, as a key.
std::uint64_t edge_key(const std::vector<int>& face, std::size_t k) {
  const auto a = static_cast<std::uint32_t>(face[k]);
  const auto b = static_cast<std::uint32_t>(face[(k + 1) % face.size()]);
  return static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b);
}

/// The first and second vertex of side `e` as its face walks it.
std::pair<int, int> side_ends(const PolyMesh& mesh, const Side& e) {
  const auto& face = mesh.faces[e.face];
  return std::pair{face[e.corner], face[(e.corner + 1) % face.size()]};
}

/// The mesh's boundary edges in face order; none when there are fewer than 4.
std::vector<Side> boundary_sides(const PolyMesh& mesh) {
  std::vector<std::uint64_t> keys;
  for (const auto& face : mesh.faces)
    for (std::size_t k = 0; k < face.size(); ++k) keys.push_back(edge_key(face, k));
  std::sort(keys.begin(), keys.end());
  std::vector<std::uint64_t> once;  // the boundary's keys, sorted
  for (std::size_t i = 0; i < keys.size(); ++i)
    if ((i == 0 || keys[i - 1] != keys[i]) && (i + 1 == keys.size() || keys[i + 1] != keys[i]))
      once.push_back(keys[i]);
  if (once.size() < 4) return {};
  std::vector<Side> boundary;
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (std::size_t k = 0; k < mesh.faces[f].size(); ++k)
      if (const std::uint64_t e = edge_key(mesh.faces[f], k);
          std::binary_search(once.begin(), once.end(), e))
        boundary.push_back({e, f, static_cast<int>(k)});
  return boundary;
}

/// Each boundary vertex with the directions of its boundary edges (unit; none for a vertex off
/// the boundary), and the mean boundary edge's length.
struct BoundaryDirections {
  std::vector<std::vector<Vec3>> along;
  double mean = 0;
};

BoundaryDirections boundary_directions(const PolyMesh& mesh, const std::vector<Side>& boundary) {
  BoundaryDirections out;
  out.along.resize(mesh.num_vertices());
  for (const Side& e : boundary) {
    const auto [a, b] = side_ends(mesh, e);
    const Vec3 d = mesh.vertex(b) - mesh.vertex(a);
    out.mean += d.norm() / static_cast<double>(boundary.size());
    if (d.norm() > 0) {
      out.along[a].push_back(d.normalized());
      out.along[b].push_back(d.normalized());
    }
  }
  return out;
}

/// The boundary vertices binned in a grid of cubic cells of side `cell`, sorted by cell.
struct BoundaryGrid {
  using Key = std::array<std::int64_t, 3>;
  double cell;
  std::vector<std::pair<Key, int>> cells;

  Key key_of(const Vec3& p) const {
    Key k;
    for (int c = 0; c < 3; ++c) k[c] = static_cast<std::int64_t>(std::floor(p[c] / cell));
    return k;
  }
};

BoundaryGrid boundary_grid(const PolyMesh& mesh, const BoundaryDirections& dirs) {
  BoundaryGrid grid{dirs.mean, {}};
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (!dirs.along[v].empty()) grid.cells.push_back({grid.key_of(mesh.vertex(v)), v});
  std::sort(grid.cells.begin(), grid.cells.end());
  return grid;
}

/// Per vertex, the nearest edge it lies on: (distance, index into boundary, parameter).
struct Hit {
  double distance = std::numeric_limits<double>::infinity();
  int edge = -1;
  double t = 0;
};

/// The T-junctions: per vertex, the nearest boundary edge (of another face) it lies on within
/// kTJunctionTolerance × the edge's length, strictly inside it and parallel to one of the
/// vertex's own boundary edges within kTJunctionAngle. Each edge looks in the grid cells its
/// widened box covers.
std::vector<Hit> find_t_junctions(const PolyMesh& mesh, const std::vector<Side>& boundary,
                                  const BoundaryDirections& dirs, const BoundaryGrid& grid) {
  using Key = BoundaryGrid::Key;
  const double cos_angle = std::cos(kTJunctionAngle * std::acos(-1.0) / 180.0);
  std::vector<Hit> hit(mesh.num_vertices());
  constexpr double kMaxCells = 4096;  // an edge far longer than the mean is not searched
  for (int i = 0; i < static_cast<int>(boundary.size()); ++i) {
    const auto [a, b] = side_ends(mesh, boundary[i]);
    const Vec3 pa = mesh.vertex(a), pb = mesh.vertex(b), d = pb - pa;
    const double length = d.norm();
    if (!(length > 0)) continue;
    const double reach = kTJunctionTolerance * length;
    const Vec3 lo = pa.cwiseMin(pb) - Vec3::Constant(reach),
               hi = pa.cwiseMax(pb) + Vec3::Constant(reach);
    const Key k0 = grid.key_of(lo), k1 = grid.key_of(hi);
    double cells_covered = 1;
    for (int c = 0; c < 3; ++c) cells_covered *= static_cast<double>(k1[c] - k0[c] + 1);
    if (cells_covered > kMaxCells) continue;
    const auto& face = mesh.faces[boundary[i].face];
    for (std::int64_t x = k0[0]; x <= k1[0]; ++x)
      for (std::int64_t y = k0[1]; y <= k1[1]; ++y)
        for (std::int64_t z = k0[2]; z <= k1[2]; ++z) {
          const Key key{x, y, z};
          auto it = std::lower_bound(grid.cells.begin(), grid.cells.end(), std::pair{key, -1});
          for (; it != grid.cells.end() && it->first == key; ++it) {
            const int v = it->second;
            const Vec3 p = mesh.vertex(v);
            const double t = (p - pa).dot(d) / (length * length);
            if (t <= 1e-3 || t >= 1 - 1e-3) continue;
            const double distance = (p - pa - t * d).norm();
            if (distance > reach || distance >= hit[v].distance) continue;
            if (std::find(face.begin(), face.end(), v) != face.end()) continue;
            bool parallel = false;
            for (const Vec3& u : dirs.along[v])
              parallel |= std::abs(u.dot(d)) >= cos_angle * length;
            if (parallel) hit[v] = {distance, i, t};
          }
        }
  }
  return hit;
}

/// Inserts each hit vertex into its edge, per edge in the order of the parameter; faces rebuilt
/// corner by corner. Returns the number of vertices inserted.
int insert_on_edges(PolyMesh& mesh, const std::vector<Side>& boundary,
                    const std::vector<Hit>& hit) {
  std::vector<std::vector<std::pair<double, int>>> on_edge(boundary.size());
  int inserted = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (hit[v].edge >= 0) {
      on_edge[hit[v].edge].push_back({hit[v].t, v});
      ++inserted;
    }
  if (inserted == 0) return 0;
  std::vector<std::vector<std::pair<int, std::vector<int>>>> per_face(mesh.num_faces());
  for (std::size_t i = 0; i < boundary.size(); ++i) {
    if (on_edge[i].empty()) continue;
    std::sort(on_edge[i].begin(), on_edge[i].end());
    std::vector<int> vs;
    for (const auto& [t, v] : on_edge[i]) vs.push_back(v);
    per_face[boundary[i].face].push_back({boundary[i].corner, std::move(vs)});
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (per_face[f].empty()) continue;
    std::sort(per_face[f].begin(), per_face[f].end());
    std::vector<int> out;
    std::size_t next = 0;
    const auto& face = mesh.faces[f];
    for (int k = 0; k < static_cast<int>(face.size()); ++k) {
      out.push_back(face[k]);
      if (next < per_face[f].size() && per_face[f][next].first == k)
        for (int v : per_face[f][next++].second) out.push_back(v);
    }
    mesh.faces[f] = std::move(out);
  }
  return inserted;
}

/// Step 4 of repair_mesh: stitches T-junctions (see repair.h). Boundary edges are the undirected
/// edges of one face; their vertices are binned in a grid of cells of the mean boundary edge's
/// length, and each boundary edge looks for candidates in the cells its (widened) box covers.
/// A vertex near several edges goes into the nearest. Returns the number of vertices inserted.
int stitch_t_junctions(PolyMesh& mesh) {
  const std::vector<Side> boundary = boundary_sides(mesh);
  if (boundary.size() < 4) return 0;
  const BoundaryDirections dirs = boundary_directions(mesh, boundary);
  // No grid when its cells would not fit the coordinates (as in step 1).
  const double mean = dirs.mean;
  if (!(mean > 0) || !std::isfinite(mean) || !(mesh.V.cwiseAbs().maxCoeff() < 1e15 * mean))
    return 0;
  const BoundaryGrid grid = boundary_grid(mesh, dirs);
  return insert_on_edges(mesh, boundary, find_t_junctions(mesh, boundary, dirs, grid));
}

/// Step 5 of repair_mesh: reverses faces so that every edge shared by exactly two faces is walked
/// once each way. Faces are visited breadth-first from the lowest id of each connected piece
/// (through such edges); a face is reversed or not to agree with the face it was reached from.
/// Within a piece, the faces marked for reversal are reversed only if they have less area than
/// the others (ties: the piece's lowest face keeps its orientation).
void orient_faces(PolyMesh& mesh, RepairReport& r) {
  // Nothing to do when no directed edge is walked twice (the usual case): checked on sorted
  // directed edges, cheaper than the topology below. (An edge of three or more faces always
  // has a directed edge walked twice, so non_manifold_edges is counted below.)
  {
    std::vector<std::uint64_t> directed;
    for (const auto& face : mesh.faces)
      for (std::size_t k = 0; k < face.size(); ++k)
        directed.push_back(static_cast<std::uint64_t>(face[k]) << 32 |
                           static_cast<std::uint32_t>(face[(k + 1) % face.size()]));
    std::sort(directed.begin(), directed.end());
    if (std::adjacent_find(directed.begin(), directed.end()) == directed.end()) return;
  }
  const Topology topo = build_topology(mesh);
  const int nf = mesh.num_faces();
  // Direction of face f's k-th edge relative to the stored (smaller, larger) edge: ±1.
  auto dir = [&](int f, int k) {
    const auto& face = mesh.faces[f];
    return face[k] < face[(k + 1) % face.size()] ? 1 : -1;
  };
  auto local = [&](int f, int e) {
    const auto& fe = topo.face_edges[f];
    return static_cast<int>(std::find(fe.begin(), fe.end(), e) - fe.begin());
  };
  std::vector<int> flip(nf, -1);  // -1 not reached; 0 keep; 1 reverse
  for (int seed = 0; seed < nf; ++seed) {
    if (flip[seed] >= 0) continue;
    std::vector<int> piece{seed};
    std::queue<int> todo;
    flip[seed] = 0;
    todo.push(seed);
    while (!todo.empty()) {
      const int f = todo.front();
      todo.pop();
      for (int k = 0; k < static_cast<int>(mesh.faces[f].size()); ++k) {
        const int e = topo.face_edges[f][k];
        if (topo.edge_faces[e].size() != 2) continue;
        const int g = topo.edge_faces[e][0] == f ? topo.edge_faces[e][1] : topo.edge_faces[e][0];
        if (g == f || flip[g] >= 0) continue;
        // Consistent when the two faces walk the edge opposite ways (after their flips).
        flip[g] = dir(f, k) * (flip[f] ? -1 : 1) == dir(g, local(g, e)) ? 1 : 0;
        piece.push_back(g);
        todo.push(g);
      }
    }
    double area[2] = {0, 0};
    for (int f : piece) area[flip[f]] += polygon_area(mesh, f);
    if (area[1] > area[0])
      for (int f : piece) flip[f] = 1 - flip[f];
  }
  for (int e = 0; e < topo.num_edges(); ++e) {
    const auto& ef = topo.edge_faces[e];
    r.non_manifold_edges += ef.size() > 2;
    if (ef.size() != 2) continue;
    const int d0 = dir(ef[0], local(ef[0], e)) * (flip[ef[0]] ? -1 : 1);
    const int d1 = dir(ef[1], local(ef[1], e)) * (flip[ef[1]] ? -1 : 1);
    r.inconsistent_edges += d0 == d1;
  }
  for (int f = 0; f < nf; ++f)
    if (flip[f] == 1) {
      std::reverse(mesh.faces[f].begin(), mesh.faces[f].end());
      ++r.reversed_faces;
    }
}

}  // namespace

std::string RepairReport::describe() const {
  std::vector<std::string> parts;
  if (merged_vertices)
    parts.push_back("merged " + plural(merged_vertices, "duplicate vertex", "duplicate vertices") +
                    (close_vertices
                         ? fmt::format(" ({} within {:g} of the size, not at the same position)",
                                       close_vertices, kWeldTolerance)
                         : ""));
  if (shortened_faces)
    parts.push_back("removed a repeated corner from " + plural(shortened_faces, "face", "faces"));
  if (dropped_faces)
    parts.push_back("dropped " + plural(dropped_faces, "face", "faces") + " without area");
  if (unreferenced_vertices)
    parts.push_back("dropped " +
                    plural(unreferenced_vertices, "unreferenced vertex", "unreferenced vertices"));
  if (t_junctions)
    parts.push_back("stitched " + plural(t_junctions, "T-junction", "T-junctions") +
                    " (a vertex on another patch's edge)");
  if (reversed_faces)
    parts.push_back("reversed " + plural(reversed_faces, "face", "faces") +
                    " to orient the surface consistently");
  if (inconsistent_edges)
    parts.push_back(plural(inconsistent_edges, "edge", "edges") +
                    " still inconsistently oriented (a non-orientable surface)");
  if (non_manifold_edges)
    parts.push_back(plural(non_manifold_edges, "edge", "edges") + " of three or more faces");
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : ", ") + p;
  return out;
}

RepairReport repair_mesh(PolyMesh& mesh) {
  RepairReport r;
  const int nv = mesh.num_vertices();

  // 1. Duplicates.
  // Within the tolerance when the coordinates allow a grid of that cell size (finite, and fewer
  // than 10¹⁵ cells from the origin), else exactly equal positions only.
  const double tolerance =
      nv > 0 && mesh.V.allFinite() ? kWeldTolerance * bbox_diagonal(mesh.V) : 0;
  const bool gridable = tolerance > 0 && mesh.V.cwiseAbs().maxCoeff() < 1e15 * tolerance;
  const std::vector<int> first = first_within(mesh.V, gridable ? tolerance : 0);
  for (int v = 0; v < nv; ++v) {
    r.merged_vertices += first[v] != v;
    r.close_vertices += first[v] != v && mesh.V.row(v) != mesh.V.row(first[v]);
  }

  // 2. Faces, on the merged ids.
  std::vector<std::vector<int>> faces;
  faces.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) {
    std::vector<int> merged(f.size());
    for (std::size_t k = 0; k < f.size(); ++k) merged[k] = first[f[k]];
    std::vector<int> g = without_repeated_neighbours(merged);
    if (g.size() < 3 || has_repeated_vertex(g)) {
      ++r.dropped_faces;
      continue;
    }
    r.shortened_faces += g.size() < f.size();
    faces.push_back(std::move(g));
  }

  // 3. Unreferenced vertices (merged-away duplicates among them are not counted again).
  std::vector<char> used(nv, 0);
  for (const auto& f : faces)
    for (int v : f) used[v] = 1;
  std::vector<int> compact(nv, -1);
  int kept = 0;
  for (int v = 0; v < nv; ++v)
    if (used[v]) compact[v] = kept++;
  for (int v = 0; v < nv; ++v) r.unreferenced_vertices += first[v] == v && !used[v];

  r.new_id.resize(nv);
  for (int v = 0; v < nv; ++v) r.new_id[v] = compact[first[v]];
  if (r.changed()) {
    Points V(kept, 3);
    for (int v = 0; v < nv; ++v)
      if (compact[v] >= 0) V.row(compact[v]) = mesh.V.row(v);
    for (auto& f : faces)
      for (int& v : f) v = compact[v];
    mesh.V = std::move(V);
    mesh.faces = std::move(faces);
  }

  // 4. T-junctions, 5. orientation.
  r.t_junctions = stitch_t_junctions(mesh);
  orient_faces(mesh, r);
  return r;
}

int count_slivers(const TriMesh& mesh, double min_angle_degrees) {
  const double limit = std::cos(min_angle_degrees * std::acos(-1.0) / 180.0);
  int count = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    bool sliver = false;
    for (int k = 0; k < 3 && !sliver; ++k) {
      const Vec3 a = mesh.vertex(mesh.F(f, k));
      const Vec3 e1 = mesh.vertex(mesh.F(f, (k + 1) % 3)) - a;
      const Vec3 e2 = mesh.vertex(mesh.F(f, (k + 2) % 3)) - a;
      const double n = e1.norm() * e2.norm();
      // An angle below the limit has a cosine above cos(limit); a zero-length edge counts too.
      sliver = !(n > 0) || e1.dot(e2) / n > limit;
    }
    count += sliver;
  }
  return count;
}

}  // namespace gridshell
