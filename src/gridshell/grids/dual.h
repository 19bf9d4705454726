#pragma once
/// \file dual.h
/// The triangle baseline: the dual of a Voronoi tessellation. Each interior joint of valence 3
/// becomes a triangle joining the seeds of its three cells; seeds become the joints.

#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

/// `seeds[f]` is the seed (generator) of face f of `cells`. Triangles are oriented like the
/// cells. Joints of valence other than 3 (rare) are fanned into triangles around their cells.
PolyMesh dual_triangulation(const PolyMesh& cells, const std::vector<Vec3>& seeds);

}  // namespace gridshell
