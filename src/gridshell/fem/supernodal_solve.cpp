#include "gridshell/fem/supernodal_solve.h"

#include <algorithm>
#include <stdexcept>

namespace gridshell::fem {

namespace {

// One supernode of a factor: its columns k1..k1+nc−1, its nr row indices (the nc columns first,
// then the nb = nr − nc rows below) and its nr × nc values, column-major.
struct Supernode {
  int k1, nc, nr;
  const int* rows;
  const double* values;
};

Supernode supernode(const cholmod_factor& L, int s) {
  const int* super = static_cast<const int*>(L.super);
  const int* pi = static_cast<const int*>(L.pi);
  const int* px = static_cast<const int*>(L.px);
  return {super[s], super[s + 1] - super[s], pi[s + 1] - pi[s],
          static_cast<const int*>(L.s) + pi[s], static_cast<const double*>(L.x) + px[s]};
}

// Forward substitution through one supernode: its columns, then its updates of the rows below
// (accumulated in `t`, nb entries, and subtracted once per row).
void forward_supernode(const Supernode& S, double* x, double* t) {
  const int nb = S.nr - S.nc;
  std::fill(t, t + nb, 0.0);
  double* xs = x + S.k1;
  for (int j = 0; j < S.nc; ++j) {
    const double* col = S.values + static_cast<std::size_t>(j) * S.nr;
    const double xj = xs[j] / col[j];
    xs[j] = xj;
    for (int i = j + 1; i < S.nc; ++i) xs[i] -= col[i] * xj;
    const double* below = col + S.nc;
    for (int i = 0; i < nb; ++i) t[i] += below[i] * xj;
  }
  const int* rows = S.rows + S.nc;
  for (int i = 0; i < nb; ++i) x[rows[i]] -= t[i];
}

// Σ a[i] b[i] in four interleaved partial sums: a single sum waits for each addition before the
// next (the compiler may not reorder floating-point sums), four keep the adder busy.
double dot(const double* a, const double* b, int n) {
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  int i = 0;
  for (; i + 4 <= n; i += 4) {
    s0 += a[i] * b[i];
    s1 += a[i + 1] * b[i + 1];
    s2 += a[i + 2] * b[i + 2];
    s3 += a[i + 3] * b[i + 3];
  }
  for (; i < n; ++i) s0 += a[i] * b[i];
  return (s0 + s1) + (s2 + s3);
}

// Back substitution through one supernode (reads the rows below, writes its columns). `g` holds
// nb.
void backward_supernode(const Supernode& S, double* x, double* g) {
  const int nb = S.nr - S.nc;
  const int* rows = S.rows + S.nc;
  for (int i = 0; i < nb; ++i) g[i] = x[rows[i]];
  double* xs = x + S.k1;
  for (int j = S.nc - 1; j >= 0; --j) {
    const double* col = S.values + static_cast<std::size_t>(j) * S.nr;
    double sum = xs[j];
    for (int i = j + 1; i < S.nc; ++i) sum -= col[i] * xs[i];
    xs[j] = (sum - dot(col + S.nc, g, nb)) / col[j];
  }
}

}  // namespace

SupernodalTriangular::SupernodalTriangular(const cholmod_factor& L) : L_(L) {
  if (!L.is_super || !L.is_ll || L.xtype != CHOLMOD_REAL || L.dtype != CHOLMOD_DOUBLE ||
      L.itype != CHOLMOD_INT)
    throw std::invalid_argument("SupernodalTriangular: not a real supernodal LL' factor");
  nsuper_ = static_cast<int>(L.nsuper);
  int max_below = 0;
  for (int s = 0; s < nsuper_; ++s) {
    const Supernode S = supernode(L, s);
    max_below = std::max(max_below, S.nr - S.nc);
  }
  work_.resize(max_below);
}

void SupernodalTriangular::forward(double* x) const {
  for (int s = 0; s < nsuper_; ++s) forward_supernode(supernode(L_, s), x, work_.data());
}

void SupernodalTriangular::backward(double* x) const {
  for (int s = nsuper_ - 1; s >= 0; --s) backward_supernode(supernode(L_, s), x, work_.data());
}

}  // namespace gridshell::fem
