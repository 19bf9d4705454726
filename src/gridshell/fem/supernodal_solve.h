#pragma once
/// \file supernodal_solve.h
/// The two triangular solves with a CHOLMOD supernodal Cholesky factor L (x ← L⁻¹ x and
/// x ← L⁻ᵀ x, in the factor's own permuted order), for a solver that repeats them many times on
/// one factor: the Lanczos iteration of the linearised buckling (fem/frame_solver.h), ~60
/// operator steps of one forward and one back substitution each.
///
/// Why not `cholmod_solve2`: a grid-shell frame's factor has mostly tiny supernodes (Aquadom
/// triangulation, 93 762 dofs: 11 281 of its 12 732 supernodes have ≤ 6 columns), where the
/// BLAS calls CHOLMOD makes per supernode (dtrsv, dgemv) cost more than their arithmetic; plain
/// loops over the columns do the same flops in about 0.8× the time. And the elimination tree of
/// a nested-dissection ordering splits into independent subtrees: the forward substitution runs
/// two groups of subtrees on two threads (their updates of the shared top of the tree kept
/// apart and added afterwards), then the top; the back substitution does the top first, then the
/// two groups. The split depends only on the factor's structure, never on the thread count, so
/// the results are the same bits with one thread or two. The results equal CHOLMOD's to rounding
/// (the sums run in another order). The two groups run in an isolated TBB region: inside a
/// parallel sweep or objective search the waiting thread takes no other design's work, and when
/// every worker is busy the calling thread simply runs both groups.
///
/// Not thread-safe: an object holds the work vectors of its solves (one solve at a time).

#include <cholmod.h>

#include <vector>

namespace gridshell::fem {

class SupernodalTriangular {
 public:
  /// `L` must be a supernodal LLᵀ factor (real, double); it is read, not copied, and must
  /// outlive this object unchanged. Throws std::invalid_argument otherwise.
  explicit SupernodalTriangular(const cholmod_factor& L);
  /// x ← L⁻¹ x (x has L.n entries, in the permuted order of the factor).
  void forward(double* x) const;
  /// x ← L⁻ᵀ x.
  void backward(double* x) const;
  /// Share of the factor's entries in each of the two groups of subtrees (0 and 0 when the
  /// tree did not split: everything then runs on the calling thread), for tests and logs.
  double group_share(int group) const;

 private:
  struct Range {
    int first = 0, last = 0;  ///< supernodes first..last (a subtree in postorder)
  };
  void forward_group(int group, double* x) const;
  void backward_group(int group, double* x) const;
  const cholmod_factor& L_;
  int n_ = 0, nsuper_ = 0, max_below_ = 0;
  double entries_ = 0;
  bool split_ = false;
  std::vector<char> top_column_;  ///< per column: its supernode is in the shared top
  std::vector<int> top_;          ///< the top's supernodes, ascending
  std::vector<Range> groups_[2];  ///< each group's subtrees, ascending
  double group_entries_[2] = {0, 0};
  mutable std::vector<double> accumulated_[2];  ///< a group's updates of top rows
  mutable std::vector<double> work_[2];         ///< per group: one supernode's rows below
};

}  // namespace gridshell::fem
