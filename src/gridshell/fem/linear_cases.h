#pragma once
/// \file linear_cases.h
/// Linear static analysis of one frame under several loads (load cases, or load combinations):
/// K is assembled and factorised once and each load costs one forward and one back substitution
/// through the same factor — what every frame code does with its load cases. For a linear
/// analysis the solution of a combination Σ γ_i case_i is Σ γ_i u_i, so solving the combinations'
/// own load vectors through the shared factor gives exactly what one analysis per combination
/// gives (the same matrix, factor and right-hand side), at a fraction of the cost.
///
/// Defined with the solver (fem/frame_solver.cpp). Cost: one assembly and one sparse Cholesky factorisation, then O(nnz(L)) per load. Not
/// thread-safe on one factor: the solves run one after another.

#include <memory>
#include <string>
#include <vector>

#include "gridshell/fem/frame_solver.h"

namespace gridshell::fem {

/// The full (6 per node of mesh.X) load vector of nodal loads on the model nodes, as discretize
/// builds FrameMesh::load_full. Throws Error(subject) for a force on a node no member uses, or a
/// moment on a node without rotational stiffness.
Eigen::VectorXd load_vector(const FrameMesh& mesh, const std::vector<NodalLoad>& loads,
                            const std::string& subject = "model");

/// Per load (full vectors, 6 per node of mesh.X) its linear solution (LinearResult: u,
/// displacements, element axial forces, reactions), every one holding the shared factorised K
/// in `stiffness` (linear_buckling reuses it; not to be used by two threads at once). Throws
/// Error(subject, "mechanism: ...") as linear_static does.
std::vector<LinearResult> linear_static_cases(const FrameMesh& mesh,
                                              const FrameAssembler& assembler,
                                              const std::vector<Eigen::VectorXd>& loads_full,
                                              const std::string& subject = "model");

}  // namespace gridshell::fem
