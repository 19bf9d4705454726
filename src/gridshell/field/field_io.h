#pragma once
/// \file field_io.h
/// Importing an external stress field (`--field FILE`) as per-triangle principal stresses.
///
/// Formats (chosen by extension, `.blk` or `.csv`; anything else is tried as BLK):
///   - BLK: tab/space separated text, one header line, then per point
///     `x y z s1 v1x v1y v1z s2 v2x v2y v2z` (position, principal stresses and their directions;
///     the format of ../shared/data/stress-fields). Points need not coincide with mesh vertices:
///     each mesh vertex takes the nearest point (Euclidean, kd-tree), which tolerates the 0.2 m
///     normal offset of the published files.
///   - CSV: `vertex,s1,s2,d1x,d1y,d1z` per mesh vertex (0-based id of the surface as loaded, after
///     the repair of surfaces/load.h; an optional header line);
///     the second direction is n × d1 in each triangle. Every vertex must appear.
///
/// Per triangle, the three vertex tensors σ = s1 d1 d1ᵀ + s2 d2 d2ᵀ are averaged (sign-free),
/// projected onto the triangle's plane and diagonalised: s1 ≥ s2 and unit tangent directions.
/// Cost: O((V + P) log P). Throws Error(path, ...) for a missing/malformed file, non-finite
/// values, out-of-range or missing vertices, or an empty point set.

#include <string>

#include "gridshell/fem/principal_stress.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell {

StressField read_field_file(const std::string& path, const TriMesh& mesh);

/// Per-vertex symmetric 3×3 stress tensors → per-triangle
/// principal stresses in the triangle planes (the last step of read_field_file).
StressField principal_stress_from_vertex_tensors(const TriMesh& mesh,
                                                 const std::vector<Eigen::Matrix3d>& tensors);

}  // namespace gridshell
