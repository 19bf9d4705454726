#include "gridshell/core/cholmod_support.h"

#include <dlfcn.h>

#include <algorithm>
#include <bit>
#include <cmath>

#include <Eigen/Core>

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

namespace {
using ColMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor>;
using ConstBlock = Eigen::Map<const ColMajor, 0, Eigen::OuterStride<>>;
ConstBlock block(const double* a, int rows, int cols, int ld) {
  return ConstBlock(a, rows, cols, Eigen::OuterStride<>(ld));
}
}  // namespace

void small_trsv_lower(char trans, int n, const double* a, int lda, double* x) {
  if (trans == 'N' || trans == 'n') {
    Eigen::Map<Eigen::VectorXd> v(x, n);
    block(a, n, n, lda).triangularView<Eigen::Lower>().solveInPlace(v);
    return;
  }
  const long ld = lda;  // Eigen's Lᵀ solve is 1.2–2.3× slower on these sizes (docs/performance.md)
  for (int j = n - 1; j >= 0; --j) {  // backward with Lᵀ: row j of Lᵀ is column j of L
    const double* c = a + j * ld;
    double s = x[j];
    for (int i = j + 1; i < n; ++i) s -= c[i] * x[i];
    x[j] = s / c[j];
  }
}

void small_syrk_lower(int n, int k, double alpha, const double* a, int lda, double* c, int ldc) {
  const long la = lda, lc = ldc;
  for (int j = 0; j < n; ++j) std::fill(c + j * lc + j, c + j * lc + n, 0.0);
  for (int l = 0; l < k; ++l) {  // rank-1 updates, column by column of the lower triangle
    const double* al = a + l * la;
    for (int j = 0; j < n; ++j) {
      const double s = alpha * al[j];
      double* cj = c + j * lc;
      for (int i = j; i < n; ++i) cj[i] += s * al[i];
    }
  }
}

void small_gemm_nt(int m, int n, int k, double alpha, const double* a, int lda, const double* b,
                   int ldb, double* c, int ldc) {
  Eigen::Map<ColMajor, 0, Eigen::OuterStride<>>(c, m, n, Eigen::OuterStride<>(ldc)).noalias() =
      alpha * block(a, m, k, lda) * block(b, n, k, ldb).transpose();
}

void small_trsm_right_lower_t(int m, int n, const double* a, int lda, double* b, int ldb) {
  // X Lᵀ = B column by column: X(:, j) = (B(:, j) − Σ_{i<j} L(j, i) X(:, i)) / L(j, j).
  const long la = lda, lb = ldb;
  for (int j = 0; j < n; ++j) {
    double* bj = b + j * lb;
    for (int i = 0; i < j; ++i) {
      const double l = a[j + i * la];
      const double* bi = b + i * lb;
      for (int r = 0; r < m; ++r) bj[r] -= l * bi[r];
    }
    const double d = a[j + j * la];
    for (int r = 0; r < m; ++r) bj[r] /= d;
  }
}

void small_gemv_accumulate(char trans, int m, int n, double alpha, const double* a, int lda,
                           const double* x, double* y) {
  if (trans == 'N' || trans == 'n') {
    Eigen::Map<Eigen::VectorXd>(y, m).noalias() +=
        alpha * block(a, m, n, lda) * Eigen::Map<const Eigen::VectorXd>(x, n);
    return;
  }
  const long ld = lda;  // Eigen's Aᵀ x is up to 2.2× slower on these sizes (docs/performance.md)
  for (int j = 0; j < n; ++j) {
    const double* c = a + j * ld;
    double s = 0;
    for (int i = 0; i < m; ++i) s += c[i] * x[i];
    y[j] += alpha * s;
  }
}

}  // namespace gridshell
