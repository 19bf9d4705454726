// The library's own dpotrf_ for small blocks (core/cholmod_support.h): it must agree with an
// independent Cholesky (Eigen's LLT) and with the system LAPACK it stands in front of, report
// a matrix that is not positive definite exactly as LAPACK does (CHOLMOD's mechanism detection
// relies on it), and be the dpotrf_ the process actually calls.
#include <gtest/gtest.h>

#include <dlfcn.h>

#include <Eigen/Dense>
#include <bit>
#include <random>

#include "gridshell/core/cholmod_support.h"

namespace gridshell {
namespace {

using Potrf = void (*)(const char*, const int*, double*, const int*, int*);

// A random SPD matrix with condition number around 1e3, stored with a leading dimension lda > n
// (the padding rows hold a sentinel that must survive).
Eigen::MatrixXd random_spd(int n, int lda, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd B(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) B(i, j) = u(rng);
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

}  // namespace
}  // namespace gridshell
