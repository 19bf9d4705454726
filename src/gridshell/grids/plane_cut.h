#pragma once
/// \file plane_cut.h
/// Splitting a triangle mesh along planes (mesh/geometry.h's Plane): every triangle crossed by
/// the plane is split so that the plane runs along mesh edges. Used to lay a plan grid onto a
/// surface (the quad baseline) and to cut a symmetric surface into the sector that is
/// tessellated (along the mirror planes of optimize/symmetry.h, the same type).
/// Cost: O(V + F) per plane.

#include <vector>

#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell {

/// A surface together with per-vertex data that must follow the cuts.
struct CutMesh {
  TriMesh mesh;
  std::vector<char> support;     ///< per vertex
  std::vector<int> parent_face;  ///< per face: the face of the original mesh it came from
};

CutMesh make_cut_mesh(const Surface& surface);

/// Splits `m` along `plane`. Vertices closer than `snap` to the plane are moved exactly onto it;
/// new vertices on an edge whose both ends are supports are supports.
void cut_along_plane(CutMesh& m, const Plane& plane, double snap);

/// Keeps the faces on the side the normal points to (signed distance of the centroid ≥ 0; cut
/// along the plane first), dropping unused vertices. Returns for each kept vertex its index in
/// the input.
std::vector<int> keep_side(CutMesh& m, const Plane& plane);

}  // namespace gridshell
