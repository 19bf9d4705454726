#pragma once
/// \file nearest.h
/// Nearest points: for each query, the indices of its k closest points of a point set
/// (Euclidean, CGAL's kd-tree). Cost: O(P log P) to build, O(log P) per query.

#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

/// Per query row, the indices of the min(k, points) nearest rows of `points`, nearest first.
/// Ties are broken by the tree, deterministically. `points` must not be empty (k ≥ 1).
std::vector<std::vector<int>> nearest_points(const Points& points, const Points& queries,
                                             int k = 1);

}  // namespace gridshell
