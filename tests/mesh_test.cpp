// Mesh topology and validity checks on small hand-made meshes.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include "gridshell/core/error.h"
#include "gridshell/mesh/repair.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/surfaces/builtin.h"

using namespace gridshell;

namespace {
PolyMesh square_with_two_triangles() {
  PolyMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  return m;
}
}  // namespace

TEST(Topology, EdgesLoopsAndEuler) {
  PolyMesh m = square_with_two_triangles();
  Topology t = build_topology(m);
  EXPECT_EQ(t.num_edges(), 5);
  ASSERT_EQ(t.boundary_loops.size(), 1u);
  EXPECT_EQ(t.boundary_loops[0].size(), 4u);
  EXPECT_EQ(euler_characteristic(m, t), 1);
  EXPECT_TRUE(check_mesh(m).ok());
  EXPECT_NEAR(polygon_area(m, 0) + polygon_area(m, 1), 1.0, 1e-15);
}

// The topology against a brute-force construction (ordered sets), on messy meshes: random
// polygons of 3–5 corners over a few vertices (non-manifold edges, faces using an edge twice,
// repeated corners), the same with an out-of-range id, and a triangle mesh against its polygon
// copy.
TEST(Topology, EqualsABruteForceConstruction) {
  std::uint64_t state = 12345;
  auto next = [&](int n) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<int>((state >> 33) % static_cast<std::uint64_t>(n));
  };
  for (int trial = 0; trial < 40; ++trial) {
    PolyMesh m;
    const int nv = 4 + next(12);
    m.V = Points::Zero(nv, 3);
    for (int f = 0, nf = 1 + next(20); f < nf; ++f) {
      std::vector<int> face(3 + next(3));
      for (int& v : face) v = next(nv);
      m.faces.push_back(face);
    }
    if (trial % 5 == 4) m.faces.back().back() = nv + 2;  // an id out of range
    const Topology t = build_topology(m);
    std::set<std::array<int, 2>> edge_set;
    for (const auto& f : m.faces)
      for (std::size_t k = 0; k < f.size(); ++k)
        edge_set.insert(
            {std::min(f[k], f[(k + 1) % f.size()]), std::max(f[k], f[(k + 1) % f.size()])});
    const std::vector<std::array<int, 2>> edges(edge_set.begin(), edge_set.end());
    ASSERT_EQ(t.edges, edges) << trial;
    std::vector<std::vector<int>> edge_faces(t.edges.size()), vertex_faces(nv);
    std::vector<std::set<int>> neighbours(nv);
    for (int fi = 0; fi < m.num_faces(); ++fi) {
      const auto& f = m.faces[fi];
      ASSERT_EQ(t.face_edges[fi].size(), f.size());
      for (std::size_t k = 0; k < f.size(); ++k) {
        const int a = f[k], b = f[(k + 1) % f.size()];
        const int e = t.face_edges[fi][k];
        EXPECT_EQ(t.edges[e], (std::array<int, 2>{std::min(a, b), std::max(a, b)}));
        EXPECT_EQ(t.find_edge(a, b), e);
        if (std::find(edge_faces[e].begin(), edge_faces[e].end(), fi) == edge_faces[e].end())
          edge_faces[e].push_back(fi);
        if (a < nv) vertex_faces[a].push_back(fi);
      }
    }
    EXPECT_EQ(t.edge_faces, edge_faces) << trial;
    EXPECT_EQ(t.vertex_faces, vertex_faces) << trial;
    std::vector<char> on_boundary(nv, 0);
    for (std::size_t e = 0; e < t.edges.size(); ++e) {
      const auto [a, b] = t.edges[e];
      if (b >= nv) continue;
      neighbours[a].insert(b);
      neighbours[b].insert(a);
      if (edge_faces[e].size() == 1) on_boundary[a] = on_boundary[b] = 1;
    }
    EXPECT_EQ(t.on_boundary, on_boundary) << trial;
    for (int v = 0; v < nv; ++v) {
      // A self-edge (a face repeating a corner) lists its vertex as its own neighbour twice.
      std::vector<int> unique(t.vertex_neighbors[v]);
      unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
      EXPECT_EQ(unique, std::vector<int>(neighbours[v].begin(), neighbours[v].end())) << trial;
      EXPECT_TRUE(std::is_sorted(t.vertex_neighbors[v].begin(), t.vertex_neighbors[v].end()));
    }
  }
  const Surface s = make_builtin("paraboloid:res=12");
  const Topology tri = build_topology(s.mesh), poly = build_topology(to_poly(s.mesh));
  EXPECT_EQ(tri.edges, poly.edges);
  EXPECT_EQ(tri.face_edges, poly.face_edges);
  EXPECT_EQ(tri.boundary_loops, poly.boundary_loops);
  EXPECT_EQ(tri.vertex_neighbors, poly.vertex_neighbors);
  EXPECT_EQ(tri.num_edges(), 12 * 13 * 2 + 12 * 12);  // grid edges and one diagonal per square
  EXPECT_EQ(tri.boundary_loops.size(), 1u);
  EXPECT_EQ(tri.boundary_loops[0].size(), 48u);
}

// Two quads sharing a corner (one component: faces meet through vertices), a lone quad apart
// and an unused vertex: the pair is kept, renumbered in order, and the rest is dropped.
TEST(Topology, LargestComponentKeepsTheBiggestPieceOnly) {
  PolyMesh m;
  m.V.resize(11, 3);
  m.V << 9, 9, 9,                          // 0: unused
      0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,  // 1–4: first quad
      2, 1, 0, 2, 2, 0, 1, 2, 0,           // 5–7: second quad with corner 3
      5, 0, 0, 6, 0, 0, 6, 1, 0;           // 8–10: a triangle apart
  m.faces = {{8, 9, 10}, {1, 2, 3, 4}, {3, 5, 6, 7}};
  const PolyMesh k = largest_component(m);
  ASSERT_EQ(k.num_vertices(), 7);
  ASSERT_EQ(k.num_faces(), 2);
  EXPECT_EQ(k.faces[0], (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(k.faces[1], (std::vector<int>{2, 4, 5, 6}));
  EXPECT_EQ(k.V.row(4), m.V.row(5));
  // A tie keeps the component of the lowest vertex index; no faces, no vertices.
  m.faces = {{8, 9, 10}, {1, 2, 3}};
  EXPECT_EQ(largest_component(m).faces[0], (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(largest_component(PolyMesh{m.V, {}}).num_vertices(), 0);
}

// A 2 × 2 block of quads with a triangle hung on one outer edge and a second triangle hung on
// the first: the second goes first, then the first; the block's faces (each sharing two edges)
// stay.
TEST(Topology, RemoveHangingFacesPeelsFlapsOffTheBoundary) {
  PolyMesh m;
  m.V.resize(11, 3);
  m.V << 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0, 0, 2, 0, 1, 2, 0, 2, 2, 0,  // 0–8
      3, 0.5, 0, 4, 0.5, 0;                                                                // 9–10
  m.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}, {3, 4, 7, 6}, {4, 5, 8, 7}, {2, 9, 5}, {9, 10, 5}};
  PolyMesh g = m;
  remove_hanging_faces(g);
  EXPECT_EQ(g.faces, (std::vector<std::vector<int>>{m.faces.begin(), m.faces.begin() + 4}));
  EXPECT_EQ(g.num_vertices(), 11);  // vertices untouched
  PolyMesh lone;                    // two faces on one edge: both hang, both kept
  lone.V = m.V;
  lone.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}};
  remove_hanging_faces(lone);
  EXPECT_EQ(lone.faces.size(), 2u);
}

TEST(Topology, DetectsEveryProblemKind) {
  PolyMesh m = square_with_two_triangles();
  m.V.conservativeResize(7, 3);
  m.V.row(4) << 0, 0, 0;  // duplicate of vertex 0
  m.V.row(5) << 5, 5, 5;  // unreferenced
  m.V.row(6) << 0.5, 0.5, 1;
  m.faces.push_back({0, 2, 6});  // third face on edge 0–2: non-manifold
  m.faces.push_back({1, 1, 2});  // repeated corner
  m.faces.push_back({0, 1, 4});  // zero area (4 coincides with 0)
  MeshProblems p = check_mesh(m);
  EXPECT_EQ(p.non_manifold_edges, 1);
  EXPECT_EQ(p.repeated_corner_faces, 1);
  EXPECT_EQ(p.degenerate_faces, 1);
  EXPECT_EQ(p.duplicate_vertices, 1);
  EXPECT_EQ(p.unreferenced_vertices, 1);
  EXPECT_FALSE(p.ok());
}

// Pinched vertices (pieces touching at one corner) against a fan count from the topology: per
// vertex, its faces joined across the edges at it, on random meshes of faces with distinct
// corners (non-manifold edges included), and closed forms: none on a grid, one on a bow-tie,
// one on three triangles around a vertex where only two share an edge.
TEST(Topology, PinchedVerticesAreWhereFacesFormSeveralFans) {
  std::uint64_t state = 777;
  auto next = [&](int n) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<int>((state >> 33) % static_cast<std::uint64_t>(n));
  };
  int pinched_total = 0;
  for (int trial = 0; trial < 60; ++trial) {
    PolyMesh m;
    const int nv = 5 + next(15);
    m.V = Points::Zero(nv, 3);
    for (int f = 0, nf = 1 + next(14); f < nf; ++f) {
      std::vector<int> face;
      while (face.size() < static_cast<std::size_t>(3 + next(2))) {
        const int v = next(nv);
        if (std::find(face.begin(), face.end(), v) == face.end()) face.push_back(v);
      }
      m.faces.push_back(face);
    }
    const Topology t = build_topology(m);
    std::vector<int> expected;
    for (int v = 0; v < nv; ++v) {
      const auto& vf = t.vertex_faces[v];
      if (vf.size() < 2) continue;
      DisjointSets fan(static_cast<int>(vf.size()));
      for (std::size_t e = 0; e < t.edges.size(); ++e) {
        if (t.edges[e][0] != v && t.edges[e][1] != v) continue;
        const auto& ef = t.edge_faces[e];
        for (std::size_t i = 1; i < ef.size(); ++i)
          fan.unite(static_cast<int>(std::find(vf.begin(), vf.end(), ef[0]) - vf.begin()),
                    static_cast<int>(std::find(vf.begin(), vf.end(), ef[i]) - vf.begin()));
      }
      int roots = 0;
      for (std::size_t i = 0; i < vf.size(); ++i) roots += fan.find(static_cast<int>(i)) == int(i);
      if (roots > 1) expected.push_back(v);
    }
    EXPECT_EQ(pinched_vertices(m), expected) << trial;
    pinched_total += static_cast<int>(expected.size());
  }
  EXPECT_GT(pinched_total, 10);  // the random meshes do exercise it
  EXPECT_TRUE(pinched_vertices(to_poly(make_builtin("paraboloid:res=12").mesh)).empty());
  PolyMesh bowtie;
  bowtie.V = Points::Zero(5, 3);
  bowtie.faces = {{0, 1, 2}, {0, 3, 4}};
  EXPECT_EQ(pinched_vertices(bowtie), std::vector<int>{0});
  EXPECT_EQ(check_mesh(bowtie).non_manifold_vertices, 1);
  bowtie.faces.push_back({0, 2, 3});  // the gap closed: one fan
  EXPECT_TRUE(pinched_vertices(bowtie).empty());
  PolyMesh three;
  three.V = Points::Zero(6, 3);
  three.faces = {{0, 1, 2}, {0, 2, 3}, {0, 4, 5}};
  EXPECT_EQ(pinched_vertices(three), std::vector<int>{0});
}

TEST(Topology, InconsistentOrientation) {
  PolyMesh m = square_with_two_triangles();
  m.faces[1] = {0, 3, 2};
  EXPECT_EQ(check_mesh(m).inconsistent_orientation, 1);
}

TEST(Topology, CollapseBoundaryStubs) {
  // Two cells along a boundary y = 0. Joint 6 sits 1 cm beside joint 1 on the boundary, joint 7
  // 2 cm inside the boundary above joint 2 (a corner). Ranks: 0 interior, 1 boundary, 2 corner.
  const std::vector<Vec3> p{{0, 0, 0}, {1, 0, 0}, {2, 0, 0},    {0, 1, 0},
                            {1, 1, 0}, {2, 1, 0}, {1.01, 0, 0}, {2, 0.02, 0}};
  const std::vector<int> rank{2, 1, 2, 2, 0, 2, 1, 0};
  std::vector<std::vector<int>> faces{{0, 1, 6, 4, 3}, {6, 2, 7, 5, 4}};
  EXPECT_EQ(collapse_boundary_stubs(faces, p, rank, 0.05), 2);
  // 1 goes into 6 (equal rank: the first end of the edge goes), 7 into the corner 2.
  EXPECT_EQ(faces[0], (std::vector<int>{0, 6, 4, 3}));
  EXPECT_EQ(faces[1], (std::vector<int>{6, 2, 5, 4}));
  // Two corners, or two interior joints, are never merged, however close; a triangle keeps its
  // three corners.
  const std::vector<Vec3> q{{0, 0, 0}, {0.01, 0, 0}, {0.5, 1, 0}, {0.51, 1, 0}};
  std::vector<std::vector<int>> tri{{0, 1, 2}}, quad{{0, 1, 3, 2}};
  EXPECT_EQ(collapse_boundary_stubs(tri, q, {1, 1, 0, 0}, 0.05), 0);
  EXPECT_EQ(collapse_boundary_stubs(quad, q, {2, 2, 0, 0}, 0.05), 0);
  EXPECT_EQ(quad[0], (std::vector<int>{0, 1, 3, 2}));
}

TEST(TriangleAdjacency, AgreesWithTopologyOnTheBuiltins) {
  for (const char* spec :
       {"paraboloid:res=10", "dome:res=12", "barrel:res=10", "court:res=14", "funicular:res=10"}) {
    const TriMesh m = make_builtin(spec).mesh;
    const Topology topo = build_topology(m);
    const TriangleAdjacency adj = build_triangle_adjacency(m.F, m.num_vertices());
    // The same boundary loops, starting vertices and order (the tessellation's seeds depend on
    // them).
    EXPECT_EQ(adj.boundary_loops, topo.boundary_loops) << spec;
    ASSERT_EQ(adj.boundary_loop_edges.size(), adj.boundary_loops.size());
    for (std::size_t l = 0; l < adj.boundary_loops.size(); ++l) {
      const auto& loop = adj.boundary_loops[l];
      for (std::size_t k = 0; k < loop.size(); ++k) {
        const auto [t, e] = adj.boundary_loop_edges[l][k];
        EXPECT_EQ(m.F(t, e), loop[k]);
        EXPECT_EQ(m.F(t, (e + 1) % 3), loop[(k + 1) % loop.size()]);
        EXPECT_EQ(adj.neighbor[t][e], -1);
      }
    }
    // Neighbours are mutual and are the other face of the edge in Topology.
    for (int t = 0; t < m.num_faces(); ++t)
      for (int k = 0; k < 3; ++k) {
        const int u = adj.neighbor[t][k];
        const auto& faces = topo.edge_faces[topo.face_edges[t][k]];
        if (u < 0) {
          EXPECT_EQ(faces.size(), 1u);
          continue;
        }
        const int j = adj.neighbor_edge[t][k];
        EXPECT_EQ(adj.neighbor[u][j], t);
        EXPECT_EQ(adj.neighbor_edge[u][j], k);
        EXPECT_EQ(m.F(u, j), m.F(t, (k + 1) % 3));  // the twin runs the other way
        EXPECT_EQ(faces.size(), 2u);
        EXPECT_EQ(faces[0] == t ? faces[1] : faces[0], u);
      }
  }
}

TEST(TriangleAdjacency, RefusesNonManifoldInput) {
  Triangles F(3, 3);
  F << 0, 1, 2, 0, 2, 3, 0, 2, 4;  // edge 0–2 in three triangles
  EXPECT_THROW(build_triangle_adjacency(F, 5), Error);
  Triangles G(2, 3);
  G << 0, 1, 2, 0, 3, 2;  // both walk 0 → … 2 → 0: inconsistent orientation
  EXPECT_THROW(build_triangle_adjacency(G, 4), Error);
  Triangles H(2, 3);
  H << 0, 1, 2, 0, 3, 4;  // two fans touching at vertex 0
  EXPECT_THROW(build_triangle_adjacency(H, 5), Error);
}

namespace {
/// The sum of |area| of the triangles of `tri`, and whether each one turns like +z.
std::pair<double, bool> unsigned_area_and_upward(const TriMesh& tri) {
  double area = 0;
  bool upward = true;
  for (int f = 0; f < tri.num_faces(); ++f) {
    const Vec3 a = tri.vertex(tri.F(f, 0)), b = tri.vertex(tri.F(f, 1)),
               c = tri.vertex(tri.F(f, 2));
    const Vec3 n = (b - a).cross(c - a);
    area += 0.5 * n.norm();
    upward = upward && n.z() > 0;
  }
  return {area, upward};
}
}  // namespace

TEST(Triangulate, ConvexPolygonsAreFansFromTheFirstCorner) {
  PolyMesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 2, 0, 0, 3, 1, 0, 1, 2, 0, -1, 1, 0;
  m.faces = {{0, 1, 2, 3, 4}};
  const TriMesh t = triangulate(m);
  ASSERT_EQ(t.num_faces(), 3);
  for (int f = 0; f < 3; ++f) EXPECT_EQ(t.F(f, 0), 0);
  EXPECT_NEAR(unsigned_area_and_upward(t).first, polygon_area(m, 0), 1e-12);
}

TEST(Triangulate, ConcavePolygonsStayInsideTheirOutline) {
  // A square with a notch cut down to (1, 0.5) from its top side: area 4 − 1.5 = 2.5. Listed from
  // the corner (2, 2) beside the notch, a fan from it would lay the notch's triangle (area 1.5,
  // turned the other way) over the others: 5.5 in all.
  PolyMesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 2, 0, 0, 2, 2, 0, 1, 0.5, 0, 0, 2, 0;
  m.faces = {{2, 3, 4, 0, 1}};
  const TriMesh t = triangulate(m);
  ASSERT_EQ(t.num_faces(), 3);
  const auto [area, upward] = unsigned_area_and_upward(t);
  EXPECT_NEAR(area, 2.5, 1e-12);
  EXPECT_TRUE(upward);

  // The same outline with the notch's bottom lifted to z = 1, far from planar: CGAL's
  // minimum-weight search in 3D, not the planar path. The triangles still turn up and do not
  // overlap in plan.
  m.V(3, 2) = 1.0;
  const TriMesh lifted = triangulate(m);
  ASSERT_EQ(lifted.num_faces(), 3);
  double plan = 0;
  for (int f = 0; f < 3; ++f) {
    const Vec3 a = lifted.vertex(lifted.F(f, 0)), b = lifted.vertex(lifted.F(f, 1)),
               c = lifted.vertex(lifted.F(f, 2));
    const double z = (b - a).cross(c - a).z();
    EXPECT_GT(z, 0) << "triangle " << f;
    plan += 0.5 * z;
  }
  EXPECT_NEAR(plan, 2.5, 1e-12);
}

TEST(Triangulate, ALargeConcavePolygonIsTriangulatedInsideItsOutline) {
  // A star of 2000 corners (radii 1 and 0.5 alternating) in the plane z = 0: above the corner
  // count of CGAL's cubic search, triangulated by the planar (constrained Delaunay) path.
  const int n = 2000;
  PolyMesh m;
  m.V.resize(n, 3);
  std::vector<int> face;
  const double pi = 3.14159265358979323846;
  for (int k = 0; k < n; ++k) {
    const double r = k % 2 == 0 ? 1.0 : 0.5, t = 2 * pi * k / n;
    m.V.row(k) << r * std::cos(t), r * std::sin(t), 0;
    face.push_back(k);
  }
  m.faces = {face};
  const double area = n * 0.5 * 1.0 * 0.5 * std::sin(2 * pi / n);  // n triangles about the centre
  const TriMesh t = triangulate(m);
  ASSERT_EQ(t.num_faces(), n - 2);
  const auto [sum, upward] = unsigned_area_and_upward(t);
  EXPECT_NEAR(sum, polygon_area(m, 0), 1e-9);
  EXPECT_NEAR(sum, area, 1e-9);
  EXPECT_TRUE(upward);
}

TEST(Triangulate, ACornerOnAStraightSideGetsNoTriangleWithoutArea) {
  // A triangle whose side 0–2 has a corner at its middle (1, 0), as a stitched T-junction leaves
  // it, listed from that side's end: a fan from corner 0 would give the triangle 0, 1, 2 with
  // no area.
  PolyMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 2, 0, 0, 1, 2, 0;
  m.faces = {{0, 1, 2, 3}};
  const TriMesh t = triangulate(m);
  ASSERT_EQ(t.num_faces(), 2);
  const auto [area, upward] = unsigned_area_and_upward(t);
  EXPECT_NEAR(area, 2.0, 1e-12);
  EXPECT_TRUE(upward);
  EXPECT_EQ(count_slivers(t), 0);
}
