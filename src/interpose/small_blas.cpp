// The BLAS calls of CHOLMOD's supernodal factorisation (dsyrk_, dgemm_, dtrsm_) and solves
// (dtrsv_, dgemv_) for small blocks (core/cholmod_support.h: kSmallBlas3Max, kSmallBlas2Max).
// Linked into an executable (CMake target gridshell_small_dense, exported to
// the dynamic symbol table), these take precedence over the system BLAS's; every case they do
// not handle themselves is passed on to it. Opt-in like dpotrf_: the library itself never
// replaces a BLAS routine of the process it is linked into.

#include <dlfcn.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstdlib>

#include "gridshell/core/cholmod_support.h"

namespace {
bool is(const char* flag, char c) {
  return *flag == c || *flag == c - 'A' + 'a';
}
bool transposed(const char* flag) {
  return is(flag, 'T') || is(flag, 'C');  // real matrices: the conjugate transpose is Aᵀ
}
// The system BLAS's `name`, for the calls passed on. A process that calls these has a BLAS
// loaded (CHOLMOD's dependency); without one there is no correct answer to give.
template <class Fn>
Fn system_blas(const char* name) {
  const auto fn = std::bit_cast<Fn>(dlsym(RTLD_NEXT, name));
  if (fn == nullptr) {
    std::fprintf(stderr, "gridshell: no system BLAS provides %s\n", name);
    std::abort();
  }
  return fn;
}
}  // namespace

extern "C" void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k,
                       const double* alpha, const double* a, const int* lda, const double* beta,
                       double* c, const int* ldc) {
  const long work = static_cast<long>(*n) * *n * *k / 2;
  const bool ours = is(uplo, 'L') && is(trans, 'N') && *beta == 0.0 && *n >= 0 && *k >= 0 &&
                    work <= gridshell::kSmallBlas3Max && *lda >= std::max(1, *n) &&
                    *ldc >= std::max(1, *n);
  if (ours) {
    gridshell::small_syrk_lower(*n, *k, *alpha, a, *lda, c, *ldc);
    return;
  }
  using Fn = void (*)(const char*, const char*, const int*, const int*, const double*,
                      const double*, const int*, const double*, double*, const int*);
  static const auto next = system_blas<Fn>("dsyrk_");
  next(uplo, trans, n, k, alpha, a, lda, beta, c, ldc);
}

extern "C" void dgemm_(const char* transa, const char* transb, const int* m, const int* n,
                       const int* k, const double* alpha, const double* a, const int* lda,
                       const double* b, const int* ldb, const double* beta, double* c,
                       const int* ldc) {
  const long work = static_cast<long>(*m) * *n * *k;
  const bool ours = is(transa, 'N') && transposed(transb) && *beta == 0.0 && *m >= 0 &&
                    *n >= 0 && *k >= 0 && work <= gridshell::kSmallBlas3Max &&
                    *lda >= std::max(1, *m) && *ldb >= std::max(1, *n) &&
                    *ldc >= std::max(1, *m);
  if (ours) {
    gridshell::small_gemm_nt(*m, *n, *k, *alpha, a, *lda, b, *ldb, c, *ldc);
    return;
  }
  using Fn = void (*)(const char*, const char*, const int*, const int*, const int*, const double*,
                      const double*, const int*, const double*, const int*, const double*,
                      double*, const int*);
  static const auto next = system_blas<Fn>("dgemm_");
  next(transa, transb, m, n, k, alpha, a, lda, b, ldb, beta, c, ldc);
}

extern "C" void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag,
                       const int* m, const int* n, const double* alpha, const double* a,
                       const int* lda, double* b, const int* ldb) {
  const long work = static_cast<long>(*m) * *n * *n / 2;
  const bool ours = is(side, 'R') && is(uplo, 'L') && transposed(transa) && is(diag, 'N') &&
                    *alpha == 1.0 && *m >= 0 && *n >= 0 && work <= gridshell::kSmallBlas3Max &&
                    *lda >= std::max(1, *n) && *ldb >= std::max(1, *m);
  if (ours) {
    gridshell::small_trsm_right_lower_t(*m, *n, a, *lda, b, *ldb);
    return;
  }
  using Fn = void (*)(const char*, const char*, const char*, const char*, const int*, const int*,
                      const double*, const double*, const int*, double*, const int*);
  static const auto next = system_blas<Fn>("dtrsm_");
  next(side, uplo, transa, diag, m, n, alpha, a, lda, b, ldb);
}

extern "C" void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n,
                       const double* a, const int* lda, double* x, const int* incx) {
  const bool ours = is(uplo, 'L') && is(diag, 'N') &&
                    (is(trans, 'N') || transposed(trans)) && *incx == 1 &&
                    *n >= 0 && *n <= gridshell::kSmallBlas2Max && *lda >= std::max(1, *n);
  if (ours) {
    gridshell::small_trsv_lower(*trans, *n, a, *lda, x);
    return;
  }
  using Fn = void (*)(const char*, const char*, const char*, const int*, const double*,
                      const int*, double*, const int*);
  static const auto next = system_blas<Fn>("dtrsv_");
  next(uplo, trans, diag, n, a, lda, x, incx);
}

extern "C" void dgemv_(const char* trans, const int* m, const int* n, const double* alpha,
                       const double* a, const int* lda, const double* x, const int* incx,
                       const double* beta, double* y, const int* incy) {
  const bool ours = (is(trans, 'N') || transposed(trans)) && *beta == 1.0 &&
                    *incx == 1 && *incy == 1 && *m >= 0 && *n >= 0 &&
                    *n <= gridshell::kSmallBlas2Max && *lda >= std::max(1, *m);
  if (ours) {
    gridshell::small_gemv_accumulate(*trans, *m, *n, *alpha, a, *lda, x, y);
    return;
  }
  using Fn = void (*)(const char*, const int*, const int*, const double*, const double*,
                      const int*, const double*, const int*, const double*, double*, const int*);
  static const auto next = system_blas<Fn>("dgemv_");
  next(trans, m, n, alpha, a, lda, x, incx, beta, y, incy);
}
