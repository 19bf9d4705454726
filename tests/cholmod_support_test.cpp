// The library's own dpotrf_ for small blocks (core/cholmod_support.h): it must agree with an
// independent Cholesky (Eigen's LLT) and with the system LAPACK it stands in front of, report
// a matrix that is not positive definite exactly as LAPACK does (CHOLMOD's mechanism detection
// relies on it), and be the dpotrf_ the process actually calls. Likewise the small BLAS calls of
// CHOLMOD's supernodal factorisation (dsyrk_, dgemm_, dtrsm_) and solves (dtrsv_, dgemv_):
// Eigen's answers, the system BLAS's to rounding, and the routines the process resolves to.
#include <gtest/gtest.h>

#include <dlfcn.h>

#include <Eigen/Dense>
#include <bit>
#include <random>
#include <tuple>

#include "gridshell/core/cholmod_support.h"

namespace gridshell {
namespace {

using Potrf = void (*)(const char*, const int*, double*, const int*, int*);

// Entries uniform in [−1, 1], column by column.
Eigen::MatrixXd random_matrix(int rows, int cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd M(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) M(i, j) = u(rng);
  return M;
}

// A random SPD matrix with condition number around 1e3, stored with a leading dimension lda > n
// (the padding rows hold a sentinel that must survive).
Eigen::MatrixXd random_spd(int n, int lda, unsigned seed) {
  const Eigen::MatrixXd B = random_matrix(n, n, seed);
  Eigen::MatrixXd A = B * B.transpose() + 1e-2 * n * Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd S = Eigen::MatrixXd::Constant(lda, n, 12345.0);
  S.topRows(n) = A;
  return S;
}

TEST(SmallPotrf, LowerAndUpperAgreeWithEigen) {
  for (int n : {1, 2, 3, 6, 17, 40, 64, kSmallPotrfMax}) {
    const int lda = n + 3;
    const Eigen::MatrixXd S = random_spd(n, lda, 7u + n);
    const Eigen::MatrixXd A = S.topRows(n);
    const Eigen::MatrixXd L = A.llt().matrixL();

    Eigen::MatrixXd lower = S;
    ASSERT_EQ(small_potrf('L', n, lower.data(), lda), 0);
    Eigen::MatrixXd upper = S;
    ASSERT_EQ(small_potrf('U', n, upper.data(), lda), 0);
    const double scale = L.cwiseAbs().maxCoeff();
    for (int j = 0; j < n; ++j)
      for (int i = j; i < n; ++i) {
        EXPECT_NEAR(lower(i, j), L(i, j), 1e-12 * scale) << "n=" << n;
        EXPECT_NEAR(upper(j, i), L(i, j), 1e-12 * scale) << "n=" << n;
      }
    // The other triangle and the padding are untouched.
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < j; ++i) EXPECT_EQ(lower(i, j), S(i, j));
      for (int i = j + 1; i < n; ++i) EXPECT_EQ(upper(i, j), S(i, j));
      for (int i = n; i < lda; ++i) EXPECT_EQ(lower(i, j), 12345.0);
    }
  }
}

TEST(SmallPotrf, ReportsTheFirstMinorThatIsNotPositiveDefinite) {
  // Leading 3×3 minor positive definite, the 4×4 one not (pivot 4 becomes −1).
  const int n = 6;
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n);
  A(3, 3) = 0.0;
  A(3, 1) = A(1, 3) = 1.0;
  for (char uplo : {'L', 'U'}) {
    Eigen::MatrixXd W = A;
    EXPECT_EQ(small_potrf(uplo, n, W.data(), n), 4) << uplo;
  }
  Eigen::MatrixXd nan = Eigen::MatrixXd::Identity(n, n);
  nan(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(small_potrf('L', n, nan.data(), n), 1);
}

TEST(SmallPotrf, IsTheDpotrfTheProcessCallsAndMatchesTheSystemLapack) {
  // The system LAPACK, loaded the way CHOLMOD's dependency would be.
  void* lapack = dlopen("liblapack.so.3", RTLD_NOW | RTLD_GLOBAL);
  if (lapack == nullptr) GTEST_SKIP() << "no liblapack.so.3";
  const auto system = std::bit_cast<Potrf>(dlsym(lapack, "dpotrf_"));
  const auto ours = std::bit_cast<Potrf>(dlsym(RTLD_DEFAULT, "dpotrf_"));
  ASSERT_NE(system, nullptr);
  ASSERT_NE(ours, nullptr);
  EXPECT_NE(ours, system) << "the process resolves dpotrf_ to LAPACK's, not the library's";
  for (int n : {5, 48, kSmallPotrfMax, kSmallPotrfMax + 1, 150}) {
    const Eigen::MatrixXd S = random_spd(n, n, 99u + n);
    Eigen::MatrixXd a = S, b = S, c = S;
    int info_a = -7, info_b = -7;
    ours("L", &n, a.data(), &n, &info_a);
    system("L", &n, b.data(), &n, &info_b);
    ASSERT_EQ(info_a, 0);
    ASSERT_EQ(info_b, 0);
    const double scale = b.cwiseAbs().maxCoeff();
    EXPECT_LT((a - b).triangularView<Eigen::Lower>().toDenseMatrix().cwiseAbs().maxCoeff(),
              1e-12 * scale)
        << "n=" << n;
    if (n <= kSmallPotrfMax) {  // small blocks: exactly small_potrf's bits
      ASSERT_EQ(small_potrf('L', n, c.data(), n), 0);
      EXPECT_EQ(a, c) << "n=" << n;
    }
  }
}

using Trsv = void (*)(const char*, const char*, const char*, const int*, const double*, const int*,
                     double*, const int*);
using Gemv = void (*)(const char*, const int*, const int*, const double*, const double*,
                      const int*, const double*, const int*, const double*, double*, const int*);

TEST(SmallBlas2, TriangularSolvesAgreeWithEigen) {
  for (int n : {1, 2, 6, 13, kSmallBlas2Max}) {
    const int lda = n + 5;  // a supernode's block: rows below the triangle
    Eigen::MatrixXd S = random_matrix(lda, n, 3u + n);
    for (int j = 0; j < n; ++j) S(j, j) = 2.0 + std::abs(S(j, j));  // well conditioned
    const Eigen::MatrixXd L = S.topRows(n).triangularView<Eigen::Lower>();
    const Eigen::VectorXd b = random_matrix(n, 1, 17u + n);
    Eigen::VectorXd x = b;
    small_trsv_lower('N', n, S.data(), lda, x.data());
    EXPECT_LT((L * x - b).cwiseAbs().maxCoeff(), 1e-13) << "n=" << n;
    x = b;
    small_trsv_lower('T', n, S.data(), lda, x.data());
    EXPECT_LT((L.transpose() * x - b).cwiseAbs().maxCoeff(), 1e-13) << "n=" << n;
  }
}

TEST(SmallBlas2, MatrixVectorProductsAgreeWithEigen) {
  for (auto [m, n] : {std::pair{0, 3}, {7, 1}, {12, 6}, {300, kSmallBlas2Max}}) {
    const int lda = m + 2;
    const Eigen::MatrixXd S = random_matrix(lda, n, 5u + m + n);
    const Eigen::MatrixXd A = S.topRows(m);
    const Eigen::VectorXd x = random_matrix(n, 1, 9u + n), xt = random_matrix(m, 1, 11u + m);
    const Eigen::VectorXd y0 = random_matrix(m, 1, 13u + m), y0t = random_matrix(n, 1, 15u + n);
    Eigen::VectorXd y = y0, yt = y0t;
    small_gemv_accumulate('N', m, n, -1.0, S.data(), lda, x.data(), y.data());
    small_gemv_accumulate('T', m, n, 0.5, S.data(), lda, xt.data(), yt.data());
    if (m > 0) {
      EXPECT_LT((y - (y0 - A * x)).cwiseAbs().maxCoeff(), 1e-13) << m << "x" << n;
    }
    EXPECT_LT((yt - (y0t + 0.5 * A.transpose() * xt)).cwiseAbs().maxCoeff(), 1e-13)
        << m << "x" << n;
  }
}

TEST(SmallBlas2, AreTheRoutinesTheProcessCallsAndMatchTheSystemBlas) {
  void* blas = dlopen("libblas.so.3", RTLD_NOW | RTLD_GLOBAL);
  if (blas == nullptr) GTEST_SKIP() << "no libblas.so.3";
  const auto system_trsv = std::bit_cast<Trsv>(dlsym(blas, "dtrsv_"));
  const auto system_gemv = std::bit_cast<Gemv>(dlsym(blas, "dgemv_"));
  const auto trsv = std::bit_cast<Trsv>(dlsym(RTLD_DEFAULT, "dtrsv_"));
  const auto gemv = std::bit_cast<Gemv>(dlsym(RTLD_DEFAULT, "dgemv_"));
  ASSERT_TRUE(system_trsv && system_gemv && trsv && gemv);
  EXPECT_NE(trsv, system_trsv) << "the process resolves dtrsv_ to the BLAS's";
  EXPECT_NE(gemv, system_gemv) << "the process resolves dgemv_ to the BLAS's";
  const int one = 1, two = 2;
  // Narrow blocks (ours) and wide ones and strided vectors (passed on): both give the BLAS's
  // answer to rounding.
  for (int n : {6, kSmallBlas2Max, kSmallBlas2Max + 8}) {
    const int m = 3 * n, lda = m;
    Eigen::MatrixXd S = random_matrix(lda, n, 21u + n);
    for (int j = 0; j < n; ++j) S(j, j) = 2.0 + std::abs(S(j, j));
    const Eigen::VectorXd b = random_matrix(2 * m, 1, 23u + n);
    for (const char* t : {"N", "T"}) {
      Eigen::VectorXd x = b.head(n), y = b.head(n);
      trsv("L", t, "N", &n, S.data(), &lda, x.data(), &one);
      system_trsv("L", t, "N", &n, S.data(), &lda, y.data(), &one);
      EXPECT_LT((x - y).cwiseAbs().maxCoeff(), 1e-12) << t << n;
      Eigen::VectorXd xs = b, ys = b;  // every other entry
      trsv("L", t, "N", &n, S.data(), &lda, xs.data(), &two);
      system_trsv("L", t, "N", &n, S.data(), &lda, ys.data(), &two);
      EXPECT_LT((xs - ys).cwiseAbs().maxCoeff(), 1e-12) << t << n << " strided";
      const double alpha = -1.0, beta = 1.0;
      Eigen::VectorXd u = b.head(t[0] == 'N' ? m : n), v = u;
      const Eigen::VectorXd in = b.tail(t[0] == 'N' ? n : m);
      gemv(t, &m, &n, &alpha, S.data(), &lda, in.data(), &one, &beta, u.data(), &one);
      system_gemv(t, &m, &n, &alpha, S.data(), &lda, in.data(), &one, &beta, v.data(), &one);
      EXPECT_LT((u - v).cwiseAbs().maxCoeff(), 1e-12) << t << n;
    }
  }
}

TEST(SmallBlas3, FactorisationKernelsAgreeWithEigen) {
  // The shapes of a supernode's update (k descendant columns, n rows of the triangle, m below).
  for (auto [m, n, k] : {std::tuple{0, 1, 1}, {5, 6, 6}, {12, 6, 3}, {40, 12, 9}}) {
    const Eigen::MatrixXd A = random_matrix(n + m, k, 31u + m + n + k);
    const int lda = n + m, ldc = n + m + 1;
    const Eigen::MatrixXd top = A.topRows(n), below = A.bottomRows(m);
    Eigen::MatrixXd C = Eigen::MatrixXd::Constant(ldc, n, 7.0);  // beta = 0: not read
    small_syrk_lower(n, k, 1.0, A.data(), lda, C.data(), ldc);
    const Eigen::MatrixXd syrk = top * top.transpose();
    EXPECT_LT((C.topRows(n) - syrk).triangularView<Eigen::Lower>().toDenseMatrix()
                  .cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_EQ(C(0, n - 1), n > 1 ? 7.0 : C(0, 0)) << "the strict upper triangle is left alone";
    Eigen::MatrixXd G = Eigen::MatrixXd::Constant(ldc, n, 7.0);
    small_gemm_nt(m, n, k, -2.0, A.data() + n, lda, A.data(), lda, G.data(), ldc);
    if (m > 0) {
      EXPECT_LT((G.topRows(m) - (-2.0 * below * top.transpose())).cwiseAbs().maxCoeff(), 1e-13);
    }
    // B L⁻ᵀ for L the Cholesky factor of an SPD block.
    Eigen::MatrixXd S = random_matrix(n, n, 41u + n);
    S = S * S.transpose() + n * Eigen::MatrixXd::Identity(n, n);
    const Eigen::MatrixXd L = S.llt().matrixL();
    const Eigen::MatrixXd B = random_matrix(m, n, 43u + m);
    Eigen::MatrixXd X = B;
    small_trsm_right_lower_t(m, n, L.data(), n, X.data(), std::max(m, 1));
    if (m > 0) {
      EXPECT_LT((X * L.transpose() - B).cwiseAbs().maxCoeff(), 1e-12);
    }
  }
}

TEST(SmallBlas3, AreTheRoutinesTheProcessCallsAndMatchTheSystemBlas) {
  void* blas = dlopen("libblas.so.3", RTLD_NOW | RTLD_GLOBAL);
  if (blas == nullptr) GTEST_SKIP() << "no libblas.so.3";
  using Syrk = void (*)(const char*, const char*, const int*, const int*, const double*,
                        const double*, const int*, const double*, double*, const int*);
  using Gemm = void (*)(const char*, const char*, const int*, const int*, const int*,
                        const double*, const double*, const int*, const double*, const int*,
                        const double*, double*, const int*);
  using Trsm = void (*)(const char*, const char*, const char*, const char*, const int*,
                        const int*, const double*, const double*, const int*, double*, const int*);
  const auto sys_syrk = std::bit_cast<Syrk>(dlsym(blas, "dsyrk_"));
  const auto sys_gemm = std::bit_cast<Gemm>(dlsym(blas, "dgemm_"));
  const auto sys_trsm = std::bit_cast<Trsm>(dlsym(blas, "dtrsm_"));
  const auto syrk = std::bit_cast<Syrk>(dlsym(RTLD_DEFAULT, "dsyrk_"));
  const auto gemm = std::bit_cast<Gemm>(dlsym(RTLD_DEFAULT, "dgemm_"));
  const auto trsm = std::bit_cast<Trsm>(dlsym(RTLD_DEFAULT, "dtrsm_"));
  ASSERT_TRUE(sys_syrk && sys_gemm && sys_trsm && syrk && gemm && trsm);
  EXPECT_NE(syrk, sys_syrk);
  EXPECT_NE(gemm, sys_gemm);
  EXPECT_NE(trsm, sys_trsm);
  const double one = 1.0, zero = 0.0;
  // Small calls (ours) and large ones (passed on) give the BLAS's answer to rounding.
  for (int n : {6, 20, 60}) {
    const int m = 2 * n, k = n, ld = m + n;
    const Eigen::MatrixXd A = random_matrix(ld, k, 51u + n);
    Eigen::MatrixXd C1 = Eigen::MatrixXd::Zero(ld, n), C2 = C1;
    syrk("L", "N", &n, &k, &one, A.data(), &ld, &zero, C1.data(), &ld);
    sys_syrk("L", "N", &n, &k, &one, A.data(), &ld, &zero, C2.data(), &ld);
    EXPECT_LT((C1 - C2).triangularView<Eigen::Lower>().toDenseMatrix().cwiseAbs().maxCoeff(),
              1e-12) << n;
    Eigen::MatrixXd G1 = Eigen::MatrixXd::Zero(ld, n), G2 = G1;
    gemm("N", "C", &m, &n, &k, &one, A.data() + n, &ld, A.data(), &ld, &zero, G1.data(), &ld);
    sys_gemm("N", "C", &m, &n, &k, &one, A.data() + n, &ld, A.data(), &ld, &zero, G2.data(), &ld);
    EXPECT_LT((G1 - G2).cwiseAbs().maxCoeff(), 1e-12) << n;
    Eigen::MatrixXd S = random_matrix(n, n, 53u + n);
    S = S * S.transpose() + n * Eigen::MatrixXd::Identity(n, n);
    const Eigen::MatrixXd L = S.llt().matrixL();
    Eigen::MatrixXd X1 = random_matrix(m, n, 57u + n), X2 = X1;
    trsm("R", "L", "C", "N", &m, &n, &one, L.data(), &n, X1.data(), &m);
    sys_trsm("R", "L", "C", "N", &m, &n, &one, L.data(), &n, X2.data(), &m);
    EXPECT_LT((X1 - X2).cwiseAbs().maxCoeff(), 1e-12) << n;
  }
}

}  // namespace
}  // namespace gridshell
