// SparseCholesky (core/sparse_cholesky.h) against dense references: solutions of every mode and
// ordering, the failing column of a singular matrix, the inertia of an indefinite one, factor
// reuse on one pattern, the triangular systems and the graph orderings.

#include "gridshell/core/sparse_cholesky.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cstdlib>
#include <numeric>
#include <vector>

#include "gridshell/core/error.h"

namespace gridshell {
namespace {

using SpMat = SparseCholesky::SpMat;

// The 2D five-point Laplacian on an m × m grid plus `shift` on the diagonal, stored whole.
SpMat grid_laplacian(int m, double shift) {
  const int n = m * m;
  std::vector<Eigen::Triplet<double>> t;
  for (int r = 0; r < m; ++r)
    for (int c = 0; c < m; ++c) {
      const int k = r * m + c;
      t.emplace_back(k, k, 4.0 + shift);
      if (c + 1 < m) {
        t.emplace_back(k, k + 1, -1.0);
        t.emplace_back(k + 1, k, -1.0);
      }
      if (r + 1 < m) {
        t.emplace_back(k, k + m, -1.0);
        t.emplace_back(k + m, k, -1.0);
      }
    }
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

Eigen::VectorXd rhs(int n) {
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b(i) = std::sin(0.37 * i) + 0.1 * i / n;
  return b;
}

TEST(SparseCholesky, EveryModeAndOrderingSolvesLikeADenseCholesky) {
  const SpMat A = grid_laplacian(12, 0.01);
  const Eigen::VectorXd b = rhs(static_cast<int>(A.rows()));
  const Eigen::VectorXd reference = Eigen::MatrixXd(A).llt().solve(b);
  for (const CholeskyMode mode : {CholeskyMode::supernodal, CholeskyMode::simplicial})
    for (const CholeskyOrdering ordering :
         {CholeskyOrdering::natural, CholeskyOrdering::amd, CholeskyOrdering::metis,
          CholeskyOrdering::best_of_amd_metis, CholeskyOrdering::cholmod_default})
      for (const StoredTriangle triangle : {StoredTriangle::upper, StoredTriangle::lower}) {
        SparseCholeskyOptions o;
        o.mode = mode;
        o.ordering = ordering;
        o.triangle = triangle;
        o.nrelax = {8, 32, 64};  // more amalgamation than CHOLMOD's default: the same solution
        SparseCholesky solver(o);
        ASSERT_TRUE(solver.compute(A).ok);
        const Eigen::VectorXd x = solver.solve(b);
        EXPECT_LT((x - reference).norm(), 1e-12 * reference.norm());
        // L Lᵀ's diagonal: Σ_k L_jk² = A_jj in factor order.
        EXPECT_GT(solver.diagonal().minCoeff(), 0.0);
        EXPECT_GT(solver.factor_nonzeros(), A.nonZeros() / 2.0);
      }
}

TEST(SparseCholesky, AGivenPermutationIsTheFactorsOrder) {
  const SpMat A = grid_laplacian(6, 0.5);
  const int n = static_cast<int>(A.rows());
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::reverse(perm.begin(), perm.end());
  SparseCholeskyOptions o;
  o.ordering = CholeskyOrdering::given;
  SparseCholesky solver(o);
  ASSERT_TRUE(solver.analyze(A, perm.data()));
  ASSERT_TRUE(solver.factorize(A).ok);
  // The factor's first pivot is √A of the first column of the order CHOLMOD reports (the given
  // order, postordered along its elimination tree).
  const int* p = solver.permutation();
  ASSERT_NE(p, nullptr);
  Eigen::VectorXd d = solver.diagonal();
  EXPECT_NEAR(d(0), std::sqrt(A.coeff(p[0], p[0])), 1e-14);
  const Eigen::VectorXd b = rhs(n);
  EXPECT_LT((A * solver.solve(b) - b).norm(), 1e-12 * b.norm());
}

// The factor-order copy (refilled at every factorisation instead of CHOLMOD's permuted
// transpose) gives the same factor bit for bit, for either stored triangle, over refactorisations
// with new values on the pattern; a matrix that is not positive definite fails at the same
// column.
TEST(SparseCholesky, TheFactorOrderCopyGivesTheSameFactor) {
  for (const StoredTriangle triangle : {StoredTriangle::upper, StoredTriangle::lower}) {
    SparseCholeskyOptions plain;
    plain.ordering = CholeskyOrdering::best_of_amd_metis;
    plain.triangle = triangle;
    plain.stop_at_failure = true;
    SparseCholeskyOptions copy = plain;
    copy.factor_order_copy = true;
    SparseCholesky a(plain), b(copy);
    for (const double shift : {0.01, 0.5, -0.3, 2.0}) {  // −0.3: below −λ_min ≈ −0.077
      const SpMat A = grid_laplacian(15, shift);
      const CholeskyStatus sa = a.factorize(A), sb = b.factorize(A);
      ASSERT_EQ(sa.ok, sb.ok) << shift;
      EXPECT_EQ(sa.ok, shift > 0);
      if (!sa.ok) {
        EXPECT_GE(sa.failed_column, 0);
        EXPECT_EQ(sa.failed_column, sb.failed_column);
        continue;
      }
      const Eigen::VectorXd da = a.diagonal(), db = b.diagonal();
      const Eigen::VectorXd xa = a.solve(rhs(225)), xb = b.solve(rhs(225));
      for (int i = 0; i < 225; ++i) {
        ASSERT_EQ(da(i), db(i)) << shift << " " << i;
        ASSERT_EQ(xa(i), xb(i)) << shift << " " << i;
      }
      EXPECT_LT((A.selfadjointView<Eigen::Upper>() * xb - rhs(225)).norm(), 1e-10);
    }
  }
}

TEST(SparseCholesky, AnAdoptedAnalysisGivesTheSameFactor) {
  // A solver that copies another's symbolic analysis of the same pattern (the paths of a frame's
  // geometries) factorises bit for bit as one that ordered the pattern itself, whether the
  // source was only analysed or already factorised; a source without an analysis is refused.
  SparseCholeskyOptions o;
  o.ordering = CholeskyOrdering::best_of_amd_metis;
  o.stop_at_failure = true;
  o.factor_order_copy = true;
  const SpMat A = grid_laplacian(15, 0.5);
  SparseCholesky own(o), analysed(o), factorised(o), adopted(o), adopted_late(o), refused(o);
  EXPECT_FALSE(refused.adopt_analysis(analysed, A));
  ASSERT_TRUE(analysed.analyze(A));
  ASSERT_TRUE(factorised.factorize(A).ok);
  ASSERT_TRUE(adopted.adopt_analysis(analysed, A));
  ASSERT_TRUE(adopted_late.adopt_analysis(factorised, A));
  for (const double shift : {0.5, 2.0, 0.01}) {
    const SpMat B = grid_laplacian(15, shift);
    ASSERT_TRUE(own.factorize(B).ok);
    ASSERT_TRUE(adopted.factorize(B).ok);
    ASSERT_TRUE(adopted_late.factorize(B).ok);
    const Eigen::VectorXd x = own.solve(rhs(225));
    const Eigen::VectorXd y = adopted.solve(rhs(225)), z = adopted_late.solve(rhs(225));
    for (int i = 0; i < 225; ++i) {
      ASSERT_EQ(own.permutation()[i], adopted.permutation()[i]) << i;
      ASSERT_EQ(x(i), y(i)) << shift << " " << i;
      ASSERT_EQ(x(i), z(i)) << shift << " " << i;
    }
    EXPECT_LT((B.selfadjointView<Eigen::Upper>() * y - rhs(225)).norm(), 1e-10);
  }
}

TEST(SparseCholesky, ReportsTheColumnWhereASingularMatrixFails) {
  // A chain of springs with node 7 cut loose from its neighbours: zero row and column but for a
  // zero diagonal, so the factorisation stops at column 7 whatever the ordering.
  const int n = 12;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    if (i == 7) continue;
    t.emplace_back(i, i, 2.0);
    for (const int j : {i - 1, i + 1})
      if (j >= 0 && j < n && j != 7) t.emplace_back(i, j, -1.0);
  }
  t.emplace_back(7, 7, 0.0);
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  for (const CholeskyMode mode : {CholeskyMode::supernodal, CholeskyMode::simplicial}) {
    SparseCholeskyOptions o;
    o.mode = mode;
    o.ordering = CholeskyOrdering::amd;
    o.stop_at_failure = true;
    SparseCholesky solver(o);
    const CholeskyStatus s = solver.compute(A);
    EXPECT_FALSE(s.ok);
    EXPECT_EQ(s.failed_column, 7);
  }
}

TEST(SparseCholesky, LdltInertiaMatchesTheEigenvalueSigns) {
  // The grid Laplacian shifted by −λ between its eigenvalues: indefinite, nonsingular.
  const SpMat K = grid_laplacian(8, 0.0);
  SpMat A = K;
  const double shift = 1.3;
  for (int i = 0; i < A.rows(); ++i) A.coeffRef(i, i) -= shift;
  const Eigen::VectorXd ev =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(A)).eigenvalues();
  const int negative = static_cast<int>((ev.array() < 0).count());
  ASSERT_GT(negative, 0);
  SparseCholeskyOptions o;
  o.kind = CholeskyKind::ldlt;
  o.mode = CholeskyMode::simplicial;
  o.ordering = CholeskyOrdering::best_of_amd_metis;
  SparseCholesky ldlt(o);
  ASSERT_TRUE(ldlt.compute(A).ok);
  const Inertia in = ldlt.inertia();
  EXPECT_EQ(in.negative, negative);
  EXPECT_EQ(in.positive, A.rows() - negative);
  EXPECT_EQ(in.singular, 0);
  const Eigen::VectorXd b = rhs(static_cast<int>(A.rows()));
  EXPECT_LT((A * ldlt.solve(b) - b).norm(), 1e-10 * b.norm());

  // The LLᵀ of the same matrix fails (at a column of the matrix); of K it succeeds, reusing the
  // analysis.
  for (const CholeskyMode mode : {CholeskyMode::supernodal, CholeskyMode::simplicial}) {
    SparseCholeskyOptions lo;
    lo.mode = mode;
    SparseCholesky llt(lo);
    ASSERT_TRUE(llt.analyze(A));
    const CholeskyStatus failed = llt.factorize(A);
    EXPECT_FALSE(failed.ok);
    EXPECT_GE(failed.failed_column, 0);
    EXPECT_LT(failed.failed_column, A.rows());
    EXPECT_TRUE(llt.factorize(K).ok);
    const Eigen::VectorXd x = llt.solve(b);
    EXPECT_LT((K * x - b).norm(), 1e-12 * b.norm());
  }
}

TEST(SparseCholesky, TriangularSystemsComposeToTheSolve) {
  const SpMat A = grid_laplacian(9, 0.2);
  const Eigen::VectorXd b = rhs(static_cast<int>(A.rows()));
  for (const bool simplicial_solves : {false, true}) {
    SparseCholeskyOptions o;
    o.ordering = CholeskyOrdering::metis;
    o.simplicial_solves = simplicial_solves;
    SparseCholesky solver(o);
    ASSERT_TRUE(solver.compute(A).ok);
    Eigen::VectorXd v = b;  // x = Pᵀ L⁻ᵀ L⁻¹ P b
    for (const CholeskySystem s :
         {CholeskySystem::P, CholeskySystem::L, CholeskySystem::Lt, CholeskySystem::Pt})
      solver.solve_in_place(s, v);
    EXPECT_LT((v - solver.solve(b)).norm(), 1e-13 * v.norm());
    Eigen::MatrixXd B(b.size(), 3);
    B << b, 2 * b, -b;
    const Eigen::MatrixXd X = solver.solve(B);
    EXPECT_LT((A * X - B).norm(), 1e-12 * B.norm());
  }
}

TEST(SparseCholesky, TheEnvironmentSwitchSetsModeAndAmalgamation) {
  SparseCholeskyOptions o;
  ::setenv("GRIDSHELL_CHOLESKY", "supernodal:8,32,64:0.9,0.2,0.1", 1);
  SparseCholeskyOptions e = with_environment(o);
  EXPECT_EQ(e.mode, CholeskyMode::supernodal);
  EXPECT_EQ(e.nrelax, (std::array<int, 3>{8, 32, 64}));
  EXPECT_EQ(e.zrelax, (std::array<double, 3>{0.9, 0.2, 0.1}));
  ::setenv("GRIDSHELL_CHOLESKY", "simplicial", 1);
  EXPECT_EQ(with_environment(o).mode, CholeskyMode::simplicial);
  EXPECT_EQ(with_environment(o, /*allow_simplicial=*/false).mode, CholeskyMode::supernodal);
  ::setenv("GRIDSHELL_CHOLESKY", "supernodal:8", 1);
  EXPECT_THROW(with_environment(o), Error);
  ::unsetenv("GRIDSHELL_CHOLESKY");
  e = with_environment(o);
  EXPECT_EQ(e.nrelax, o.nrelax);
  EXPECT_EQ(e.mode, o.mode);
}

TEST(SparseCholesky, GraphOrderingsArePermutationsAndSeparators) {
  // The node graph of a 10 × 10 grid (upper pattern with diagonal).
  const SpMat A = grid_laplacian(10, 0.0);
  const SpMat U = A.triangularView<Eigen::Upper>();
  const int n = static_cast<int>(U.rows());
  std::vector<int> p(U.outerIndexPtr(), U.outerIndexPtr() + n + 1);
  std::vector<int> i(U.innerIndexPtr(), U.innerIndexPtr() + U.nonZeros());
  std::vector<int> order(n);
  ASSERT_TRUE(metis_graph_order(n, p.data(), i.data(), order.data()));
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int k = 0; k < n; ++k) EXPECT_EQ(sorted[k], k);
  std::vector<int> part(n);
  const long nsep = bisect_graph(n, p.data(), i.data(), part.data());
  ASSERT_GT(nsep, 0);
  EXPECT_EQ(std::count(part.begin(), part.end(), 2), nsep);
  // A separator: no edge joins the two halves.
  for (int c = 0; c < n; ++c)
    for (int k = p[c]; k < p[c + 1]; ++k) {
      const int r = i[k];
      EXPECT_FALSE((part[r] == 0 && part[c] == 1) || (part[r] == 1 && part[c] == 0));
    }
}

}  // namespace
}  // namespace gridshell
