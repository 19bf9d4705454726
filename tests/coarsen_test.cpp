// The coarsened analysis surface (mesh/coarsen.h): what stays exact (supports, corners, the
// boundary's vertices, every vertex on the input surface) and how much coarser it gets.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "gridshell/field/transfer.h"
#include "gridshell/mesh/coarsen.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/projector.h"
#include "gridshell/surfaces/builtin.h"

using namespace gridshell;

namespace {

double boundary_length(const TriMesh& m) {
  const Topology t = build_topology(m);
  double total = 0;
  for (const auto& loop : t.boundary_loops)
    for (std::size_t k = 0; k < loop.size(); ++k)
      total += (m.vertex(loop[(k + 1) % loop.size()]) - m.vertex(loop[k])).norm();
  return total;
}

double min_angle_deg(const TriMesh& m) {
  double worst = 180;
  for (int f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = m.vertex(m.F(f, k)), b = m.vertex(m.F(f, (k + 1) % 3)),
                 c = m.vertex(m.F(f, (k + 2) % 3));
      const double cosine = (b - a).normalized().dot((c - a).normalized());
      worst = std::min(worst, std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / M_PI);
    }
  return worst;
}

}  // namespace

TEST(Coarsen, ParaboloidKeepsBoundarySupportsAndSurface) {
  BuiltinOptions bo;
  bo.res = 96;  // edges 20/96 ≈ 0.21 m
  const Surface fine = make_builtin("paraboloid", bo);
  const CoarseSurface c = coarsen_surface(fine, {.edge_length = 1.0});
  const TriMesh& m = c.surface.mesh;
  // Edges of ≥ 1 m on a 20 m square: ~ (20/1.2)² · 2 ≈ 550 triangles, far fewer than 18 432.
  EXPECT_LT(m.num_faces(), fine.mesh.num_faces() / 15);
  EXPECT_GT(m.num_faces(), 200);
  EXPECT_TRUE(check_mesh(to_poly(m)).ok());
  // The boundary is a polyline through some of the input's boundary vertices (each side a
  // parabola of rise 2 m over 20 m: its chords lose < 0.1 % of the length), with all four corners.
  EXPECT_LT(boundary_length(m), boundary_length(fine.mesh));
  EXPECT_NEAR(boundary_length(m) / boundary_length(fine.mesh), 1.0, 1e-3);
  const Topology t = build_topology(m);
  int corners = 0;
  for (int v = 0; v < m.num_vertices(); ++v) {
    if (!t.on_boundary[v]) continue;
    ASSERT_GE(c.source_vertex[v], 0) << "a boundary vertex moved";
    EXPECT_EQ((m.vertex(v) - fine.mesh.vertex(c.source_vertex[v])).norm(), 0.0);
    if (std::abs(std::abs(m.V(v, 0)) - 10) < 1e-12 && std::abs(std::abs(m.V(v, 1)) - 10) < 1e-12)
      ++corners;
  }
  EXPECT_EQ(corners, 4);
  // Every boundary vertex of the paraboloid is a support, so the supports are the boundary.
  EXPECT_EQ(c.surface.supports, boundary_vertices(t));
  // Every vertex lies on the input surface (the fine mesh), and the area shrinks only by the
  // chords of the coarser triangles (curvature 2·4/10² = 0.08 /m, edges ≈ 1.2 m: < 1 %).
  const SurfaceProjector on_fine(fine.mesh);
  double worst = 0;
  for (int v = 0; v < m.num_vertices(); ++v) worst = std::max(worst, on_fine.distance(m.vertex(v)));
  EXPECT_LT(worst, 1e-12);
  EXPECT_NEAR(surface_area(m) / surface_area(fine.mesh), 1.0, 0.01);
  EXPECT_LT(surface_area(m), surface_area(fine.mesh));
  // Shortest-edge-first collapses to midpoints keep the triangles reasonable for the shell FEM.
  EXPECT_GT(min_angle_deg(m), 10.0);
}

TEST(Coarsen, InteriorSupportStaysPut) {
  BuiltinOptions bo;
  bo.res = 40;
  Surface s = make_builtin("paraboloid", bo);
  const int centre = 20 * 41 + 20;  // grid vertex (20, 20): the apex
  ASSERT_NEAR(s.mesh.V(centre, 2), 4.0, 1e-12);
  s.supports.push_back(centre);
  std::sort(s.supports.begin(), s.supports.end());
  const CoarseSurface c = coarsen_surface(s, {.edge_length = 2.0});
  int found = 0;
  for (int v : c.surface.supports)
    if (c.source_vertex[v] == centre &&
        (c.surface.mesh.vertex(v) - s.mesh.vertex(centre)).norm() == 0)
      ++found;
  EXPECT_EQ(found, 1);
  EXPECT_LT(c.surface.mesh.num_faces(), s.mesh.num_faces() / 10);
}

// The copy's map to the input's triangles, found with the coarsening's own tree, is the map
// nearest_faces builds its tree for, entry for entry (ties between equally near triangles, where
// a centroid's closest point lies on a shared edge, included).
TEST(Coarsen, NearestInputFacesAreThoseOfNearestFaces) {
  for (const char* spec : {"paraboloid:res=96", "funicular:res=64", "barrel:res=64"})
    for (double edge : {0.6, 1.5}) {
      const Surface fine = make_builtin(spec);
      const CoarseSurface c = coarsen_surface(fine, {.edge_length = edge});
      ASSERT_LT(c.surface.mesh.num_faces(), fine.mesh.num_faces()) << spec;
      EXPECT_EQ(c.nearest_input_face, nearest_faces(fine.mesh, c.surface.mesh)) << spec << edge;
    }
  EXPECT_TRUE(coarsen_surface(make_builtin("paraboloid", {}), {}).nearest_input_face.empty());
}

TEST(Coarsen, ZeroLengthCopiesTheInput) {
  const Surface s = make_builtin("paraboloid", {});
  const CoarseSurface c = coarsen_surface(s, {});
  EXPECT_EQ(c.surface.mesh.V, s.mesh.V);
  EXPECT_EQ(c.surface.mesh.F, s.mesh.F);
  EXPECT_EQ(c.surface.supports, s.supports);
  EXPECT_EQ(c.source_vertex.size(), static_cast<std::size_t>(s.mesh.num_vertices()));
}
