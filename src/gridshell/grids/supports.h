#pragma once
/// \file supports.h
/// Which joints of a grid-shell are supported, given the supported vertices of the surface it was
/// built on: a joint lying on the surface boundary (within `tolerance`) is supported when the
/// boundary edge under it has a supported endpoint on each side (or it sits on a supported
/// vertex); each supported surface vertex that is not on the boundary (a column, as in Aquadom)
/// supports the joint nearest to it.

#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

/// `tolerance` is absolute (m); a good value is 1e-6 × the bounding-box diagonal.
std::vector<int> transfer_supports(const Points& joints, const Surface& surface, double tolerance);

}  // namespace gridshell
