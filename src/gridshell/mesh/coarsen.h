#pragma once
/// \file coarsen.h
/// A coarser copy of a finely meshed surface, for the stages that only need the resolution of
/// the cells (the shell FEM, the field, the metric; docs/shell.md "Analysis resolution").
///
/// Method: CGAL's edge-collapse simplification (Surface_mesh_simplification), shortest edge
/// first, until no edge is shorter than `edge_length`; a collapse that would turn a triangle's
/// normal by more than ~90° is refused (CGAL's bounded-normal-change filter). What stays exact:
///   - the supports and the sharp corners of the boundary never move and are never removed,
///     nor is a boundary vertex where the supported part of the boundary ends;
///   - the other boundary vertices are only removed, never moved (the boundary of the copy runs
///     through a subset of the input's boundary vertices: exact where the boundary is straight,
///     a chord of it where it curves);
///   - an interior vertex of the copy is placed at an edge midpoint and then projected onto the
///     input surface (closest point), so every vertex of the copy lies on the input surface.
/// A support of the copy is a vertex that was a support of the input, at the same position.
/// Cost: O(F log F) for F input triangles (≈ 1 s for 250 K triangles). Deterministic.

#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct CoarsenOptions {
  double edge_length = 0;        ///< collapse edges shorter than this (m); ≤ 0 = copy as is
  double corner_angle_deg = 30;  ///< boundary corners kept: turning angle above this
};

struct CoarseSurface {
  Surface surface;                 ///< the coarser copy (supports sorted)
  std::vector<int> source_vertex;  ///< per vertex of the copy: the input vertex it was (boundary
                                   ///< and supports), or −1 (interior, moved)
  /// Per triangle of the copy: the input triangle nearest its centroid, found with the tree the
  /// copy's vertices were projected with (mesh/nearest_triangles.h) — bit for bit
  /// `nearest_faces(input, copy)` of field/transfer.h, which on a 2 M-triangle input would build
  /// that tree again. Empty when the copy is the input.
  std::vector<int> nearest_input_face;
};

/// The coarsened copy of `surface` (see the file comment). The input is returned unchanged
/// (source_vertex = identity) when `edge_length` ≤ 0 or when its triangles do not form an
/// oriented manifold (CGAL's Surface_mesh refuses them).
CoarseSurface coarsen_surface(const Surface& surface, const CoarsenOptions& options);

}  // namespace gridshell
