#pragma once
/// \file repair.h
/// Making a surface read from a file usable when its exporter left some mess behind. What is
/// repaired, in this order:
///   1. duplicate vertices (exporters that split the mesh at seams or per face, or mesh the
///      patches of a CAD surface one by one): vertices within kWeldTolerance × the bounding
///      box's diagonal of each other (transitively) are merged into the lowest-numbered of
///      them, so the surface is connected again;
///   2. faces that then use a vertex twice: a repeated corner next to itself is removed
///      (a quad 0 1 1 2 becomes the triangle 0 1 2); a face left with fewer than 3 corners, or
///      that still visits a vertex twice, has no area and is dropped;
///   3. unreferenced vertices (construction points, sometimes even coloured as supports):
///      dropped, the other vertices keep their order;
///   4. T-junctions (patches meshed one by one, each with its own vertices along a shared edge:
///      the seam is then two boundaries, and would be read as supports): a boundary vertex that
///      lies on another face's boundary edge — within kTJunctionTolerance × the edge's length of
///      it (the edge is a chord of the curved seam the vertex was placed on), strictly between its
///      ends, and with a boundary edge of its own along it (within kTJunctionAngle degrees) — is
///      inserted into that face as a corner, so both sides of the seam walk the same vertices;
///   5. face orientation (exporters and hand-edited files often mix clockwise and
///      counter-clockwise faces; topology would see each such edge as two boundary edges):
///      faces are made to agree across every edge they share with exactly one other face, in
///      each connected piece keeping the orientation of the larger area (so a consistently
///      oriented file is left untouched). A non-orientable piece (a Möbius strip) keeps the
///      conflicts it cannot resolve; `inconsistent_edges` counts them. Edges of three or more
///      faces (a fin, two roofs meeting in a T) are left alone and counted in
///      `non_manifold_edges`: which faces to drop is the designer's choice.
/// Sliver triangles are not repaired (the analyses cope with them; moving vertices would change
/// the designer's surface): `count_slivers` lets the loader say how many there are.
/// Cost: O(V log V + S log S), S the sum of face sizes.

#include <string>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

/// Vertices closer than this fraction of the bounding box's diagonal are one vertex: 30 µm on a
/// 30 m roof, far below any member or panel, and well above the rounding of coordinates written
/// in single precision (relative 6e-8) near the roof.
inline constexpr double kWeldTolerance = 1e-6;

/// Step 4: how far (× the edge's length) a boundary vertex may lie from another face's boundary
/// edge to be stitched into it: 6 % covers the chord of a seam bent by 28° over the edge (the
/// sagitta of an arc is ≈ its length × its turn / 8), far more than one patch's mesh bends
/// between neighbouring vertices.
inline constexpr double kTJunctionTolerance = 0.06;
/// Step 4: the largest angle between the edge and one of the vertex's own boundary edges.
inline constexpr double kTJunctionAngle = 20.0;

struct RepairReport {
  int merged_vertices = 0;        ///< duplicate vertices merged into another one
  int close_vertices = 0;         ///< of those, the ones not exactly at the same position
  int shortened_faces = 0;        ///< faces that lost a repeated corner and are still polygons
  int dropped_faces = 0;          ///< faces without area (fewer than 3 distinct corners)
  int unreferenced_vertices = 0;  ///< vertices no face uses, dropped
  int t_junctions = 0;            ///< boundary vertices inserted into a face's edge (step 4)
  int reversed_faces = 0;         ///< faces whose corner order was reversed (step 5)
  int inconsistent_edges = 0;     ///< edges still walked the same way by both faces (step 5)
  int non_manifold_edges = 0;     ///< edges of three or more faces (a fin): left as they are
  /// For each vertex of the mesh as it was: its id after the repair, or -1 when it was dropped
  /// (an unreferenced vertex). Duplicates map to the id of the vertex they were merged into.
  std::vector<int> new_id;

  /// True when something was repaired (steps 1–5; a non-orientable piece alone is not).
  bool changed() const {
    return merged_vertices + shortened_faces + dropped_faces + unreferenced_vertices + t_junctions +
               reversed_faces >
           0;
  }
  /// What was done, e.g. "merged 9 duplicate vertices, dropped 3 unreferenced vertices", and the
  /// edges left inconsistent or non-manifold; empty when there is nothing to say.
  std::string describe() const;
};

/// Repairs `mesh` in place as described above. Indices must be in range (as io::read_mesh
/// guarantees). Never throws; the result may have no faces left (the caller decides).
RepairReport repair_mesh(PolyMesh& mesh);

/// Number of sliver triangles: those whose smallest angle is below `min_angle_degrees`
/// (zero-area triangles included).
int count_slivers(const TriMesh& mesh, double min_angle_degrees = 1.0);

}  // namespace gridshell
