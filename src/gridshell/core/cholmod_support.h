#pragma once
/// \file cholmod_support.h
/// What every CHOLMOD user in the library shares, so that results are the same bits run to run
/// and for any number of concurrent solves (a parallel `sweep` factorises in several threads).
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

#include <mutex>

namespace gridshell {

/// Lock held for the duration of a CHOLMOD symbolic analysis (see above).
[[nodiscard]] std::unique_lock<std::mutex> lock_symbolic_analysis();

/// `solver.analyzePattern(A)` under the analysis lock (Eigen's Cholmod* classes).
template <class Solver, class Matrix>
void analyze_pattern(Solver& solver, const Matrix& A) {
  const auto lock = lock_symbolic_analysis();
  solver.analyzePattern(A);
}

/// `solver.compute(A)` with the symbolic analysis under the lock.
template <class Solver, class Matrix>
void compute_factorization(Solver& solver, const Matrix& A) {
  analyze_pattern(solver, A);
  solver.factorize(A);
}

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
