// Mesh topology and validity checks on small hand-made meshes.

#include <gtest/gtest.h>

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
