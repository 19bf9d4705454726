#pragma once
/// \file overlaps.h
/// Where a polygon mesh lying on a surface (a grid-shell) covers part of the roof twice: two beams
/// that cross without a joint, or a joint that lies inside a panel it does not belong to. Either is
/// a grid that cannot be built — two beams through one point, two panels of glass one over the
/// other — although every face alone may be a fine simple polygon.
///
/// Near each pair the surface is taken as flat: beams are seen along the mean of their ends'
/// normals (vertex normals from the faces' vector areas), a joint along the panel's normal. Two
/// beams cross when their views cross (not at a shared joint) and the crossing points on the two
/// beams are closer in space than a quarter of the beams' mean length; a joint is inside a panel
/// when its view is inside the panel's, farther than a thousandth of the panel's mean side from
/// its sides, and it lies within half that mean side of the panel's mean plane. The proximity
/// bounds keep two layers of the surface (a fold of the roof, its two sides) apart.

#include <array>
#include <vector>

#include "gridshell/mesh/mesh.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

struct Overlaps {
  /// Pairs of edges (ids into Topology::edges, the smaller first) whose beams cross.
  std::vector<std::array<int, 2>> crossing_edges;
  /// (vertex, face): a joint inside a face that does not use it.
  std::vector<std::array<int, 2>> covered_vertices;

  int count() const { return static_cast<int>(crossing_edges.size() + covered_vertices.size()); }
};

/// The overlaps of `mesh` (its topology `topo`). Candidate pairs come from CGAL's
/// box_intersection_d on the beams' and panels' bounding boxes, so the cost is about
/// O(n log n + pairs).
Overlaps find_overlaps(const PolyMesh& mesh, const Topology& topo);

}  // namespace gridshell
