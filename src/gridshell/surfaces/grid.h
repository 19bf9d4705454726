#pragma once
/// \file grid.h
/// Structured triangle grids for tests, benchmarks and benchmark models: (nu+1) × (nv+1) nodes
/// mapped by `map(s, t)` with s, t ∈ [0, 1], each cell split along alternating diagonals
/// (chequerboard), so the pattern has no preferred direction.

#include <functional>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

TriMesh parametric_grid(int nu, int nv, const std::function<Vec3(double s, double t)>& map);

/// The flat rectangle [0, w] × [0, h] at z = 0 as an nx × ny parametric grid.
TriMesh flat_grid(int nx, int ny, double w, double h);

}  // namespace gridshell
