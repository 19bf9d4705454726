#include "gridshell/fem/split_cholesky.h"

#include <cholmod.h>
#include <dlfcn.h>
#include <tbb/parallel_invoke.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <bit>

#include "gridshell/core/cholmod_support.h"
#include "gridshell/core/sparse_cholesky.h"


namespace gridshell::fem {

namespace {

using DenseMatrix = Eigen::MatrixXd;

// LAPACK's dpotrf, looked up in the process (CHOLMOD's LAPACK is loaded with it): the dense
// Cholesky that reports the failing column, without a link-time dependency of the library on
// LAPACK. An executable that exports its own dpotrf_ (src/interpose/) is found first.
int lapack_potrf_lower(int n, double* a) {
  using Potrf = void (*)(const char*, const int*, double*, const int*, int*);
  static const auto potrf = std::bit_cast<Potrf>(dlsym(RTLD_DEFAULT, "dpotrf_"));
  if (potrf == nullptr) return small_potrf('L', n, a, n);
  int info = 0;
  potrf("L", &n, a, &n, &info);
  return info;
}

// A half's factorisation: supernodal LLᵀ (the separator block is read off its last
// supernodes) of its upper triangle, in the given (already fill-reducing, S last) order.
SparseCholeskyOptions half_options() {
  SparseCholeskyOptions o;
  o.ordering = CholeskyOrdering::given;
  o.triangle = StoredTriangle::upper;
  return with_environment(o, /*allow_simplicial=*/false);
}

// One half h ∪ S of the split, factorised by CHOLMOD with S ordered last.
struct Half {
  SparseCholesky llt{half_options()};
  cholmod_sparse K{};           // local upper CSC: pattern and values
  std::vector<int> p, i;        // K's arrays
  std::vector<double> x;        //
  std::vector<long> source;     // K.x[k] = global K.x[source[k]]
  std::vector<int> global_dof;  // local dof → global dof
  int n = 0;                    // local dofs
  int nh = 0;                   // dofs of the half itself (S follows)
  std::vector<int> s_order;     // position q in the factor's S block → separator dof index
  DenseMatrix Lss;              // dense trailing block of L (factor order), lower
};

}  // namespace

namespace {

/// 1. A vertex separator of the node graph (upper CSC gp, gi): part[v] = 0 or 1 for the
/// halves, 2 for the separator. False when it is not worth splitting (separator over 6 % of
/// the nodes, or a half under 20 %).
bool bisect_nodes(const std::vector<int>& gp, const std::vector<int>& gi, std::vector<int>& part) {
  const int nn = static_cast<int>(gp.size()) - 1;
  const long nsep = bisect_graph(nn, gp.data(), gi.data(), part.data());
  if (nsep <= 0) return false;
  const long n0 = std::count(part.begin(), part.end(), 0);
  const long n1 = std::count(part.begin(), part.end(), 1);
  return !(nsep > 0.06 * nn || n0 < 0.2 * nn || n1 < 0.2 * nn);
}

/// The nodes of half h, in the fill-reducing (METIS) order of the half's own node graph.
/// Empty and false when METIS fails.
bool half_nodes_in_order(const std::vector<int>& gp, const std::vector<int>& gi,
                         const std::vector<int>& part, int h, std::vector<int>& ordered) {
  const int nn = static_cast<int>(gp.size()) - 1;
  std::vector<int> local(nn, -1), nodes;
  for (int v = 0; v < nn; ++v)
    if (part[v] == h) {
      local[v] = static_cast<int>(nodes.size());
      nodes.push_back(v);
    }
  const int nh_nodes = static_cast<int>(nodes.size());
  std::vector<int> hp(nh_nodes + 1, 0), hi;
  for (int q = 0; q < nh_nodes; ++q) {
    const int v = nodes[q];
    for (int k = gp[v]; k < gp[v + 1]; ++k)
      if (local[gi[k]] >= 0) hi.push_back(local[gi[k]]);
    hp[q + 1] = static_cast<int>(hi.size());
  }
  // gi is sorted per column and local[] is increasing in v: hi stays sorted, upper.
  std::vector<int> node_perm(nh_nodes);
  if (!metis_graph_order(nh_nodes, hp.data(), hi.data(), node_perm.data())) return false;
  ordered.resize(nh_nodes);
  for (int q = 0; q < nh_nodes; ++q) ordered[q] = nodes[node_perm[q]];
  return true;
}

/// H's local upper pattern: every stored entry of K between dofs with a local number
/// (dof_local ≥ 0), in the column of its larger local index (counting pass, then the short
/// columns sorted by row); H.source remembers where each value comes from in K.
void build_local_pattern(const cholmod_sparse& K, const std::vector<int>& dof_local, Half& H) {
  const int* Kp = static_cast<const int*>(K.p);
  const int* Ki = static_cast<const int*>(K.i);
  const int ndof = static_cast<int>(dof_local.size());
  H.p.assign(H.n + 1, 0);
  for (int j = 0; j < ndof; ++j) {
    const int lj = dof_local[j];
    if (lj < 0) continue;
    for (int k = Kp[j]; k < Kp[j + 1]; ++k) {
      const int li = dof_local[Ki[k]];
      if (li >= 0) ++H.p[std::max(li, lj) + 1];
    }
  }
  for (int j = 0; j < H.n; ++j) H.p[j + 1] += H.p[j];
  const long nnz = H.p[H.n];
  std::vector<std::pair<int, long>> slot(nnz);  // (row, source)
  std::vector<int> next(H.p.begin(), H.p.end() - 1);
  for (int j = 0; j < ndof; ++j) {
    const int lj = dof_local[j];
    if (lj < 0) continue;
    for (int k = Kp[j]; k < Kp[j + 1]; ++k) {
      const int li = dof_local[Ki[k]];
      if (li >= 0) slot[next[std::max(li, lj)]++] = {std::min(li, lj), k};
    }
  }
  H.i.resize(nnz);
  H.x.assign(nnz, 0.0);
  H.source.resize(nnz);
  for (int j = 0; j < H.n; ++j) {
    std::sort(slot.begin() + H.p[j], slot.begin() + H.p[j + 1]);
    for (int k = H.p[j]; k < H.p[j + 1]; ++k) {
      H.i[k] = slot[k].first;
      H.source[k] = slot[k].second;
    }
  }
  H.K = upper_csc_view(H.n, H.p.data(), H.i.data(), H.x.data());
}

/// Symbolic analysis of H in its local numbering (already fill-reducing, S last: identity
/// ordering). Postordering the elimination tree keeps S last when it is the top of a single
/// tree; false when it did not.
bool analyze_separator_last(int m, Half& H) {
  std::vector<int> ident(H.n);
  for (int l = 0; l < H.n; ++l) ident[l] = l;
  if (!H.llt.analyze(H.K, ident.data())) return false;
  const int* perm = H.llt.permutation();
  H.s_order.resize(m);
  for (int q = 0; q < m; ++q) {
    const int l = perm[H.nh + q];
    if (l < H.nh) return false;  // S did not stay last
    H.s_order[q] = l - H.nh;
  }
  return true;
}

/// 2. Half h ∪ S: local numbering (its nodes in METIS order, then the separator nodes in id
/// order), pattern, symbolic analysis with S kept last.
bool prepare_half(const cholmod_sparse& K, int dpn, const std::vector<int>& gp,
                  const std::vector<int>& gi, const std::vector<int>& part,
                  const std::vector<int>& sep_dof, int h, Half& H) {
  std::vector<int> nodes;
  if (!half_nodes_in_order(gp, gi, part, h, nodes)) return false;
  const int nh_nodes = static_cast<int>(nodes.size());
  const int m = static_cast<int>(sep_dof.size()), ndof = static_cast<int>(K.ncol);
  std::vector<int> dof_local(ndof, -1);
  H.nh = nh_nodes * dpn;
  H.n = H.nh + m;
  H.global_dof.resize(H.n);
  for (int q = 0; q < nh_nodes; ++q)
    for (int d = 0; d < dpn; ++d) H.global_dof[dpn * q + d] = dpn * nodes[q] + d;
  for (int k = 0; k < m; ++k) H.global_dof[H.nh + k] = sep_dof[k];
  for (int l = 0; l < H.n; ++l) dof_local[H.global_dof[l]] = l;
  build_local_pattern(K, dof_local, H);
  return analyze_separator_last(m, H);
}

}  // namespace

struct SplitCholesky::Impl {
  int dpn = 6;
  int ndof = 0;
  std::vector<int> sep_dof;  // separator dof index → global dof
  std::array<std::unique_ptr<Half>, 2> half;
  DenseMatrix C;  // dense Cholesky factor of the separator's Schur complement (lower)
  std::vector<std::pair<long, long>> kss;  // (global K.x index, dense position r*m + c)
};

SplitCholesky::SplitCholesky() : impl_(std::make_unique<Impl>()) {}
SplitCholesky::~SplitCholesky() = default;

bool SplitCholesky::analyze(const cholmod_sparse& K, int dofs_per_node, const std::vector<int>& gp,
                            const std::vector<int>& gi) {
  Impl& I = *impl_;
  I = Impl{};
  I.dpn = dofs_per_node;
  const int nn = static_cast<int>(gp.size()) - 1;
  I.ndof = static_cast<int>(K.ncol);
  if (nn < 64 || I.ndof != nn * I.dpn) return false;

  std::vector<int> part(nn, 0);
  if (!bisect_nodes(gp, gi, part)) return false;
  for (int v = 0; v < nn; ++v)
    if (part[v] == 2)
      for (int d = 0; d < I.dpn; ++d) I.sep_dof.push_back(I.dpn * v + d);
  const int m = static_cast<int>(I.sep_dof.size());

  // The two halves are prepared side by side (only the METIS calls take turns, under the lock).
  for (auto& h : I.half) h = std::make_unique<Half>();
  bool ok0 = false, ok1 = false;
  tbb::parallel_invoke(
      [&] { ok0 = prepare_half(K, I.dpn, gp, gi, part, I.sep_dof, 0, *I.half[0]); },
      [&] { ok1 = prepare_half(K, I.dpn, gp, gi, part, I.sep_dof, 1, *I.half[1]); });
  if (!ok0 || !ok1) return false;
  // Positions of K_SS's stored entries in the dense separator matrix.
  const int* Kp = static_cast<const int*>(K.p);
  const int* Ki = static_cast<const int*>(K.i);
  std::vector<int> sep_of_dof(I.ndof, -1);
  for (int k = 0; k < m; ++k) sep_of_dof[I.sep_dof[k]] = k;
  for (int j = 0; j < I.ndof; ++j) {
    const int sj = sep_of_dof[j];
    if (sj < 0) continue;
    for (int k = Kp[j]; k < Kp[j + 1]; ++k) {
      const int si = sep_of_dof[Ki[k]];
      if (si < 0) continue;
      I.kss.emplace_back(k, static_cast<long>(std::max(si, sj)) * m + std::min(si, sj));
    }
  }
  return true;
}

long SplitCholesky::factorize(const cholmod_sparse& K) {
  Impl& I = *impl_;
  const int m = static_cast<int>(I.sep_dof.size());
  const double* Kx = static_cast<const double*>(K.x);
  std::array<long, 2> failed{-1, -1};
  std::array<DenseMatrix, 2> share;  // L_SS L_SSᵀ of each half, separator order (lower)
  auto run = [&](int h) {
    Half& H = *I.half[h];
    for (std::size_t k = 0; k < H.x.size(); ++k) H.x[k] = Kx[H.source[k]];
    const CholeskyStatus status = H.llt.factorize(H.K);
    if (!status.ok) {
      failed[h] = status.failed_column >= 0 ? H.global_dof[status.failed_column] : 0;
      return;
    }
    // The trailing m × m block of the supernodal factor (its last supernodes).
    H.Lss = DenseMatrix::Zero(m, m);
    const cholmod_factor* L = H.llt.factor();
    const int* super = static_cast<const int*>(L->super);
    const int* pi = static_cast<const int*>(L->pi);
    const int* px = static_cast<const int*>(L->px);
    const int* Ls = static_cast<const int*>(L->s);
    const double* Lx = static_cast<const double*>(L->x);
    for (long s = static_cast<long>(L->nsuper) - 1; s >= 0 && super[s + 1] > H.nh; --s) {
      const int k1 = super[s], k2 = super[s + 1];
      const int nsrow = pi[s + 1] - pi[s];
      for (int col = std::max(k1, H.nh); col < k2; ++col)
        for (int r = 0; r < nsrow; ++r) {
          const int row = Ls[pi[s] + r];
          if (row >= H.nh) H.Lss(row - H.nh, col - H.nh) = Lx[px[s] + (col - k1) * nsrow + r];
        }
    }
    const DenseMatrix LLt = H.Lss.triangularView<Eigen::Lower>() * H.Lss.transpose();
    share[h] = DenseMatrix(m, m);
    for (int b = 0; b < m; ++b)
      for (int a = 0; a < m; ++a) share[h](H.s_order[a], H.s_order[b]) = LLt(a, b);
  };
  tbb::parallel_invoke([&] { run(0); }, [&] { run(1); });
  for (long f : failed)
    if (f >= 0) return f;
  // Schur complement of the separator and its dense Cholesky factor.
  I.C = share[0] + share[1];
  for (const auto& [k, pos] : I.kss) {
    const long r = pos / m, c = pos % m;
    I.C(r, c) -= Kx[k];
    if (r != c) I.C(c, r) -= Kx[k];
  }
  const int info = lapack_potrf_lower(m, I.C.data());
  if (info > 0) return I.sep_dof[info - 1];
  I.C.triangularView<Eigen::StrictlyUpper>().setZero();
  return -1;
}

Eigen::VectorXd SplitCholesky::solve(const Eigen::VectorXd& b) const {
  const Impl& I = *impl_;
  const int m = static_cast<int>(I.sep_dof.size());
  std::array<Eigen::VectorXd, 2> w;  // L⁻¹ P r of each half, then its back substitution
  std::array<Eigen::VectorXd, 2> g;  // Σ contributions L_SS w_S, separator order
  auto forward = [&](int h) {
    const Half& H = *I.half[h];
    w[h] = Eigen::VectorXd::Zero(H.n);
    for (int l = 0; l < H.nh; ++l) w[h](l) = b(H.global_dof[l]);
    H.llt.solve_in_place(CholeskySystem::P, w[h]);
    H.llt.solve_in_place(CholeskySystem::L, w[h]);
    const Eigen::VectorXd t = H.Lss.triangularView<Eigen::Lower>() * w[h].tail(m);
    g[h] = Eigen::VectorXd(m);
    for (int q = 0; q < m; ++q) g[h](H.s_order[q]) = t(q);
  };
  tbb::parallel_invoke([&] { forward(0); }, [&] { forward(1); });
  Eigen::VectorXd xs(m);
  for (int k = 0; k < m; ++k) xs(k) = b(I.sep_dof[k]) + g[0](k) + g[1](k);
  I.C.triangularView<Eigen::Lower>().solveInPlace(xs);
  I.C.triangularView<Eigen::Lower>().transpose().solveInPlace(xs);

  Eigen::VectorXd x(I.ndof);
  for (int k = 0; k < m; ++k) x(I.sep_dof[k]) = xs(k);
  auto backward = [&](int h) {
    const Half& H = *I.half[h];
    Eigen::VectorXd xq(m);  // x_S in this half's factor order
    for (int q = 0; q < m; ++q) xq(q) = xs(H.s_order[q]);
    w[h].tail(m) = H.Lss.triangularView<Eigen::Lower>().transpose() * xq;
    H.llt.solve_in_place(CholeskySystem::Lt, w[h]);
    H.llt.solve_in_place(CholeskySystem::Pt, w[h]);
    for (int l = 0; l < H.nh; ++l) x(H.global_dof[l]) = w[h](l);
  };
  tbb::parallel_invoke([&] { backward(0); }, [&] { backward(1); });
  return x;
}

double SplitCholesky::factor_nnz() const {
  const Impl& I = *impl_;
  const double m = static_cast<double>(I.sep_dof.size());
  double s = m * (m + 1) / 2;
  for (const auto& h : I.half)
    if (h) s += h->llt.factor_nonzeros();
  return s;
}

double SplitCholesky::factor_flops() const {
  const Impl& I = *impl_;
  const double m = static_cast<double>(I.sep_dof.size());
  double s = m * m * m / 3 + 2 * m * m * m / 2;  // dense factor + the two L_SS L_SSᵀ
  for (const auto& h : I.half)
    if (h) s += h->llt.factor_flops();
  return s;
}

int SplitCholesky::separator_dofs() const {
  return static_cast<int>(impl_->sep_dof.size());
}

}  // namespace gridshell::fem
