// dpotrf_ for small blocks (core/cholmod_support.h). CHOLMOD calls LAPACK's dpotrf_ on the
// diagonal block of every supernode; this definition, linked into an executable (CMake target
// gridshell_small_dense, exported to the dynamic symbol table), takes precedence over liblapack's.
// It is opt-in: the library itself never replaces a LAPACK routine of the process it is linked
// into. The gridshell executable, the tests and the benchmarks link it.

#include <dlfcn.h>

#include <algorithm>
#include <bit>

#include "gridshell/core/cholmod_support.h"

extern "C" void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info) {
  const bool valid_uplo = *uplo == 'L' || *uplo == 'l' || *uplo == 'U' || *uplo == 'u';
  if (valid_uplo && *n >= 0 && *n <= gridshell::kSmallPotrfMax && *lda >= std::max(1, *n)) {
    *info = gridshell::small_potrf(*uplo, *n, a, *lda);
    return;
  }
  using PotrfFn = void (*)(const char*, const int*, double*, const int*, int*);
  static const auto next = std::bit_cast<PotrfFn>(dlsym(RTLD_NEXT, "dpotrf_"));
  if (next != nullptr)
    next(uplo, n, a, lda, info);
  else if (valid_uplo && *n >= 0 && *lda >= std::max(1, *n))
    *info = gridshell::small_potrf(*uplo, *n, a, *lda);
  else
    *info = -1;
}
