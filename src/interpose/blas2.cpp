// dtrsv_ and dgemv_ for the narrow blocks of CHOLMOD's supernodal solves (core/cholmod_support.h,
// kSmallBlas2Max). Linked into an executable (CMake target gridshell_small_dense, exported to
// the dynamic symbol table), these take precedence over the system BLAS's; every case they do
// not handle themselves is passed on to it. Opt-in like dpotrf_: the library itself never
// replaces a BLAS routine of the process it is linked into.

#include <dlfcn.h>

#include <bit>

#include "gridshell/core/cholmod_support.h"

namespace {
bool is(const char* flag, char c) {
  return *flag == c || *flag == c - 'A' + 'a';
}
}  // namespace

extern "C" void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n,
                       const double* a, const int* lda, double* x, const int* incx) {
  const bool ours = is(uplo, 'L') && is(diag, 'N') &&
                    (is(trans, 'N') || is(trans, 'T') || is(trans, 'C')) && *incx == 1 &&
                    *n >= 0 && *n <= gridshell::kSmallBlas2Max && *lda >= (*n > 1 ? *n : 1);
  if (ours) {
    gridshell::small_trsv_lower(*trans, *n, a, *lda, x);
    return;
  }
  using Fn = void (*)(const char*, const char*, const char*, const int*, const double*,
                      const int*, double*, const int*);
  static const auto next = std::bit_cast<Fn>(dlsym(RTLD_NEXT, "dtrsv_"));
  if (next != nullptr) next(uplo, trans, diag, n, a, lda, x, incx);
}

extern "C" void dgemv_(const char* trans, const int* m, const int* n, const double* alpha,
                       const double* a, const int* lda, const double* x, const int* incx,
                       const double* beta, double* y, const int* incy) {
  const bool ours = (is(trans, 'N') || is(trans, 'T') || is(trans, 'C')) && *beta == 1.0 &&
                    *incx == 1 && *incy == 1 && *m >= 0 && *n >= 0 &&
                    *n <= gridshell::kSmallBlas2Max && *lda >= (*m > 1 ? *m : 1);
  if (ours) {
    gridshell::small_gemv_accumulate(*trans, *m, *n, *alpha, a, *lda, x, y);
    return;
  }
  using Fn = void (*)(const char*, const int*, const int*, const double*, const double*,
                      const int*, const double*, const int*, const double*, double*, const int*);
  static const auto next = std::bit_cast<Fn>(dlsym(RTLD_NEXT, "dgemv_"));
  if (next != nullptr) next(trans, m, n, alpha, a, lda, x, incx, beta, y, incy);
}
