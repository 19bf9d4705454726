#include "gridshell/mesh/repair.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>

#include <fmt/format.h>

#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

namespace {

/// For each vertex, the lowest-numbered vertex at exactly the same position (itself if none).
std::vector<int> first_at_same_position(const Points& V) {
  const int nv = static_cast<int>(V.rows());
  std::vector<int> order(nv);
  std::iota(order.begin(), order.end(), 0);
  auto key_less = [&V](int a, int b) {
    for (int c = 0; c < 3; ++c)
      if (V(a, c) != V(b, c)) return V(a, c) < V(b, c);
    return a < b;  // equal positions: lowest id first
  };
  std::sort(order.begin(), order.end(), key_less);
  std::vector<int> first(nv);
  for (int i = 0; i < nv; ++i) {
    const int v = order[i];
    const bool same = i > 0 && V.row(v) == V.row(order[i - 1]);
    first[v] = same ? first[order[i - 1]] : v;
  }
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

/// Step 4 of repair_mesh: reverses faces so that every edge shared by exactly two faces is walked
/// once each way. Faces are visited breadth-first from the lowest id of each connected piece
/// (through such edges); a face is reversed or not to agree with the face it was reached from.
/// Within a piece, the faces marked for reversal are reversed only if they have less area than
/// the others (ties: the piece's lowest face keeps its orientation).
void orient_faces(PolyMesh& mesh, RepairReport& r) {
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
        if (g == f) continue;
        if (flip[g] >= 0) continue;
        // Consistent when the two faces walk the edge opposite ways (after their flips).
        flip[g] = dir(f, k) * (flip[f] ? -1 : 1) == dir(g, local(g, e)) ? 1 : 0;
        {
          piece.push_back(g);
          todo.push(g);
        }
      }
    }
    double area[2] = {0, 0};
    for (int f : piece) area[flip[f]] += polygon_area(mesh, f);
    if (area[1] > area[0])
      for (int f : piece) flip[f] = 1 - flip[f];
  }
  for (int e = 0; e < topo.num_edges(); ++e) {
    const auto& ef = topo.edge_faces[e];
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
    parts.push_back("merged " + plural(merged_vertices, "duplicate vertex", "duplicate vertices"));
  if (shortened_faces)
    parts.push_back("removed a repeated corner from " + plural(shortened_faces, "face", "faces"));
  if (dropped_faces)
    parts.push_back("dropped " + plural(dropped_faces, "face", "faces") + " without area");
  if (unreferenced_vertices)
    parts.push_back("dropped " +
                    plural(unreferenced_vertices, "unreferenced vertex", "unreferenced vertices"));
  if (reversed_faces)
    parts.push_back("reversed " + plural(reversed_faces, "face", "faces") +
                    " to orient the surface consistently");
  if (inconsistent_edges)
    parts.push_back(plural(inconsistent_edges, "edge", "edges") +
                    " still inconsistently oriented (a non-orientable surface)");
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : ", ") + p;
  return out;
}

RepairReport repair_mesh(PolyMesh& mesh) {
  RepairReport r;
  const int nv = mesh.num_vertices();

  // 1. Duplicates.
  const std::vector<int> first = first_at_same_position(mesh.V);
  for (int v = 0; v < nv; ++v) r.merged_vertices += first[v] != v;

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

  // 4. Orientation.
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
