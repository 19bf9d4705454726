#pragma once
/// \file split_cholesky.h
/// A sparse SPD solve on two cores that gives the same answer for any machine: one level of
/// nested dissection done by hand around CHOLMOD.
///
/// The node graph is cut by a METIS vertex separator S into halves A and B (no couplings
/// between A and B). Each half h is factorised by CHOLMOD (supernodal LLᵀ, its own METIS
/// ordering, S ordered last) as the matrix
///     K_h = [K_hh  K_hS]
///           [K_Sh  K_SS],
/// the two side by side. The trailing dense block L_SS of each factor gives the half's share
/// of the Schur complement: L_SS L_SSᵀ = K_SS − K_Sh K_hh⁻¹ K_hS, so the separator's matrix is
///     C = L_SS^A L_SS^Aᵀ + L_SS^B L_SS^Bᵀ − K_SS,
/// factorised densely (LAPACK dpotrf). Solve: forward substitution in each half with [b_h; 0]
/// gives w_h and K_Sh K_hh⁻¹ b_h = −L_SS w_h,S; x_S = C⁻¹(b_S + Σ_h L_SS w_h,S); then a backward
/// substitution in each half with w_h's S part replaced by L_SSᵀ x_S returns x_h.
///
/// The halves run side by side as two TBB tasks (so inside a parallel sweep, or with
/// `--threads 1`, they share the cores TBB has). Every step is a fixed sequence of floating-point
/// operations, so results are the same bits on any machine and thread count. The analysis
/// calls METIS and holds `lock_symbolic_analysis()` (core/cholmod_support.h).
///
/// Worth it for large models: at 50 K shell triangles (155 K dofs) the two halves cost about
/// half of the monolithic factorisation each; below ~30 K dofs the extra dense work does not pay.

#include <Eigen/Core>
#include <memory>
#include <vector>

struct cholmod_sparse_struct;

namespace gridshell::fem {

class SplitCholesky {
 public:
  SplitCholesky();
  ~SplitCholesky();
  SplitCholesky(const SplitCholesky&) = delete;
  SplitCholesky& operator=(const SplitCholesky&) = delete;

  /// Symbolic analysis. `K` is the upper triangle of the matrix in CSC (values not read),
  /// `dofs_per_node` consecutive dofs per node; `gp`/`gi` the upper pattern (with diagonal) of
  /// the node graph in CSC. Returns false when the graph does not split usefully (a separator
  /// over 6 % of the nodes, a half under 20 %, or a CHOLMOD failure): use a monolithic solver.
  bool analyze(const cholmod_sparse_struct& K, int dofs_per_node, const std::vector<int>& gp,
               const std::vector<int>& gi);

  /// Numeric factorisation of `K` (same pattern as analysed). Returns -1, or the global index of
  /// a dof at which a pivot was not positive (the matrix is singular or indefinite there).
  long factorize(const cholmod_sparse_struct& K);

  /// Solution of K x = b after a successful factorize. Not for concurrent calls on one object.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

  /// Non-zeros of the two sparse factors plus the dense separator factor, and their flops.
  double factor_nnz() const;
  double factor_flops() const;
  /// Number of separator dofs.
  int separator_dofs() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gridshell::fem
