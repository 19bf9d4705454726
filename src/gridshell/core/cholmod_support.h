#pragma once
/// \file cholmod_support.h
/// What the library's CHOLMOD use (core/sparse_cholesky.h, the one caller) shares, so that
/// results are the same bits run to run and for any number of concurrent solves (a parallel
/// `sweep` factorises in several threads), and the small dense kernels the executables link.
///
/// - METIS (called by CHOLMOD's symbolic analysis: explicitly, with nmethods > 1, or as the
///   default's fallback when AMD fills badly) keeps its random-number state in a process-wide
///   global (GKlib). Concurrent analyses interleave it and get different orderings — the same
///   solution to rounding, different bits. Every symbolic analysis holds
///   `lock_symbolic_analysis()`; the numeric factorisation and the solves need no lock.
/// - CHOLMOD's supernodal factorisation opens OpenMP regions with a compiled-in num_threads(4)
///   for its scatter loops; on 2 cores and inside parallel sweeps they cost more than they give
///   (50 K-triangle shell: factorisation CPU 2.6 s → 1.4–1.9 s). `SerialOpenMpScope` keeps them
///   at one thread on the calling thread; they partition by column, so results do not change.
///   The OpenMP runtime is CHOLMOD's dependency, found at run time; without one nothing is done.
///   libgomp still ends each one-thread region with a system call (several per supernode: 88 000
///   for one factorisation of the Aquadom frame); executables that link the CMake target
///   `gridshell_openmp` (src/interpose/openmp.cpp: the gridshell executable, the tests and the
///   benchmarks) run such regions directly instead.
/// - The supernodal factorisation calls LAPACK's `dpotrf_` once per supernode on its diagonal
///   block; most blocks are small (50 K-triangle shell: 10 000 calls, n ≈ 40 on average), where
///   the LAPACKs Debian offers spend ~40 µs per call in per-call overhead (ATLAS recursing into
///   BLAS: 0.5 GFlop/s, 0.4 s of a 1.5 s factorisation; libflame and reference LAPACK are no
///   better). The project therefore has its own `dpotrf_` (src/interpose/dpotrf.cpp, CMake
///   target `gridshell_small_dense`, linked into the gridshell executable, the tests and the
///   benchmarks; the library alone does not replace a routine of the process that links it):
///   blocks up to `kSmallPotrfMax` are
///   factorised in place by `small_potrf` (a plain column Cholesky, same result to rounding and
///   the same `info` for a matrix that is not positive definite), larger ones are passed on to
///   the system LAPACK (`dlsym(RTLD_NEXT)`), which is fast there. Not Eigen's in-place LLT:
///   it reports a failure but not the failing column, which CHOLMOD needs (it is how a singular
///   stiffness names its free dof).

#include <cholmod.h>

#include <mutex>

namespace gridshell {

/// A CHOLMOD view, without copy, of a symmetric n × n matrix stored as its upper triangle in
/// compressed columns: `p` the n + 1 column starts, `i` the row indices (sorted in each column),
/// `x` the values, or nullptr for a pattern only.
cholmod_sparse upper_csc_view(int n, int* p, int* i, double* x = nullptr);

/// Lock held for the duration of a CHOLMOD symbolic analysis (see above).
[[nodiscard]] std::unique_lock<std::mutex> lock_symbolic_analysis();

/// Largest block `dpotrf_` factorises itself rather than passing it on to the system LAPACK.
inline constexpr int kSmallPotrfMax = 96;

/// LAPACK `dpotrf` semantics on a column-major n × n block with leading dimension lda: the
/// Cholesky factor of the `uplo` ('L' or 'U') triangle in place. Returns LAPACK's info: 0, or the
/// 1-based order of the first leading minor that is not positive definite.
int small_potrf(char uplo, int n, double* a, int lda);

/// Widest block (columns) that the executables' `dtrsv_` and `dgemv_` handle themselves
/// (src/interpose/small_blas.cpp). CHOLMOD's supernodal solve makes one of each per supernode and
/// direction; most supernodes of a frame are ≤ 6 columns wide (Aquadom: 11 281 of 12 732), where
/// the BLAS's per-call cost (BLIS: ~0.2 µs) outweighs the work: 3.3 M such calls in the Aquadom
/// LBA's 62 Lanczos steps. Wider blocks, strides ≠ 1 and the cases CHOLMOD does not use are
/// passed on to the system BLAS.
inline constexpr int kSmallBlas2Max = 32;

// The kernels below: Eigen (through Map views of the BLAS arguments) where it is at least as
// fast per call on CHOLMOD's typical shapes (L⁻¹ x, A x, A Bᵀ: 0.4–0.8× the loops' time), plain
// loops where Eigen's small-size paths cost more (L⁻ᵀ x, Aᵀ x, B L⁻ᵀ and A Aᵀ: Eigen 1.2–2.4×
// on ≤ 6 columns, where most calls are). Per-call timings: docs/performance.md.

/// BLAS `dtrsv` for a lower-triangular, non-unit n × n block (column-major, leading dimension
/// lda) and a contiguous x: x = L⁻¹ x (`trans` 'N') or L⁻ᵀ x ('T' or 'C'), in place.
void small_trsv_lower(char trans, int n, const double* a, int lda, double* x);

/// BLAS `dgemv` with β = 1 and contiguous x and y: y += α A x (`trans` 'N'; A is m × n) or
/// y += α Aᵀ x ('T' or 'C').
void small_gemv_accumulate(char trans, int m, int n, double alpha, const double* a, int lda,
                           const double* x, double* y);

/// Largest level-3 call, in multiply-adds, that the executables' `dgemm_`, `dsyrk_` and
/// `dtrsm_` do themselves (src/interpose/small_blas.cpp). CHOLMOD's supernodal factorisation
/// makes a dsyrk and a dgemm per pair of a supernode and a descendant updating it, and a dtrsm
/// per supernode: 52 000 calls for the Aquadom frame, 95 % of them under this size, where BLIS's
/// per-call cost (packing buffers, ~µs) is most of the time. Larger calls, and the cases CHOLMOD
/// does not make, are passed on to the system BLAS.
inline constexpr long kSmallBlas3Max = 8192;

/// BLAS `dsyrk` ('L', 'N', β = 0): the lower triangle of the n × n C = α A Aᵀ, A n × k.
void small_syrk_lower(int n, int k, double alpha, const double* a, int lda, double* c, int ldc);

/// BLAS `dgemm` ('N', 'T', β = 0): the m × n C = α A Bᵀ, A m × k, B n × k.
void small_gemm_nt(int m, int n, int k, double alpha, const double* a, int lda, const double* b,
                   int ldb, double* c, int ldc);

/// BLAS `dtrsm` ('R', 'L', 'T', 'N', α = 1): B = B L⁻ᵀ, B m × n, L n × n lower triangular.
void small_trsm_right_lower_t(int m, int n, const double* a, int lda, double* b, int ldb);

/// For its lifetime, OpenMP regions opened by the calling thread run on one thread.
class SerialOpenMpScope {
 public:
  SerialOpenMpScope();
  ~SerialOpenMpScope();
  SerialOpenMpScope(const SerialOpenMpScope&) = delete;
  SerialOpenMpScope& operator=(const SerialOpenMpScope&) = delete;

 private:
  using Get = int (*)();
  using Set = void (*)(int);
  Get get_ = nullptr;
  Set set_ = nullptr;
  int previous_ = 1;
};

}  // namespace gridshell
