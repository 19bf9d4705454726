#pragma once
/// \file topology.h
/// Connectivity of a polygon (or triangle) mesh: unique edges, edge–face incidence, boundary
/// loops, vertex neighbourhoods, Euler characteristic, and the validity checks of `info`.
/// Cost: O(sum of face sizes · log) time and memory.
///
/// TriangleAdjacency is the lean companion for manifold triangle meshes that are refined and
/// walked many times (the tessellation's support mesh, 10⁵–10⁶ triangles): the neighbour across
/// each triangle edge and the boundary loops with their triangle edges, in linear time, no
/// per-vertex lists. It refuses non-manifold input; its boundary loops are Topology's.

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "gridshell/mesh/geometry.h"  // areas and sizes (polygon_area, surface_area, …)
#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct Topology {
  /// Unique undirected edges, each as (smaller id, larger id), sorted lexicographically.
  std::vector<std::array<int, 2>> edges;
  /// The faces incident to each edge (1 = boundary, 2 = interior, more = non-manifold).
  std::vector<std::vector<int>> edge_faces;
  /// For face f with vertices (v0 … vn-1), face_edges[f][k] is the edge v_k → v_{k+1}.
  std::vector<std::vector<int>> face_edges;
  /// Boundary loops as vertex cycles, oriented like the faces next to them.
  std::vector<std::vector<int>> boundary_loops;
  /// Per vertex: 1 when it lies on a boundary edge.
  std::vector<char> on_boundary;
  /// Per vertex: the faces that use it.
  std::vector<std::vector<int>> vertex_faces;
  /// Per vertex: the vertices sharing an edge with it (sorted).
  std::vector<std::vector<int>> vertex_neighbors;

  int num_edges() const { return static_cast<int>(edges.size()); }
  /// Index of edge (a, b) or -1.
  int find_edge(int a, int b) const;
};

Topology build_topology(const PolyMesh& mesh);
Topology build_topology(const TriMesh& mesh);

/// The vertices on the mesh boundary (`on_boundary`), in id order.
std::vector<int> boundary_vertices(const Topology& topo);

/// Triangle-to-triangle adjacency of a manifold, consistently oriented triangle mesh. Local
/// edge k of triangle t runs from corner k to corner k + 1 (mod 3).
struct TriangleAdjacency {
  /// Per triangle, per local edge: the triangle across it, or −1 on the boundary.
  std::vector<std::array<int, 3>> neighbor;
  /// Per triangle, per local edge: the local index of the same edge in that neighbour (−1).
  std::vector<std::array<int, 3>> neighbor_edge;
  /// Boundary loops as vertex cycles, oriented like the triangles next to them: the same loops,
  /// starting vertices and order as Topology::boundary_loops (each loop starts at its smallest
  /// vertex id, loops by that id).
  std::vector<std::vector<int>> boundary_loops;
  /// Per loop, per position k: (triangle, local edge) of the edge loop[k] → loop[k + 1].
  std::vector<std::vector<std::array<int, 2>>> boundary_loop_edges;
};

/// Builds the adjacency of `F` over `num_vertices` vertices: half-edges grouped by origin vertex
/// (counting sort), twins looked up there; O(F + V). Throws Error("surface", …) for an edge of
/// more than two triangles, triangles walking an edge the same way (inconsistent orientation),
/// and boundaries that touch at a vertex or do not close.
TriangleAdjacency build_triangle_adjacency(const Triangles& F, int num_vertices);

/// Disjoint sets of 0 … n−1 (union–find with path halving), for connected components. `unite`
/// hangs the larger root under the smaller, so a set's root is always its smallest element,
/// whatever the order of the unions.
struct DisjointSets {
  std::vector<int> parent;

  explicit DisjointSets(int n) : parent(n) {
    for (int i = 0; i < n; ++i) parent[i] = i;
  }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

/// The faces of the connected component (faces joined through shared vertices) with the most
/// faces (on a tie, the one holding the lowest vertex index); vertices no kept face uses are
/// dropped, the others keep their order. A grid-shell is one structure: a piece an extraction
/// left apart from it would be a mechanism, or a second structure, in the analysis.
PolyMesh largest_component(const PolyMesh& mesh);
/// The same per piece of a surface made of several: `piece[v]` names the piece vertex v lies on,
/// and of the components lying on each piece (by their lowest vertex) the one with the most
/// faces is kept. One value everywhere: largest_component(mesh).
PolyMesh largest_component(const PolyMesh& mesh, const std::vector<int>& piece);

/// Removes, repeatedly, the flaps: faces held by the rest at the two ends of a single edge only
/// (no other edge shared, no other corner used by another face). Such a face turns about that
/// edge in a frame analysis, nearly a mechanism when both ends are pinned supports. A face that
/// also touches others at a corner is held at three points and stays, so a staircase boundary
/// does not erode. When every face left is a flap (one face, or two sharing an edge) they are
/// kept. Vertices are not touched (largest_component drops the unused ones).
void remove_hanging_faces(PolyMesh& mesh);

/// V − E + F counted over referenced vertices.
int euler_characteristic(const PolyMesh& mesh, const Topology& topo);

/// Counts of everything `info` reports as a validity problem.
struct MeshProblems {
  int non_finite_coordinates = 0;    ///< vertices with a NaN or infinite coordinate
  int bad_indices = 0;               ///< face corners out of range
  int small_faces = 0;               ///< faces with fewer than 3 vertices
  int repeated_corner_faces = 0;     ///< faces that use a vertex twice
  int degenerate_faces = 0;          ///< faces of (near) zero area
  int non_manifold_edges = 0;        ///< edges with more than two faces
  int non_manifold_vertices = 0;     ///< vertices whose faces form more than one fan
  int inconsistent_orientation = 0;  ///< interior edges walked the same way by both faces
  int duplicate_vertices = 0;        ///< vertices at exactly the same position as another
  int unreferenced_vertices = 0;     ///< vertices no face uses

  /// One human-readable line per kind of problem present ("3 degenerate faces", …).
  std::vector<std::string> describe() const;
  bool ok() const { return describe().empty(); }
};

/// The vertices where pieces of the surface touch at a single corner (a bow-tie): the faces
/// around such a vertex form more than one fan, fans being joined across the edges that meet at
/// the vertex. Every face must have in-range indices and distinct corners. Increasing order.
/// Cost: O(S log d), S the sum of face sizes, d the largest number of faces at a vertex.
std::vector<int> pinched_vertices(const PolyMesh& mesh);

/// Checks a mesh for everything above. Never throws on bad indices: they are counted.
/// `degenerate_tolerance` is relative to the squared bounding-box diagonal.
MeshProblems check_mesh(const PolyMesh& mesh, double degenerate_tolerance = 1e-14);

/// Collapses stub edges at a boundary: every edge shorter than `min_length` with an end of rank
/// ≥ 1 is collapsed into its end of higher rank (rank per vertex: 0 interior, 1 boundary,
/// 2 corner; a corner never moves, two corners are never merged, two interior vertices are left
/// alone). Shortest first; each vertex takes part in at most one collapse; a collapse that would
/// leave a face with fewer than 3 corners is skipped. `faces` (vertex cycles, empty ones
/// allowed) are rewritten in place; collapsed vertices are left unused, not removed. Returns the
/// number of collapses.
int collapse_boundary_stubs(std::vector<std::vector<int>>& faces, const std::vector<Vec3>& position,
                            const std::vector<int>& rank, double min_length);

}  // namespace gridshell
