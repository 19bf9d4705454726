#pragma once
/// \file dual.h
/// The triangle baseline: the dual of a Voronoi tessellation. Each interior joint of valence 3
/// becomes a triangle joining the seeds of its three cells; seeds become the joints.

#include <vector>

#include "gridshell/grids/quad_grid.h"
#include "gridshell/mesh/mesh.h"
#include "gridshell/voronoi/tessellation.h"

namespace gridshell {

/// `seeds[f]` is the seed (generator) of face f of `cells`. Triangles are oriented like the
/// cells. Joints of valence other than 3 (rare) are fanned into triangles around their cells.
PolyMesh dual_triangulation(const PolyMesh& cells, const std::vector<Vec3>& seeds);

/// `baseline --kind tri`: the dual of the isotropic tessellation of `surface`. Its beams are
/// about √3 × longer than the Voronoi ones, so with `length` > 0 the tessellation's length target
/// starts at length/√3 and is corrected (at most `max_fits` tessellations) until the
/// triangulation's total is within `fit_tolerance` of `length`. Without a length the size
/// options of `tessellation` decide. Another seed (seed + 7919 k, up to 3) when extraction fails.
struct TriBaselineOptions {
  TessellationOptions tessellation;  ///< size (radius/cells) and seed; its length is set here
  double length = 0;                 ///< total beam length wanted (m); 0 = not fitted
  int max_fits = 6;
  double fit_tolerance = 0.02;
};
GridShell tri_baseline(const Surface& surface, const TriBaselineOptions& options);

}  // namespace gridshell
