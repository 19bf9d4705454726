#pragma once
/// \file recover_quads.h
/// The original quad grid-shell of a shared surface file that stores each quad as two triangles
/// (Botanic.ply: Tang et al.'s 1076 quads as 2152 triangles): `baseline --kind original`.
///
/// Method: Tang's panels are planar, so the two halves of a panel are coplanar while two
/// triangles of neighbouring panels meet at the surface's bending angle. Adjacent triangles are
/// paired greedily, smallest fold first (angle between their normals, plus 1/100 of the pair's
/// summed defect from right angles at its four corners, which decides on flat parts), when the
/// pair is a convex quad; a triangle still alone is paired through the shortest augmenting path
/// (alternating unpaired and paired neighbours, breadth-first, no blossom shrinking: a path that
/// visits a triangle twice is not applied); the rest stay triangles. On Botanic.ply this gives
/// 1076 quads, no triangle, 98.5 % interior joints of valence 4 and a median panel bend of
/// 1.5e-4 (tests/quad_aniso_test.cpp; pairing by the largest angle instead: 88 %, 2.6e-4, with
/// 238 quads bent over 1 %).
/// O(F log F). (scripts/tang_quads.py handles British Quad's other encoding: four triangles
/// around a centre vertex per quad.)

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct RecoveredQuads {
  PolyMesh mesh;      ///< same vertices as the input; quads, and triangles left unpaired
  int greedy = 0;     ///< quads from the greedy pass
  int augmented = 0;  ///< triangles paired by an augmenting path (re-pairing others)
  int triangles = 0;  ///< triangles left
};

/// Throws Error("surface", …) for a mesh whose triangles are not consistently oriented.
RecoveredQuads recover_quads(const TriMesh& mesh);

}  // namespace gridshell
