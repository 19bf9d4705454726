// The triangular solves with a CHOLMOD supernodal factor (fem/supernodal_solve.h) against
// CHOLMOD's own solves and against the system they solve.

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include "gridshell/core/cholmod_support.h"
#include "gridshell/fem/supernodal_solve.h"

using namespace gridshell;
using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

namespace {

// The 5-point Laplacian of an m × m grid plus a small shift: SPD, with supernodes of many sizes
// under a nested-dissection ordering.
SpMat grid_laplacian(int m) {
  std::vector<Eigen::Triplet<double>> t;
  const auto id = [m](int i, int j) { return i * m + j; };
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      t.emplace_back(id(i, j), id(i, j), 4.01);
      if (i + 1 < m) {
        t.emplace_back(id(i, j), id(i + 1, j), -1.0);
        t.emplace_back(id(i + 1, j), id(i, j), -1.0);
      }
      if (j + 1 < m) {
        t.emplace_back(id(i, j), id(i, j + 1), -1.0);
        t.emplace_back(id(i, j + 1), id(i, j), -1.0);
      }
    }
  SpMat A(m * m, m * m);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

class Llt : public Eigen::CholmodSupernodalLLT<SpMat, Eigen::Lower> {
 public:
  explicit Llt(int ordering) {
    cholmod().nmethods = 1;
    cholmod().method[0].ordering = ordering;
    cholmod().postorder = 1;
  }
  cholmod_factor* factor() const { return m_cholmodFactor; }
  cholmod_common* common() { return &cholmod(); }
};

// x ← L⁻¹ x (sys CHOLMOD_L) or L⁻ᵀ x (CHOLMOD_Lt) by CHOLMOD.
Eigen::VectorXd cholmod_triangular(Llt& llt, int sys, const Eigen::VectorXd& x) {
  Eigen::VectorXd b = x;
  cholmod_dense d{};
  d.nrow = d.nzmax = d.d = static_cast<size_t>(b.size());
  d.ncol = 1;
  d.x = b.data();
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* out = cholmod_solve(sys, llt.factor(), &d, llt.common());
  Eigen::VectorXd r = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(out->x), b.size());
  cholmod_free_dense(&out, llt.common());
  return r;
}

Eigen::VectorXd pseudo_random(int n) {
  Eigen::VectorXd v(n);
  for (int k = 0; k < n; ++k) v(k) = std::sin(0.7 * k + 0.3) + 0.25 * std::cos(3.1 * k);
  return v;
}

}  // namespace

TEST(SupernodalSolve, MatchesCholmodAndSolvesTheSystem) {
  const SpMat A = grid_laplacian(90);
  Llt llt(CHOLMOD_METIS);
  analyze_pattern(llt, A);
  llt.factorize(A);
  ASSERT_EQ(llt.info(), Eigen::Success);
  const fem::SupernodalTriangular tri(*llt.factor());

  const Eigen::VectorXd b = pseudo_random(static_cast<int>(A.rows()));
  Eigen::VectorXd y = b;
  tri.forward(y.data());
  const Eigen::VectorXd y_ref = cholmod_triangular(llt, CHOLMOD_L, b);
  EXPECT_LT((y - y_ref).norm(), 1e-13 * y_ref.norm());
  Eigen::VectorXd z = b;
  tri.backward(z.data());
  const Eigen::VectorXd z_ref = cholmod_triangular(llt, CHOLMOD_Lt, b);
  EXPECT_LT((z - z_ref).norm(), 1e-13 * z_ref.norm());

  // A = Pᵀ L Lᵀ P: x = Pᵀ L⁻ᵀ L⁻¹ P b solves A x = b.
  const int* perm = static_cast<const int*>(llt.factor()->Perm);
  Eigen::VectorXd w(b.size()), x(b.size());
  for (Eigen::Index k = 0; k < b.size(); ++k) w(k) = b(perm[k]);
  tri.forward(w.data());
  tri.backward(w.data());
  for (Eigen::Index k = 0; k < b.size(); ++k) x(perm[k]) = w(k);
  EXPECT_LT((A * x - b).norm(), 1e-12 * b.norm());
}

TEST(SupernodalSolve, RepeatedSolvesAndASingleSupernode) {
  const SpMat A = grid_laplacian(40);
  Llt llt(CHOLMOD_METIS);
  analyze_pattern(llt, A);
  llt.factorize(A);
  const fem::SupernodalTriangular tri(*llt.factor());
  const Eigen::VectorXd b = pseudo_random(static_cast<int>(A.rows()));
  Eigen::VectorXd first = b, again = b;
  tri.forward(first.data());
  tri.backward(first.data());
  tri.forward(again.data());
  tri.backward(again.data());
  EXPECT_EQ(first, again);  // the work vector carries nothing from one solve to the next

  // A dense matrix is one supernode (no rows below its columns).
  Eigen::MatrixXd D = Eigen::MatrixXd::Identity(5, 5) * 6.0;
  D(0, 4) = D(4, 0) = 1.0;
  D(1, 2) = D(2, 1) = -2.0;
  const SpMat S = D.sparseView();
  Llt small(CHOLMOD_AMD);
  analyze_pattern(small, S);
  small.factorize(S);
  const fem::SupernodalTriangular one_node(*small.factor());
  const Eigen::VectorXd c = pseudo_random(5);
  Eigen::VectorXd u = c, v = c;
  one_node.forward(u.data());
  EXPECT_LT((u - cholmod_triangular(small, CHOLMOD_L, c)).norm(), 1e-14 * u.norm());
  one_node.backward(v.data());
  EXPECT_LT((v - cholmod_triangular(small, CHOLMOD_Lt, c)).norm(), 1e-14 * v.norm());
}

TEST(SupernodalSolve, RefusesASimplicialFactor) {
  struct Simplicial : Eigen::CholmodSimplicialLLT<SpMat, Eigen::Lower> {
    cholmod_factor* factor() const { return m_cholmodFactor; }
  };
  const SpMat A = grid_laplacian(10);
  Simplicial simplicial;
  compute_factorization(simplicial, A);
  ASSERT_EQ(simplicial.info(), Eigen::Success);
  EXPECT_THROW(fem::SupernodalTriangular{*simplicial.factor()}, std::invalid_argument);
}
