#pragma once
/// \file plane_cut.h
/// Splitting a triangle mesh along planes: every triangle crossed by the plane n·x = c is split
/// so that the plane runs along mesh edges. Used to lay a plan grid onto a surface (the quad
/// baseline) and to cut a symmetric surface into the sector that is tessellated.
/// Cost: O(V + F) per plane.

#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct CutPlane {
  Vec3 n = Vec3::UnitX();  ///< unit normal
  double c = 0;            ///< offset: the plane is n·x = c
  double signed_distance(const Vec3& x) const { return n.dot(x) - c; }
};

/// A surface together with per-vertex data that must follow the cuts.
struct CutMesh {
  TriMesh mesh;
  std::vector<char> support;     ///< per vertex
  std::vector<int> parent_face;  ///< per face: the face of the original mesh it came from
};

CutMesh make_cut_mesh(const Surface& surface);

/// Splits `m` along `plane`. Vertices closer than `snap` to the plane are moved exactly onto it;
/// new vertices on an edge whose both ends are supports are supports.
void cut_along_plane(CutMesh& m, const CutPlane& plane, double snap);

/// Keeps the faces on the side n·x ≥ c (after cutting along the plane), dropping unused
/// vertices. Returns for each kept vertex its index in the input.
std::vector<int> keep_side(CutMesh& m, const CutPlane& plane);

}  // namespace gridshell
