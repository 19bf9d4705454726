#pragma once
/// \file supernodal_solve.h
/// The two triangular solves with a CHOLMOD supernodal Cholesky factor L (x ← L⁻¹ x and
/// x ← L⁻ᵀ x, in the factor's own permuted order), for a solver that repeats them many times on
/// one factor: the Lanczos iteration of the linearised buckling (fem/frame_solver.h), ~60
/// operator steps of one forward and one back substitution each.
///
/// Why not `cholmod_solve2`: a grid-shell frame's factor has mostly tiny supernodes (Aquadom
/// triangulation, 93 762 dofs: 11 281 of its 12 732 supernodes have ≤ 6 columns), where the
/// two BLAS calls CHOLMOD makes per supernode (dtrsv, dgemv) cost more than their arithmetic.
/// Plain loops over the columns do the same flops in about half the time (frame_bench
/// `BM_AquadomSubstitutions`). The results equal CHOLMOD's to rounding (the sums run in another
/// order); they do not depend on the thread count (one thread: the substitutions read the whole
/// factor, memory-bound, and a second thread gained nothing on the shared 2-core machine).
///
/// Not thread-safe: an object holds the work vector of its solves (one solve at a time).

#include <cholmod.h>

#include <vector>

namespace gridshell::fem {

class SupernodalTriangular {
 public:
  /// `L` must be a supernodal LLᵀ factor (real, double, int indices); it is read, not copied,
  /// and must outlive this object unchanged. Throws std::invalid_argument otherwise.
  explicit SupernodalTriangular(const cholmod_factor& L);
  /// x ← L⁻¹ x (x has L.n entries, in the permuted order of the factor).
  void forward(double* x) const;
  /// x ← L⁻ᵀ x.
  void backward(double* x) const;

 private:
  const cholmod_factor& L_;
  int nsuper_ = 0;
  mutable std::vector<double> work_;  ///< one supernode's rows below its columns
};

}  // namespace gridshell::fem
