#pragma once
/// \file recover_quads.h
/// The original quad grid-shell of a shared surface file that stores each quad as two triangles
/// (Botanic.ply: Tang et al.'s 1076 quads as 2152 triangles): `baseline --kind original`.
///
/// Method: each triangle names as its diagonal the edge opposite its largest angle (a quad's
/// corners are near 90°, so the split's diagonal faces the largest angle of both halves);
/// where the triangles on both sides of an edge name it, the pair becomes the quad. Triangles
/// left over are then paired greedily with a left-over neighbour, flattest pair first (smallest
/// angle between the two normals), when the pair is convex; the rest stay triangles.
/// O(F log F). (scripts/tang_quads.py handles British Quad's other encoding: four triangles
/// around a centre vertex per quad.)

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct RecoveredQuads {
  PolyMesh mesh;        ///< same vertices as the input; quads, and triangles left unpaired
  int mutual = 0;       ///< quads from pairs that named each other's shared edge
  int greedy = 0;       ///< quads from the greedy second pass
  int triangles = 0;    ///< triangles left
};

/// Throws Error("surface", …) for a mesh whose triangles are not consistently oriented.
RecoveredQuads recover_quads(const TriMesh& mesh);

}  // namespace gridshell
