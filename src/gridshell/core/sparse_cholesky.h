#pragma once
/// \file sparse_cholesky.h
/// The one sparse Cholesky of the library: every factorisation of a symmetric sparse matrix
/// (frame stiffness and tangents, the arc-length corrector's local relaxation, shell stiffness,
/// the metric's global step, force density, regularization, flat panels; not the quad-aniso
/// baseline's small Laplacian, docs/performance.md) goes through `SparseCholesky`, which owns
/// its CHOLMOD workspace (`cholmod_common`) and factor and configures them from small
/// `SparseCholeskyOptions`:
///
/// - ordering: none (natural), AMD, METIS nested dissection, the better of AMD and METIS
///   (fewer flops; frames), CHOLMOD's default (AMD, METIS as well when AMD fills badly), or a
///   permutation given to `analyze` (the shell's METIS order of the node graph);
/// - mode: supernodal (dense BLAS blocks over the supernodes; relaxed amalgamation by CHOLMOD's
///   `nrelax` / `zrelax`) or simplicial (column by column: no BLAS, no OpenMP regions);
/// - LLᵀ, or LDLᵀ (simplicial only: CHOLMOD has no supernodal LDLᵀ) for indefinite matrices,
///   whose D gives the inertia;
/// - threading: CHOLMOD's OpenMP regions (the supernodal scatter loops) on the calling thread
///   alone (`SerialOpenMpScope`, the default: on 2 cores and inside parallel sweeps they cost more
///   than they give; they partition by column, so the result does not depend on it), or the
///   library's own thread count.
///
/// The symbolic analysis holds `lock_symbolic_analysis()` whenever the ordering may call METIS
/// (core/cholmod_support.h: METIS's random state is one global), so concurrent analyses give
/// the same bits as serial ones. A factorisation that meets a non-positive pivot (LLᵀ) reports
/// the column, in the matrix's own numbering, for mechanism messages. Not for concurrent calls on
/// one object (the solves reuse workspaces); distinct objects are independent.
///
/// Cost: CHOLMOD's. The analysis (ordering) is done once per pattern; `factorize` may be called
/// again with new values on the same pattern.

#include <array>
#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

struct cholmod_sparse_struct;
struct cholmod_factor_struct;

namespace gridshell {

/// Fill-reducing ordering of the symbolic analysis.
enum class CholeskyOrdering {
  natural,            ///< the matrix's own order (the elimination tree is still postordered)
  amd,                ///< approximate minimum degree
  metis,              ///< METIS nested dissection
  best_of_amd_metis,  ///< both, the one with fewer flops kept
  cholmod_default,    ///< AMD, and METIS too when AMD's fill is poor (CHOLMOD's default)
  given,              ///< the permutation passed to `analyze`
};

/// Supernodal: columns with (nearly) the same pattern are factorised as dense blocks by BLAS.
/// Simplicial: column by column (CHOLMOD's up-looking factorisation), no BLAS.
enum class CholeskyMode { supernodal, simplicial };

/// A = L Lᵀ, or A = L D Lᵀ with unit L (indefinite matrices; simplicial only).
enum class CholeskyKind { llt, ldlt };

/// Where CHOLMOD's OpenMP regions run: on the calling thread alone, or on the library's threads.
enum class CholeskyThreads { calling_thread, library };

/// The triangle of the matrix CHOLMOD reads (a matrix stored whole is read from this triangle).
enum class StoredTriangle { upper, lower };

struct SparseCholeskyOptions {
  CholeskyOrdering ordering = CholeskyOrdering::cholmod_default;
  CholeskyMode mode = CholeskyMode::supernodal;
  CholeskyKind kind = CholeskyKind::llt;
  StoredTriangle triangle = StoredTriangle::lower;
  CholeskyThreads threads = CholeskyThreads::calling_thread;
  /// Relaxed supernode amalgamation (CHOLMOD's defaults): a child supernode is merged into its
  /// parent when the merged one has ≤ nrelax[0] columns, or adds no explicit zeros, or its
  /// fraction z of explicit zeros is < zrelax[0] with ≤ nrelax[1] columns, < zrelax[1] with
  /// ≤ nrelax[2] columns, or < zrelax[2]. Wider supernodes: fewer, larger BLAS calls, more flops.
  std::array<int, 3> nrelax{4, 16, 48};
  std::array<double, 3> zrelax{0.8, 0.1, 0.05};
  /// A supernodal LLᵀ stops at the first non-positive pivot instead of finishing the factor of
  /// the leading columns (only the failing column is wanted).
  bool stop_at_failure = false;
  /// After a supernodal factorisation, convert the factor to a simplicial one for the solves
  /// (faster substitutions when the supernodes are small; the metric's global step).
  bool simplicial_solves = false;
  /// Keep the analysed triangle in the factor's order (tril(P A Pᵀ): its pattern and, per entry,
  /// where its value sits in A; 16 bytes per entry) and refill it at every factorisation, instead
  /// of CHOLMOD forming it by a permuted transpose each time — a third of the factorisation of a
  /// frame's tangent, whose supernodes are small. Supernodal LLᵀ only; the same factor, bit for
  /// bit. For matrices factorised many times on one pattern.
  bool factor_order_copy = false;
};

/// Outcome of a numeric factorisation.
struct CholeskyStatus {
  bool ok = false;  ///< LLᵀ: positive definite; LDLᵀ: no zero pivot
  /// When not ok: the column (matrix numbering) at which a pivot was not positive (LLᵀ) or zero
  /// (LDLᵀ); −1 when CHOLMOD failed otherwise (out of memory).
  long failed_column = -1;
};

/// Counts of the signs of D of an LDLᵀ factor (Sylvester: the inertia of A).
struct Inertia {
  int negative = 0, positive = 0;
  int singular = 0;  ///< zero or non-finite pivots
};

/// The systems `solve_in_place` solves, for A = Pᵀ L Lᵀ P (CHOLMOD's names).
enum class CholeskySystem { A, L, Lt, P, Pt };

class SparseCholesky {
 public:
  using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  explicit SparseCholesky(const SparseCholeskyOptions& options = {});
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  /// Symbolic analysis of A's pattern (values not read). `permutation` (n entries, new → old)
  /// is required by the `given` ordering and ignored by the others. False when CHOLMOD failed
  /// (out of memory).
  bool analyze(const SpMat& A, const int* permutation = nullptr);
  /// The same for a CHOLMOD view whose `stype` already names the triangle read (+1 upper).
  bool analyze(const cholmod_sparse_struct& A, const int* permutation = nullptr);
  /// The symbolic analysis of `analysed` (analysed, on A's pattern) copied instead of made again:
  /// the same ordering and supernodes, so the same factor bit for bit, without the ordering's
  /// cost (or METIS's lock). `analysed` is only read: many solvers may copy it at once. False
  /// when CHOLMOD failed (out of memory) or `analysed` is not analysed.
  bool adopt_analysis(const SparseCholesky& analysed, const SpMat& A);
  bool analyzed() const;

  /// Numeric factorisation of A (the analysed pattern; analyses first if not done).
  CholeskyStatus factorize(const SpMat& A);
  CholeskyStatus factorize(const cholmod_sparse_struct& A);
  /// Analysis (under the lock when needed) and factorisation.
  CholeskyStatus compute(const SpMat& A);

  /// x with A x = b after a successful factorisation; NaN entries if CHOLMOD failed.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  /// X with A X = B, all columns in one call.
  template <class Derived>
  Eigen::MatrixXd solve(const Eigen::MatrixBase<Derived>& B) const {
    const Eigen::Ref<const Eigen::MatrixXd> columns(B.derived());
    return solve_columns(columns.data(), columns.rows(), columns.cols(), columns.outerStride());
  }
  /// v = S⁻¹ v for one of the systems (S = A, L, Lᵀ, or the permutations v = P v, Pᵀ v), with
  /// workspaces kept between calls: repeated solves (Lanczos steps) allocate nothing.
  void solve_in_place(CholeskySystem system, Eigen::VectorXd& v) const;

  /// The fill-reducing permutation (factor column k is matrix column permutation()[k]), or
  /// nullptr for the identity.
  const int* permutation() const;
  /// The factor's diagonal in factor order: L_kk (LLᵀ) or D_kk (LDLᵀ).
  Eigen::VectorXd diagonal() const;
  /// Signs of D (LDLᵀ).
  Inertia inertia() const;
  /// Non-zeros of L and flops of the factorisation (CHOLMOD's analysis figures).
  double factor_nonzeros() const;
  double factor_flops() const;
  /// The factor itself, read-only, for callers that read its blocks (the split Cholesky's
  /// separator block); nullptr before the analysis.
  const cholmod_factor_struct* factor() const;

 private:
  Eigen::MatrixXd solve_columns(const double* B, Eigen::Index rows, Eigen::Index cols,
                                Eigen::Index stride) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// `options` with the mode and supernode amalgamation named by the environment variable
/// GRIDSHELL_CHOLESKY, a measurement switch (docs/performance.md) that the supernodal LLᵀ
/// factorisations of the frame, the shell and the metric pass their options through:
/// `simplicial`, `supernodal`, or `supernodal:N0,N1,N2:Z0,Z1,Z2` (nrelax, zrelax). Unset or
/// empty: `options` unchanged. `allow_simplicial` false (a caller that reads supernodal blocks)
/// keeps the mode. A malformed value throws Error.
SparseCholeskyOptions with_environment(SparseCholeskyOptions options,
                                       bool allow_simplicial = true);

/// METIS nested-dissection order (new → old) of a graph given as the upper pattern of its
/// adjacency (with diagonal) in compressed columns, under the analysis lock; false when METIS
/// failed. The shell orders its node graph with it (6× smaller than the dof graph).
bool metis_graph_order(int n, const int* p, const int* i, int* order);

/// A vertex separator of the same kind of graph (METIS): part[v] = 0 or 1 for the two halves, 2
/// for the separator. Returns the separator's size, ≤ 0 when METIS failed.
long bisect_graph(int n, const int* p, const int* i, int* part);

}  // namespace gridshell
