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
  m.V.row(4) << 0, 0, 0;   // duplicate of vertex 0
  m.V.row(5) << 5, 5, 5;   // unreferenced
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
