#include "gridshell/core/sparse_cholesky.h"

#include <cholmod.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "gridshell/core/cholmod_support.h"
#include "gridshell/core/error.h"

namespace gridshell {

namespace {

// The CHOLMOD settings of the options (analysis and factorisation).
void configure(const SparseCholeskyOptions& o, cholmod_common& c) {
  c.print = 0;
  switch (o.ordering) {
    case CholeskyOrdering::natural:
      c.nmethods = 1;
      c.method[0].ordering = CHOLMOD_NATURAL;
      break;
    case CholeskyOrdering::amd:
      c.nmethods = 1;
      c.method[0].ordering = CHOLMOD_AMD;
      break;
    case CholeskyOrdering::metis:
      c.nmethods = 1;
      c.method[0].ordering = CHOLMOD_METIS;
      break;
    case CholeskyOrdering::best_of_amd_metis:
      c.nmethods = 2;
      c.method[0].ordering = CHOLMOD_AMD;
      c.method[1].ordering = CHOLMOD_METIS;
      break;
    case CholeskyOrdering::cholmod_default:
    case CholeskyOrdering::given:  // set per analysis (a permutation is needed)
      break;
  }
  c.postorder = 1;
  if (o.kind == CholeskyKind::ldlt) {
    if (o.mode != CholeskyMode::simplicial)
      throw std::logic_error("SparseCholesky: LDLᵀ is simplicial only");
    c.supernodal = CHOLMOD_SIMPLICIAL;
    c.final_asis = 1;  // keep LDLᵀ
  } else if (o.mode == CholeskyMode::simplicial) {
    c.supernodal = CHOLMOD_SIMPLICIAL;
    c.final_asis = 0;  // CHOLMOD's simplicial factorisation is LDLᵀ; converted to LLᵀ at the end
    c.final_ll = 1;
  } else {
    c.supernodal = CHOLMOD_SUPERNODAL;
    c.final_asis = 1;
  }
  for (int k = 0; k < 3; ++k) {
    c.nrelax[k] = static_cast<std::size_t>(o.nrelax[k]);
    c.zrelax[k] = o.zrelax[k];
  }
  c.quick_return_if_not_posdef = o.stop_at_failure ? 1 : 0;
}

// A CHOLMOD view, without copy, of a compressed-column matrix read from one triangle.
cholmod_sparse view(const SparseCholesky::SpMat& A, StoredTriangle t) {
  auto& M = const_cast<SparseCholesky::SpMat&>(A);
  cholmod_sparse s{};
  s.nrow = static_cast<std::size_t>(A.rows());
  s.ncol = static_cast<std::size_t>(A.cols());
  s.nzmax = static_cast<std::size_t>(A.nonZeros());
  s.p = M.outerIndexPtr();
  s.i = M.innerIndexPtr();
  s.x = M.valuePtr();
  s.nz = A.isCompressed() ? nullptr : M.innerNonZeroPtr();
  s.packed = A.isCompressed() ? 1 : 0;
  s.sorted = 1;
  s.stype = t == StoredTriangle::upper ? 1 : -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  return s;
}

// A CHOLMOD view of a column-major dense block.
cholmod_dense dense_view(double* x, Eigen::Index rows, Eigen::Index cols) {
  cholmod_dense d{};
  d.nrow = d.d = static_cast<std::size_t>(rows);
  d.ncol = static_cast<std::size_t>(cols);
  d.nzmax = d.nrow * d.ncol;
  d.x = x;
  d.xtype = CHOLMOD_REAL;
  d.dtype = CHOLMOD_DOUBLE;
  return d;
}

int cholmod_system(CholeskySystem s) {
  switch (s) {
    case CholeskySystem::A: return CHOLMOD_A;
    case CholeskySystem::L: return CHOLMOD_L;
    case CholeskySystem::Lt: return CHOLMOD_Lt;
    case CholeskySystem::P: return CHOLMOD_P;
    case CholeskySystem::Pt: return CHOLMOD_Pt;
  }
  return CHOLMOD_A;
}

}  // namespace

struct SparseCholesky::Impl {
  SparseCholeskyOptions options;
  mutable cholmod_common c{};
  cholmod_factor* L = nullptr;
  // solve_in_place's workspaces (cholmod_solve2): kept from one call to the next.
  mutable cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr;
  // options.factor_order_copy: tril(P A Pᵀ) in compressed columns, rows sorted, and per entry
  // the index of its value in the analysed matrix's value array (of `copied_nnz` entries); the
  // values themselves are gathered into a buffer of the factorisation's own.
  std::vector<int> fp, fi, from;
  int copied_nnz = -1;

  void build_factor_order_copy(const cholmod_sparse& A);
  bool factorize_factor_order_copy(const cholmod_sparse& A);

  explicit Impl(const SparseCholeskyOptions& o) : options(o) {
    cholmod_start(&c);
    configure(options, c);
  }
  ~Impl() {
    cholmod_free_dense(&x, &c);
    cholmod_free_dense(&y, &c);
    cholmod_free_dense(&e, &c);
    if (L) cholmod_free_factor(&L, &c);
    cholmod_finish(&c);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
};

// The analysed triangle of A in the factor's order (SparseCholeskyOptions::factor_order_copy);
// left empty when A is not packed or not symmetric.
void SparseCholesky::Impl::build_factor_order_copy(const cholmod_sparse& A) {
  fp.clear();
  fi.clear();
  from.clear();
  copied_nnz = -1;
  if (!A.packed || A.stype == 0) return;
  const int n = static_cast<int>(A.ncol);
  const int* Ap = static_cast<const int*>(A.p);
  const int* Ai = static_cast<const int*>(A.i);
  const int* perm = static_cast<const int*>(L->Perm);
  std::vector<int> inv(n);
  for (int k = 0; k < n; ++k) inv[perm ? perm[k] : k] = k;
  const auto in_triangle = [&](int i, int j) { return A.stype > 0 ? i <= j : i >= j; };
  fp.assign(n + 1, 0);
  for (int j = 0; j < n; ++j)
    for (int q = Ap[j]; q < Ap[j + 1]; ++q)
      if (in_triangle(Ai[q], j)) ++fp[std::min(inv[Ai[q]], inv[j]) + 1];
  for (int k = 0; k < n; ++k) fp[k + 1] += fp[k];
  std::vector<std::pair<int, int>> entry(fp[n]);  // (row, source) per factor-order entry
  std::vector<int> next(fp.begin(), fp.end() - 1);
  for (int j = 0; j < n; ++j)
    for (int q = Ap[j]; q < Ap[j + 1]; ++q)
      if (in_triangle(Ai[q], j)) {
        const int a = inv[Ai[q]], b = inv[j];
        entry[next[std::min(a, b)]++] = {std::max(a, b), q};
      }
  for (int k = 0; k < n; ++k) std::sort(entry.begin() + fp[k], entry.begin() + fp[k + 1]);
  fi.resize(entry.size());
  from.resize(entry.size());
  for (std::size_t t = 0; t < entry.size(); ++t) std::tie(fi[t], from[t]) = entry[t];
  copied_nnz = Ap[n];
}

// Refills the factor-order copy from A and has CHOLMOD factorise it as a matrix already in the
// factor's order (lower triangle, "natural" ordering: no transpose); the factor keeps its
// permutation for the solves. False (nothing done) when A is not the analysed pattern's size.
bool SparseCholesky::Impl::factorize_factor_order_copy(const cholmod_sparse& A) {
  if (fp.empty() || !A.packed || A.ncol + 1 != fp.size() ||
      static_cast<const int*>(A.p)[A.ncol] != copied_nnz)
    return false;
  const double* ax = static_cast<const double*>(A.x);
  const std::size_t nnz = from.size();
  const std::unique_ptr<double[]> fx(new double[nnz]);
  for (std::size_t t = 0; t < nnz; ++t) fx[t] = ax[from[t]];
  cholmod_sparse S{};
  S.nrow = S.ncol = A.ncol;
  S.nzmax = nnz;
  S.p = fp.data();
  S.i = fi.data();
  S.x = fx.get();
  S.packed = 1;
  S.sorted = 1;
  S.stype = -1;
  S.itype = CHOLMOD_INT;
  S.xtype = CHOLMOD_REAL;
  S.dtype = CHOLMOD_DOUBLE;
  const int ordering = L->ordering;
  L->ordering = CHOLMOD_NATURAL;
  cholmod_factorize(&S, L, &c);
  L->ordering = ordering;
  return true;
}

SparseCholesky::SparseCholesky(const SparseCholeskyOptions& options)
    : impl_(std::make_unique<Impl>(options)) {}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

bool SparseCholesky::analyze(const SpMat& A, const int* permutation) {
  const cholmod_sparse s = view(A, impl_->options.triangle);
  return analyze(s, permutation);
}

bool SparseCholesky::analyze(const cholmod_sparse& A, const int* permutation) {
  Impl& m = *impl_;
  if (m.L) cholmod_free_factor(&m.L, &m.c);
  auto& a = const_cast<cholmod_sparse&>(A);
  const CholeskyOrdering o = m.options.ordering;
  if (o == CholeskyOrdering::given) {
    if (permutation == nullptr) throw std::logic_error("SparseCholesky: no permutation given");
    m.c.nmethods = 1;
    m.c.method[0].ordering = CHOLMOD_GIVEN;
    m.L = cholmod_analyze_p(&a, const_cast<int*>(permutation), nullptr, 0, &m.c);
  } else {
    // METIS (also CHOLMOD's default's fallback) keeps its state in a global: one at a time.
    std::optional<std::unique_lock<std::mutex>> lock;
    if (o != CholeskyOrdering::natural && o != CholeskyOrdering::amd)
      lock.emplace(lock_symbolic_analysis());
    m.L = cholmod_analyze(&a, &m.c);
  }
  if (m.L && m.options.factor_order_copy && m.L->is_super && m.options.kind == CholeskyKind::llt)
    m.build_factor_order_copy(A);
  return m.L != nullptr;
}

bool SparseCholesky::adopt_analysis(const SparseCholesky& analysed, const SpMat& A) {
  Impl& m = *impl_;
  if (m.L) cholmod_free_factor(&m.L, &m.c);
  const cholmod_factor* source = analysed.impl_->L;
  if (!source) return false;
  m.L = cholmod_copy_factor(const_cast<cholmod_factor*>(source), &m.c);
  if (m.L && m.L->xtype != CHOLMOD_PATTERN)  // a factorised source: keep its analysis only
    cholmod_change_factor(CHOLMOD_PATTERN, m.L->is_ll, m.L->is_super, 1, 1, m.L, &m.c);
  if (m.L && m.options.factor_order_copy && m.L->is_super && m.options.kind == CholeskyKind::llt)
    m.build_factor_order_copy(view(A, m.options.triangle));
  return m.L != nullptr;
}

bool SparseCholesky::analyzed() const {
  return impl_->L != nullptr;
}

CholeskyStatus SparseCholesky::factorize(const SpMat& A) {
  const cholmod_sparse s = view(A, impl_->options.triangle);
  if (!analyzed()) analyze(s);
  return factorize(s);
}

CholeskyStatus SparseCholesky::factorize(const cholmod_sparse& A) {
  Impl& m = *impl_;
  CholeskyStatus status;
  if (m.L == nullptr) return status;
  {
    std::optional<SerialOpenMpScope> serial;
    if (m.options.threads == CholeskyThreads::calling_thread) serial.emplace();
    if (!m.factorize_factor_order_copy(A))
      cholmod_factorize(const_cast<cholmod_sparse*>(&A), m.L, &m.c);
  }
  status.ok = m.L->minor == m.L->n;
  if (!status.ok) {
    if (m.L->minor < m.L->n) {
      const int* perm = static_cast<const int*>(m.L->Perm);
      const long k = static_cast<long>(m.L->minor);
      status.failed_column = perm ? perm[k] : k;
    }
    return status;
  }
  if (m.options.simplicial_solves && m.L->is_super)
    cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, m.L, &m.c);
  return status;
}

CholeskyStatus SparseCholesky::compute(const SpMat& A) {
  const cholmod_sparse s = view(A, impl_->options.triangle);
  if (!analyze(s)) return {};
  return factorize(s);
}

Eigen::MatrixXd SparseCholesky::solve_columns(const double* B, Eigen::Index rows,
                                              Eigen::Index cols, Eigen::Index stride) const {
  const Impl& m = *impl_;
  cholmod_dense b = dense_view(const_cast<double*>(B), rows, cols);
  b.d = static_cast<std::size_t>(stride);
  b.nzmax = b.d * b.ncol;
  cholmod_dense* x = m.L ? cholmod_solve(CHOLMOD_A, m.L, &b, &m.c) : nullptr;
  if (x == nullptr)
    return Eigen::MatrixXd::Constant(rows, cols, std::numeric_limits<double>::quiet_NaN());
  Eigen::MatrixXd out =
      Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(x->x), rows, cols);
  cholmod_free_dense(&x, &m.c);
  return out;
}

Eigen::VectorXd SparseCholesky::solve(const Eigen::VectorXd& b) const {
  return solve_columns(b.data(), b.size(), 1, b.size()).col(0);
}

void SparseCholesky::solve_in_place(CholeskySystem system, Eigen::VectorXd& v) const {
  const Impl& m = *impl_;
  cholmod_dense b = dense_view(v.data(), v.size(), 1);
  if (m.L == nullptr ||
      !cholmod_solve2(cholmod_system(system), m.L, &b, nullptr, &m.x, nullptr, &m.y, &m.e, &m.c)) {
    v.setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  v = Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(m.x->x), v.size());
}

const int* SparseCholesky::permutation() const {
  return impl_->L ? static_cast<const int*>(impl_->L->Perm) : nullptr;
}

Eigen::VectorXd SparseCholesky::diagonal() const {
  const cholmod_factor* L = impl_->L;
  if (L == nullptr || L->xtype == CHOLMOD_PATTERN) return {};
  Eigen::VectorXd d(static_cast<Eigen::Index>(L->n));
  const double* x = static_cast<const double*>(L->x);
  if (L->is_super) {
    const int* super = static_cast<const int*>(L->super);
    const int* pi = static_cast<const int*>(L->pi);
    const int* px = static_cast<const int*>(L->px);
    for (std::size_t k = 0; k < L->nsuper; ++k) {
      const int ncols = super[k + 1] - super[k], nrows = pi[k + 1] - pi[k];
      for (int j = 0; j < ncols; ++j) d(super[k] + j) = x[px[k] + j * (nrows + 1)];
    }
  } else {
    const int* p = static_cast<const int*>(L->p);  // the diagonal leads each column
    for (std::size_t j = 0; j < L->n; ++j) d(static_cast<Eigen::Index>(j)) = x[p[j]];
  }
  return d;
}

Inertia SparseCholesky::inertia() const {
  Inertia in;
  const Eigen::VectorXd d = diagonal();
  for (const double v : d) {
    if (!std::isfinite(v) || v == 0)
      ++in.singular;
    else if (v < 0)
      ++in.negative;
    else
      ++in.positive;
  }
  return in;
}

double SparseCholesky::factor_nonzeros() const {
  return impl_->c.lnz;
}

double SparseCholesky::factor_flops() const {
  return impl_->c.fl;
}

const cholmod_factor* SparseCholesky::factor() const {
  return impl_->L;
}

SparseCholeskyOptions with_environment(SparseCholeskyOptions options, bool allow_simplicial) {
  const char* env = std::getenv("GRIDSHELL_CHOLESKY");
  if (env == nullptr || *env == '\0' || options.kind != CholeskyKind::llt) return options;
  const std::string value(env);
  if (value == "simplicial") {
    if (allow_simplicial) options.mode = CholeskyMode::simplicial;
    return options;
  }
  options.mode = CholeskyMode::supernodal;
  if (value == "supernodal") return options;
  std::array<int, 3> n{};
  std::array<double, 3> z{};
  if (std::sscanf(env, "supernodal:%d,%d,%d:%lf,%lf,%lf", &n[0], &n[1], &n[2], &z[0], &z[1],
                  &z[2]) != 6)
    throw Error("GRIDSHELL_CHOLESKY", "expected simplicial, supernodal or "
                                      "supernodal:N0,N1,N2:Z0,Z1,Z2, not '" + value + "'");
  options.nrelax = n;
  options.zrelax = z;
  return options;
}

namespace {
// Calls `call(G, c)` on the graph of an upper CSC pattern under the METIS lock, with a
// cholmod_common of its own.
template <class Call>
auto on_graph(int n, const int* p, const int* i, Call call) {
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  cholmod_sparse G = upper_csc_view(n, const_cast<int*>(p), const_cast<int*>(i));
  const auto result = [&] {
    const auto lock = lock_symbolic_analysis();
    return call(G, c);
  }();
  cholmod_finish(&c);
  return result;
}
}  // namespace

bool metis_graph_order(int n, const int* p, const int* i, int* order) {
  return on_graph(n, p, i, [&](cholmod_sparse& G, cholmod_common& c) {
    return cholmod_metis(&G, nullptr, 0, 0, order, &c) != 0;
  });
}

long bisect_graph(int n, const int* p, const int* i, int* part) {
  return on_graph(n, p, i, [&](cholmod_sparse& G, cholmod_common& c) {
    return static_cast<long>(cholmod_bisect(&G, nullptr, 0, 1, part, &c));
  });
}

}  // namespace gridshell
