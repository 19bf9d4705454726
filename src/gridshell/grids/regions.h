#pragma once
/// \file regions.h
/// From a labelling of the triangles of a fine mesh to a polygon mesh: every connected set of
/// equally-labelled triangles (a region) becomes one polygon whose corners are the junctions of
/// the labelling — vertices where three or more regions meet, where two regions meet on the
/// mesh boundary, and sharp corners of the boundary. The borders between junctions become
/// straight edges (beams). Used by the quad baseline; the same extraction rule as a discrete
/// Voronoi diagram.

#include <numbers>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct RegionOptions {
  /// Regions smaller than this area are merged into the neighbour they share most border with.
  double min_area = 0;
  /// A boundary vertex is a sharp corner when its boundary turns by more than this many degrees
  /// (mesh/geometry.h boundary_corners). The default is 0.5 rad ≈ 28.6°.
  double corner_angle_deg = 90 / std::numbers::pi;
};

struct RegionMesh {
  PolyMesh mesh;                   ///< one polygon per region
  std::vector<int> source_vertex;  ///< per polygon vertex: the fine-mesh vertex it sits on
  std::vector<int> face_label;     ///< per polygon: the label of its region
};

/// Extracts the polygon mesh of the labelling. Regions that are not disks or have fewer than
/// three junctions are merged into a neighbour; throws Error if that cannot make them valid.
RegionMesh extract_regions(const TriMesh& mesh, std::vector<int> face_label,
                           const RegionOptions& options = {});

}  // namespace gridshell
