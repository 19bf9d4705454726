#include "gridshell/core/cholmod_support.h"

#include <dlfcn.h>

#include <algorithm>
#include <bit>
#include <cmath>

namespace gridshell {

cholmod_sparse upper_csc_view(int n, int* p, int* i, double* x) {
  cholmod_sparse A{};
  A.nrow = A.ncol = static_cast<size_t>(n);
  A.nzmax = static_cast<size_t>(p[n]);
  A.p = p;
  A.i = i;
  A.x = x;
  A.stype = 1;
  A.itype = CHOLMOD_INT;
  A.xtype = x != nullptr ? CHOLMOD_REAL : CHOLMOD_PATTERN;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  return A;
}

std::unique_lock<std::mutex> lock_symbolic_analysis() {
  // One lock for the whole process: METIS's state is one global, whoever calls it.
  static std::mutex metis;
  return std::unique_lock<std::mutex>(metis);
}

// libgomp's max-active-levels is per thread: setting it to 0 makes every parallel region this
// thread opens run on the thread alone.
SerialOpenMpScope::SerialOpenMpScope()
    : get_(std::bit_cast<Get>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"))),
      set_(std::bit_cast<Set>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"))) {
  if (get_ && set_) {
    previous_ = get_();
    set_(0);
  }
}

SerialOpenMpScope::~SerialOpenMpScope() {
  if (get_ && set_) set_(previous_);
}

// ---------------------------------------------------------------------------------------------
// small_potrf: what src/interpose/dpotrf.cpp's dpotrf_ uses for small blocks (see the header).

namespace {

// Right-looking column Cholesky, A = L·Lᵀ in the lower triangle (column-major, leading dim lda).
// Returns 0, or the 1-based order of the first leading minor that is not positive definite.
int potrf_lower(int n, double* a, long lda) {
  for (int j = 0; j < n; ++j) {
    double* cj = a + j * lda;
    const double d = cj[j];
    if (!(d > 0.0)) return j + 1;  // also catches NaN
    const double l = std::sqrt(d);
    cj[j] = l;
    const double inv = 1.0 / l;
    for (int i = j + 1; i < n; ++i) cj[i] *= inv;
    for (int k = j + 1; k < n; ++k) {  // update the trailing columns with column j
      double* ck = a + k * lda;
      const double f = cj[k];
      for (int i = k; i < n; ++i) ck[i] -= f * cj[i];
    }
  }
  return 0;
}

// A = Uᵀ·U in the upper triangle: column j of U from dot products of columns above the diagonal.
int potrf_upper(int n, double* a, long lda) {
  for (int j = 0; j < n; ++j) {
    double* cj = a + j * lda;
    for (int i = 0; i < j; ++i) {
      const double* ci = a + i * lda;
      double s = cj[i];
      for (int k = 0; k < i; ++k) s -= ci[k] * cj[k];
      cj[i] = s / ci[i];
    }
    double d = cj[j];
    for (int k = 0; k < j; ++k) d -= cj[k] * cj[k];
    if (!(d > 0.0)) {
      cj[j] = d;
      return j + 1;
    }
    cj[j] = std::sqrt(d);
  }
  return 0;
}

}  // namespace

int small_potrf(char uplo, int n, double* a, int lda) {
  if (n <= 0) return 0;
  return (uplo == 'U' || uplo == 'u') ? potrf_upper(n, a, lda) : potrf_lower(n, a, lda);
}

}  // namespace gridshell

