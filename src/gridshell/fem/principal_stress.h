#pragma once
/// \file principal_stress.h
/// The value the shell analysis hands to the field stage: per triangle, the principal membrane
/// stresses s1 ≥ s2 (Pa, tension positive) and their unit directions in the triangle's plane.

#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct PrincipalStress {
  double s1 = 0;              ///< larger principal membrane stress (Pa)
  double s2 = 0;              ///< smaller principal membrane stress (Pa)
  Vec3 d1 = Vec3::UnitX();    ///< unit direction of s1, tangent to the triangle
  Vec3 d2 = Vec3::UnitY();    ///< unit direction of s2 (⊥ d1, tangent)
};

/// One entry per triangle of the analysed mesh.
using StressField = std::vector<PrincipalStress>;

}  // namespace gridshell
