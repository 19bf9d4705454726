// Plane cuts, label-region extraction and the quad baseline grid.

#include <gtest/gtest.h>

#include <algorithm>

#include "gridshell/grids/dual.h"
#include "gridshell/grids/plane_cut.h"
#include "gridshell/grids/quad_grid.h"
#include "gridshell/grids/regions.h"
#include "gridshell/grids/supports.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/surfaces/builtin.h"
#include "gridshell/surfaces/load.h"
#include "test_support.h"

using namespace gridshell;

TEST(PlaneCut, SplitsAlongThePlaneAndKeepsTheSurface) {
  Surface s = make_builtin("dome:res=12");
  const double area = surface_area(s.mesh);
  CutMesh c = make_cut_mesh(s);
  cut_along_plane(c, Plane{Vec3(0.37, 0, 0), Vec3(1, 0, 0)}, 1e-12);
  EXPECT_NEAR(surface_area(c.mesh), area, 1e-9 * area);  // same surface, only split
  EXPECT_TRUE(check_mesh(to_poly(c.mesh)).ok());
  // No triangle straddles the plane any more.
  for (int f = 0; f < c.mesh.num_faces(); ++f) {
    double lo = 1e300, hi = -1e300;
    for (int k = 0; k < 3; ++k) {
      const double d = c.mesh.V(c.mesh.F(f, k), 0) - 0.37;
      lo = std::min(lo, d), hi = std::max(hi, d);
    }
    EXPECT_FALSE(lo < -1e-12 && hi > 1e-12);
  }
  keep_side(c, Plane{Vec3(0.37, 0, 0), Vec3(1, 0, 0)});
  for (int v = 0; v < c.mesh.num_vertices(); ++v) EXPECT_GE(c.mesh.V(v, 0), 0.37 - 1e-12);
  Topology t = build_topology(c.mesh);
  EXPECT_EQ(t.boundary_loops.size(), 1u);
}

TEST(Regions, GridLabellingGivesQuads) {
  // A flat 12×12 grid labelled in 3×3 blocks gives a 4×4 quad mesh.
  TriMesh m;
  const int n = 12;
  m.V.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.V.row(j * (n + 1) + i) << i, j, 0;
  m.F.resize(2 * n * n, 3);
  std::vector<int> label;
  for (int j = 0, f = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      m.F.row(f++) << a, a + 1, a + n + 2;
      m.F.row(f++) << a, a + n + 2, a + n + 1;
      label.push_back((i / 3) * 10 + j / 3);
      label.push_back((i / 3) * 10 + j / 3);
    }
  RegionMesh r = extract_regions(m, label);
  EXPECT_EQ(r.mesh.num_faces(), 16);
  EXPECT_EQ(r.mesh.num_vertices(), 25);
  for (const auto& f : r.mesh.faces) EXPECT_EQ(f.size(), 4u);
  EXPECT_TRUE(check_mesh(r.mesh).ok());
  EXPECT_NEAR(total_edge_length(r.mesh), 2 * 5 * 12.0, 1e-12);
}

TEST(QuadGrid, OnBuiltinsIsAValidSymmetricGrid) {
  for (const char* spec : {"paraboloid", "dome", "court", "funicular"}) {
    SCOPED_TRACE(spec);
    Surface s = make_builtin(std::string(spec));
    GridShell g = quad_grid(s, {.spacing = 1.5});
    PolyMesh& m = g.mesh;
    MeshProblems p = check_mesh(m);
    EXPECT_TRUE(p.ok()) << (p.describe().empty() ? "" : p.describe()[0]);
    Topology t = build_topology(m);
    Topology st = build_topology(s.mesh);
    EXPECT_EQ(t.boundary_loops.size(), st.boundary_loops.size());
    EXPECT_EQ(euler_characteristic(m, t), euler_characteristic(to_poly(s.mesh), st));
    int quads = 0, interior = 0;
    for (int f = 0; f < m.num_faces(); ++f) {
      bool inner = true;
      for (int v : m.faces[f]) inner &= !t.on_boundary[v];
      if (inner) ++interior, quads += m.faces[f].size() == 4;
    }
    EXPECT_EQ(quads, interior);  // every interior cell is a quad
    EXPECT_FALSE(g.supports.empty());
    // Interior joints lie on the grid lines' crossings in plan (centre + (k+1/2)h).
    for (int v = 0; v < m.num_vertices(); ++v) {
      if (t.on_boundary[v]) continue;
      for (int c = 0; c < 2; ++c) {
        const double u = m.V(v, c) / 1.5 - 0.5;
        EXPECT_NEAR(u, std::round(u), 1e-9);
      }
    }
  }
}

TEST(QuadGrid, HitsATargetLength) {
  Surface s = make_builtin("funicular");
  GridShell g = quad_grid_for_length(s, 400.0, {});
  EXPECT_NEAR(total_edge_length(g.mesh), 400.0, 0.05 * 400.0);
}

TEST(QuadGrid, SharedSurfacesAtThePapersLengths) {
  SKIP_WITHOUT_SHARED_DATA();
  struct C {
    const char* file;
    double length;
  };
  for (C c : {C{"surfaces/Shell.ply", 415}, C{"surfaces/Botanic.ply", 2018},
              C{"surfaces/aquadom_Vouga.ply", 3898}, C{"surfaces/liliumVouga.ply", 1164}}) {
    SCOPED_TRACE(c.file);
    Surface s = load_surface(test::shared_file(c.file).string());
    GridShell g = quad_grid_for_length(s, c.length, {});
    EXPECT_NEAR(total_edge_length(g.mesh), c.length, 0.05 * c.length);
    EXPECT_TRUE(check_mesh(g.mesh).ok());
    // No stub beams where grid lines cross the boundary next to a corner or to each other
    // (Aquadom had a 0.3 mm beam, which made the frame's non-linear analysis fail).
    std::vector<double> len;
    for (const auto& e : build_topology(g.mesh).edges)
      len.push_back((g.mesh.vertex(e[0]) - g.mesh.vertex(e[1])).norm());
    std::sort(len.begin(), len.end());
    EXPECT_GT(len.front(), 0.05 * len[len.size() / 2]);
    EXPECT_EQ(build_topology(g.mesh).boundary_loops.size(),
              build_topology(s.mesh).boundary_loops.size());
  }
}

TEST(Dual, OfAQuadGridGivesConsistentlyOrientedTriangles) {
  Surface s = make_builtin("paraboloid");
  GridShell g = quad_grid(s, {.spacing = 2.0});
  std::vector<Vec3> seeds;
  for (const auto& f : g.mesh.faces) {
    Vec3 c = Vec3::Zero();
    for (int v : f) c += g.mesh.vertex(v) / static_cast<double>(f.size());
    seeds.push_back(c);
  }
  PolyMesh d = dual_triangulation(g.mesh, seeds);
  Topology t = build_topology(g.mesh);
  int expected = 0;  // an interior joint of valence k fans into k − 2 triangles
  for (int v = 0; v < g.mesh.num_vertices(); ++v)
    if (!t.on_boundary[v]) expected += static_cast<int>(t.vertex_faces[v].size()) - 2;
  EXPECT_EQ(d.num_faces(), expected);
  EXPECT_TRUE(check_mesh(d).inconsistent_orientation == 0);
  for (int f = 0; f < d.num_faces(); ++f) {
    const Vec3 a = d.vertex(d.faces[f][0]), b = d.vertex(d.faces[f][1]),
               c = d.vertex(d.faces[f][2]);
    EXPECT_GT((b - a).cross(c - a).z(), 0);
  }
}

TEST(Supports, TransferredByPositionMatchTheQuadGrid) {
  Surface s = make_builtin("barrel");
  GridShell g = quad_grid(s, {.spacing = 1.7});
  std::vector<int> again = transfer_supports(g.mesh.V, s, 1e-9);
  EXPECT_EQ(again, g.supports);
  for (int v : again) EXPECT_NEAR(g.mesh.V(v, 2), 0.0, 1e-9);  // barrel: ground edges only
}
