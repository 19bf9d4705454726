// mesh/overlaps.h on hand-made grids whose overlaps are known by construction.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "gridshell/mesh/overlaps.h"
#include "gridshell/mesh/topology.h"

using namespace gridshell;

namespace {

/// An n × n grid of unit quads in the plane z = 0, counter-clockwise about +z.
PolyMesh plane_grid(int n) {
  PolyMesh g;
  g.V.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) g.V.row(j * (n + 1) + i) << i, j, 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      g.faces.push_back({a, a + 1, a + n + 2, a + n + 1});
    }
  return g;
}

/// Appends the square [x0, x0 + s] × [y0, y0 + s] at height z as a face of its own.
void add_square(PolyMesh& g, double x0, double y0, double s, double z) {
  const int first = g.num_vertices();
  g.V.conservativeResize(first + 4, 3);
  g.V.row(first) << x0, y0, z;
  g.V.row(first + 1) << x0 + s, y0, z;
  g.V.row(first + 2) << x0 + s, y0 + s, z;
  g.V.row(first + 3) << x0, y0 + s, z;
  g.faces.push_back({first, first + 1, first + 2, first + 3});
}

Overlaps overlaps_of(const PolyMesh& g) { return find_overlaps(g, build_topology(g)); }

}  // namespace

TEST(Overlaps, AGridWithoutFoldsHasNone) {
  EXPECT_EQ(overlaps_of(plane_grid(6)).count(), 0);
  // The same grid bent round a cylinder of radius 2 (a barrel vault): still none.
  PolyMesh g = plane_grid(6);
  for (int v = 0; v < g.num_vertices(); ++v) {
    const double x = g.V(v, 0);
    g.V.row(v) << 2 * std::sin(x / 2), g.V(v, 1), 2 * std::cos(x / 2);
  }
  EXPECT_EQ(overlaps_of(g).count(), 0);
}

TEST(Overlaps, TwoSquaresShiftedByHalfCrossTwice) {
  // [0, 1]² and [0.5, 1.5]²: the first's right side crosses the second's bottom, its top the
  // second's left; no corner of either is inside the other but (1, 1) and (0.5, 0.5).
  PolyMesh g;
  add_square(g, 0, 0, 1, 0);
  add_square(g, 0.5, 0.5, 1, 0);
  const Overlaps ov = overlaps_of(g);
  EXPECT_EQ(ov.crossing_edges.size(), 2u);
  ASSERT_EQ(ov.covered_vertices.size(), 2u);
  EXPECT_EQ(ov.covered_vertices[0][0], 2);  // (1, 1) inside the second square
  EXPECT_EQ(ov.covered_vertices[0][1], 1);
  EXPECT_EQ(ov.covered_vertices[1][0], 4);  // (0.5, 0.5) inside the first
  EXPECT_EQ(ov.covered_vertices[1][1], 0);
}

TEST(Overlaps, APanelOverSmallerOnesCoversTheirJoints) {
  // A 2 × 2 grid, and the panel [0.6, 1.4]² over its middle joint (1, 1) without using it: that
  // joint is inside the panel, each of the panel's corners inside one of the grid's quads, and
  // the four beams from (1, 1) cross the panel's sides.
  PolyMesh g = plane_grid(2);
  add_square(g, 0.6, 0.6, 0.8, 0);
  const Overlaps ov = overlaps_of(g);
  ASSERT_EQ(ov.covered_vertices.size(), 5u);
  EXPECT_EQ(ov.covered_vertices[0][0], 4);  // the grid's middle joint…
  EXPECT_EQ(ov.covered_vertices[0][1], 4);  // …inside the added panel
  for (int k = 1; k < 5; ++k) EXPECT_EQ(ov.covered_vertices[k][0], 8 + k);  // its corners
  EXPECT_EQ(ov.crossing_edges.size(), 4u);
}

TEST(Overlaps, TwoLayersOfARoofDoNotOverlap) {
  // The same square 5 m above another (two sides of a folded surface) and a square touching
  // the grid along a shared side: neither is an overlap.
  PolyMesh g;
  add_square(g, 0, 0, 1, 0);
  add_square(g, 0, 0, 1, 5);
  EXPECT_EQ(overlaps_of(g).count(), 0);
  PolyMesh touching = plane_grid(1);
  add_square(touching, 1, 0, 1, 0);  // shares the side x = 1 (by position, not by joints)
  EXPECT_EQ(overlaps_of(touching).count(), 0);
}

TEST(Overlaps, AFoldedStripIsFound) {
  // A strip of three quads whose last joint pair is pulled back over the middle quad: the last
  // quad turns over and lies on the middle one.
  PolyMesh g = plane_grid(1);
  g.V.conservativeResize(8, 3);
  g.V.row(4) << 2, 0, 0;
  g.V.row(5) << 2, 1, 0;
  g.V.row(6) << 0.5, 0.2, 0;  // the third quad's far side, back over the first quad
  g.V.row(7) << 0.5, 0.8, 0;
  g.faces.push_back({1, 4, 5, 3});
  g.faces.push_back({4, 6, 7, 5});
  const Overlaps ov = overlaps_of(g);
  EXPECT_GT(ov.count(), 0);
  for (const auto& [v, f] : ov.covered_vertices) {
    EXPECT_TRUE(v == 6 || v == 7);
    EXPECT_EQ(f, 0);
  }
}
