#pragma once
/// \file force_density.h
/// Form finding by the force-density method (Schek 1974). For a network of edges with force
/// densities q_e (force / length), fixed nodes and nodal loads p, equilibrium at each free node i
/// is  Σ_j q_ij (x_j − x_i) + p_i = 0 : one sparse SPD linear system per coordinate,
/// C_fᵀ Q C_f x_f = p_f − C_fᵀ Q C_x x_x. Inverting the hanging net (loads pointing up) gives a
/// compression-only shell.

#include <array>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct ForceDensityProblem {
  Points X;                               ///< start positions; fixed nodes keep theirs
  std::vector<std::array<int, 2>> edges;  ///< the network's bars
  std::vector<double> q;                  ///< force density per edge (> 0)
  std::vector<char> fixed;                ///< per node: 1 = anchored
  Points loads;                           ///< nodal loads (N), one row per node
};

struct ForceDensityResult {
  Points X;             ///< equilibrium positions
  double residual = 0;  ///< max over free nodes of |Σ q (x_j − x_i) + p_i| / max |p|
};

/// Solves the linear force-density equilibrium (one Cholesky factorisation, three solves).
/// Throws Error if a free node is not connected to any anchor.
ForceDensityResult solve_force_density(const ForceDensityProblem& problem);

/// The equilibrium residual of positions X for `problem` (as in ForceDensityResult::residual).
double force_density_residual(const ForceDensityProblem& problem, const Points& X);

}  // namespace gridshell
