#pragma once
/// \file quad_grid.h
/// The paper's quad baseline: an isotropic square grid drawn in plan, lifted vertically onto the
/// surface, with the cells at the boundary clipped by it (slivers merged into a neighbour, and
/// stub beams at the boundary collapsed into their boundary end, so no beam is absurdly short). The
/// grid is centred on the plan's bounding box, so a surface symmetric about its mid-planes gets a
/// symmetric grid.

#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct QuadGridOptions {
  double spacing = 1.0;            ///< grid spacing in plan (m)
  double angle = 0.0;              ///< rotation of the grid in plan (radians)
  double min_cell_fraction = 0.3;  ///< cells smaller than this × spacing² are merged
  /// Beams shorter than this × spacing with an end on the boundary are collapsed into that end.
  double min_edge_fraction = 0.1;
};

struct GridShell {
  PolyMesh mesh;
  std::vector<int> supports;  ///< sorted joint ids
};

/// Builds the grid. Joints lie exactly on the input surface (on its triangles).
GridShell quad_grid(const Surface& surface, const QuadGridOptions& options);

/// Total beam (edge) length of a polygon mesh.
double total_edge_length(const PolyMesh& mesh);

/// Solves for the spacing whose grid has total beam length `length` (within `tolerance`
/// relative, by a secant iteration on length ∝ 1/spacing). Throws Error if not reached.
GridShell quad_grid_for_length(const Surface& surface, double length, QuadGridOptions options,
                               double tolerance = 0.02);

}  // namespace gridshell
