#pragma once
/// \file dual.h
/// The polygonal dual of a triangle mesh, a valence-3 hex-dominant polygon mesh on (near) the
/// surface: the stand-in for a Voronoi tessellation in tests and benchmarks.
///
/// Polygon vertices: one per triangle (its centroid), one per boundary edge (its midpoint), and
/// the corners of M's boundary (boundary vertices where the boundary turns by more than
/// `corner_angle_deg`). One polygon per vertex of M: its incident triangles' centroids in order;
/// for a boundary vertex also the midpoints of its two boundary edges (and itself when it is a
/// corner), so the polygons cover M up to its boundary. Interior vertices have valence 3,
/// boundary midpoints valence 3, corners valence 2. Faces are oriented like M's triangles.
/// Cost O(n). Throws Error for a non-manifold input.

#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct DualMesh {
  PolyMesh mesh;
  std::vector<char> on_boundary;  ///< per polygon vertex: lies on M's boundary
  std::vector<char> corner;       ///< per polygon vertex: a corner of M's boundary
};

DualMesh dual_polygon_mesh(const TriMesh& surface, double corner_angle_deg = 30.0);

}  // namespace gridshell
