#pragma once
/// \file support_mesh.h
/// The support mesh of the tessellation: the rest surface M and the deformed surface M' (same
/// connectivity) refined together by conforming midpoint splits, with a map from every refined
/// triangle back to the triangle of the original M it lies in. Points found on the refined mesh
/// (triangle + barycentrics) are mapped back to the original M exactly: refined triangles lie in
/// the planes of their parents.
///
/// Cost: one pass is O(F) time and memory (the split edges sorted); `refine_to_length` does
/// O(log(max edge / target)) passes.

#include <array>
#include <functional>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct SupportMesh {
  TriMesh rest;      ///< refined M (where the output lives), metres
  TriMesh deformed;  ///< refined M' (where distances are measured)
  /// The original mesh's triangles (its vertices keep their ids in the refined mesh).
  Triangles original;
  /// Per refined triangle: the triangle of the original mesh that contains it.
  std::vector<int> parent;
  /// Per refined vertex: (a, a) if it is original vertex a; (a, b), a < b, if it lies inside
  /// the original edge a–b; (-1, -1) if inside an original triangle.
  std::vector<std::array<int, 2>> origin;
  /// Per refined vertex, where it lies on the original mesh as barycentric weights — exact
  /// dyadic numbers, as midpoint splits make them: inside edge (a, b) the weights of a and b
  /// (entries 0 and 1); inside a triangle (`origin_face`) the weights of its three corners.
  std::vector<Vec3> origin_weights;
  std::vector<int> origin_face;  ///< per refined vertex: the original triangle it is inside, or -1
  /// Per refined vertex: the lower-numbered end of the edge whose midpoint it is (-1 for an
  /// original vertex), a vertex next to it with a smaller number.
  std::vector<int> split_end;
};

/// The unrefined support mesh of (rest, deformed). Throws Error when the two meshes do not have
/// the same connectivity or hold non-finite coordinates.
SupportMesh make_support_mesh(const TriMesh& rest, const TriMesh& deformed);

/// One conforming refinement pass: every edge (a, b) for which `split(a, b)` is true is split at
/// its midpoint (on both M and M'); triangles with 1, 2 or 3 split edges are divided into 2, 3
/// or 4 (the 3-split pattern picks the shorter diagonal on M'). Returns the number of edges split.
/// `source`, when given, receives per new triangle the index of the triangle it came from.
int refine_support_mesh(SupportMesh& mesh, const std::function<bool(int, int)>& split,
                        std::vector<int>* source = nullptr);

/// Splits until every edge of M' is at most `max_edge` long. Returns the number of passes.
/// `source`, when given, receives per new triangle the triangle of the mesh before the call.
int refine_to_length(SupportMesh& mesh, double max_edge, std::vector<int>* source = nullptr);

/// Position on the original mesh of the point (triangle t of the support mesh, barycentrics b):
/// the original triangle and its barycentrics.
std::pair<int, Vec3> to_original(const SupportMesh& mesh, int t, const Vec3& b);

}  // namespace gridshell
