#include "gridshell/fem/frame_relax.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include <tbb/parallel_for.h>

#include "gridshell/core/sparse_cholesky.h"

namespace gridshell::fem {

std::vector<std::vector<int>> node_elements(const FrameMesh& mesh) {
  std::vector<std::vector<int>> out(mesh.X.rows());
  for (int k = 0; k < static_cast<int>(mesh.elements.size()); ++k) {
    out[mesh.elements[k].i].push_back(k);
    out[mesh.elements[k].j].push_back(k);
  }
  return out;
}

namespace {

// The fewest nodes carrying `share` of |r|² (ties by node id), or empty when more than
// `max_nodes` are needed.
std::vector<int> residual_core(const FrameMesh& mesh, const Eigen::VectorXd& r, double share,
                               int max_nodes) {
  const int n = static_cast<int>(mesh.X.rows());
  std::vector<double> e(n, 0.0);
  double total = 0;
  for (int v = 0; v < n; ++v) {
    for (int c = 0; c < 6; ++c)
      if (mesh.dof[v][c] >= 0) e[v] += r(mesh.dof[v][c]) * r(mesh.dof[v][c]);
    total += e[v];
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  const int take = std::min(n, max_nodes + 1);
  std::partial_sort(order.begin(), order.begin() + take, order.end(),
                    [&](int a, int b) { return e[a] != e[b] ? e[a] > e[b] : a < b; });
  double acc = 0;
  for (int k = 0; k < take; ++k) {
    acc += e[order[k]];
    if (acc >= share * total) {
      order.resize(k + 1);
      return order;
    }
  }
  return {};
}

// The core and `rings` rings of neighbours; sorted node ids.
std::vector<int> grow_region(const FrameMesh& mesh, const std::vector<std::vector<int>>& ne,
                             std::vector<int> nodes, int rings) {
  std::vector<char> in(mesh.X.rows(), 0);
  for (int v : nodes) in[v] = 1;
  std::vector<int> front = nodes;
  for (int ring = 0; ring < rings; ++ring) {
    std::vector<int> next;
    for (int v : front)
      for (int k : ne[v])
        for (int w : {mesh.elements[k].i, mesh.elements[k].j})
          if (!in[w]) {
            in[w] = 1;
            next.push_back(w);
          }
    nodes.insert(nodes.end(), next.begin(), next.end());
    front = std::move(next);
  }
  std::sort(nodes.begin(), nodes.end());
  return nodes;
}

// The region's equations: local index per free dof of its nodes, the elements that touch it,
// and the pattern of its tangent (upper triangle) with each element entry's value slot.
struct Region {
  std::vector<int> nodes, elements;
  std::vector<int> local;  // per free dof: local index or −1
  std::vector<int> dofs;   // local index → free dof
  SpMat K;                 // upper triangle; values refilled by every evaluation
  std::vector<int> slot;   // 144 per element of `elements`, (q, p) row-major: value index or −1
};

// Local indices of an element's 12 dofs (−1: restrained or outside the region).
std::array<int, 12> local_indices(const FrameMesh& mesh, const Region& g,
                                  const FrameMesh::Element& e) {
  std::array<int, 12> idx;
  for (int q = 0; q < 12; ++q) {
    const int v = q < 6 ? e.i : e.j, d = mesh.dof[v][q % 6];
    idx[q] = d >= 0 ? g.local[d] : -1;
  }
  return idx;
}

Region make_region(const FrameMesh& mesh, const std::vector<std::vector<int>>& ne,
                   std::vector<int> nodes) {
  Region g;
  g.nodes = std::move(nodes);
  g.local.assign(mesh.num_dofs, -1);
  for (int v : g.nodes)
    for (int c = 0; c < 6; ++c)
      if (const int d = mesh.dof[v][c]; d >= 0) {
        g.local[d] = static_cast<int>(g.dofs.size());
        g.dofs.push_back(d);
      }
  for (int v : g.nodes) g.elements.insert(g.elements.end(), ne[v].begin(), ne[v].end());
  std::sort(g.elements.begin(), g.elements.end());
  g.elements.erase(std::unique(g.elements.begin(), g.elements.end()), g.elements.end());
  // The pattern, then every element entry's place in it (upper triangle: row ≤ column).
  const int m = static_cast<int>(g.dofs.size());
  std::vector<Eigen::Triplet<double>> trip;
  for (int k : g.elements) {
    const std::array<int, 12> idx = local_indices(mesh, g, mesh.elements[k]);
    for (int q = 0; q < 12; ++q)
      for (int p = 0; p < 12; ++p)
        if (idx[q] >= 0 && idx[p] >= idx[q]) trip.emplace_back(idx[q], idx[p], 0.0);
  }
  g.K.resize(m, m);
  g.K.setFromTriplets(trip.begin(), trip.end());
  g.slot.assign(g.elements.size() * 144, -1);
  for (size_t a = 0; a < g.elements.size(); ++a) {
    const std::array<int, 12> idx = local_indices(mesh, g, mesh.elements[g.elements[a]]);
    for (int q = 0; q < 12; ++q)
      for (int p = 0; p < 12; ++p) {
        if (idx[q] < 0 || idx[p] < idx[q]) continue;
        const int* begin = g.K.innerIndexPtr() + g.K.outerIndexPtr()[idx[p]];
        const int* end = g.K.innerIndexPtr() + g.K.outerIndexPtr()[idx[p] + 1];
        g.slot[a * 144 + q * 12 + p] =
            static_cast<int>(std::lower_bound(begin, end, idx[q]) - g.K.innerIndexPtr());
      }
  }
  return g;
}

// The region's residual λ f − f_int over its free dofs (every other node held), its elements'
// forces (in the order of g.elements) and, when `tangent`, its tangent's values in g.K. The
// elements are evaluated in parallel into their own slots and added in element order, so the
// result does not depend on the thread count.
Eigen::VectorXd region_residual(const FrameMesh& mesh, Region& g, const FrameState& st,
                                double lambda, bool tangent, std::vector<Vec12>& forces) {
  const int m = static_cast<int>(g.dofs.size()), ne = static_cast<int>(g.elements.size());
  forces.resize(ne);
  std::vector<Mat12> Ke(tangent ? ne : 0);
  tbb::parallel_for(0, ne, [&](int a) {
    const FrameMesh::Element& e = mesh.elements[g.elements[a]];
    double N;
    if (tangent)
      Ke[a] = element_tangent(e, st, forces[a], N);
    else
      forces[a] = element_force(e, st, N);
  });
  Eigen::VectorXd res(m);
  for (int a = 0; a < m; ++a) res(a) = lambda * mesh.load(g.dofs[a]);
  if (tangent) std::fill_n(g.K.valuePtr(), g.K.nonZeros(), 0.0);
  for (int a = 0; a < ne; ++a) {
    const std::array<int, 12> idx = local_indices(mesh, g, mesh.elements[g.elements[a]]);
    for (int q = 0; q < 12; ++q)
      if (idx[q] >= 0) res(idx[q]) -= forces[a](q);
    if (!tangent) continue;
    const int* slot = g.slot.data() + static_cast<size_t>(a) * 144;
    for (int q = 0; q < 144; ++q)
      if (slot[q] >= 0) g.K.valuePtr()[slot[q]] += Ke[a](q / 12, q % 12);
  }
  return res;
}

// Adds the region's increment x (local dofs) to the state and to du (free dofs).
void apply_local(const FrameMesh& mesh, const Region& g, const Eigen::VectorXd& x, FrameState& st,
                 Eigen::VectorXd& du) {
  Eigen::VectorXd full = Eigen::VectorXd::Zero(mesh.num_dofs);
  for (size_t a = 0; a < g.dofs.size(); ++a) full(g.dofs[a]) = x(a);
  apply_increment(mesh, full, st);  // exp(0) = I exactly: nodes outside the region stay as they are
  du += full;
}

// The region's tangent is factorised by the library's sparse Cholesky (LLᵀ: it must be positive
// definite, or the relaxation is refused), AMD-ordered once per region.
SparseCholeskyOptions region_cholesky() {
  SparseCholeskyOptions o;
  o.ordering = CholeskyOrdering::amd;
  o.triangle = StoredTriangle::upper;
  o.stop_at_failure = true;
  return o;
}

}  // namespace

LocalRelaxResult relax_locally(const FrameMesh& mesh,
                               const std::vector<std::vector<int>>& node_elements, double lambda,
                               const Eigen::VectorXd& r, FrameState& state, Eigen::VectorXd& du,
                               const LocalRelaxOptions& opt, std::vector<Vec12>* element_forces) {
  LocalRelaxResult out;
  const int n = static_cast<int>(mesh.X.rows());
  const int max_core = std::max(1, static_cast<int>(opt.max_core_fraction * n));
  std::vector<int> core = residual_core(mesh, r, opt.share, max_core);
  if (core.empty()) return out;
  out.core = static_cast<int>(core.size());
  Region g = make_region(mesh, node_elements, grow_region(mesh, node_elements, core, opt.rings));
  out.nodes = static_cast<int>(g.nodes.size());
  if (g.dofs.empty()) return out;
  std::vector<Vec12> forces, best_forces;
  Eigen::VectorXd res = region_residual(mesh, g, state, lambda, true, forces);
  out.before = out.after = res.norm();
  if (!(out.before > 0)) return out;
  const double target = opt.reduction * out.before;
  // Newton on the region from `state`; the iterate with the smallest residual is kept (a first
  // step may overshoot where held neighbours stiffen the region by membrane action). The
  // tangent is evaluated only where another iteration follows.
  FrameState it_state = state;
  Eigen::VectorXd it_du = du;
  SparseCholesky chol(region_cholesky());
  for (int it = 0; it < opt.max_iterations; ++it) {
    if (!chol.factorize(g.K).ok) break;
    const Eigen::VectorXd x = chol.solve(res);
    if (!x.allFinite()) break;
    apply_local(mesh, g, x, it_state, it_du);
    res = region_residual(mesh, g, it_state, lambda, false, forces);
    const double it_norm = res.norm();
    if (!std::isfinite(it_norm)) break;
    if (it_norm < out.after) {
      state = it_state;
      du = it_du;
      out.after = it_norm;
      out.relaxed = true;
      out.iterations = it + 1;
      best_forces = forces;
    }
    if (it_norm <= target || it + 1 == opt.max_iterations) break;
    res = region_residual(mesh, g, it_state, lambda, true, forces);
  }
  if (out.relaxed && element_forces)
    for (size_t a = 0; a < g.elements.size(); ++a)
      (*element_forces)[g.elements[a]] = best_forces[a];
  return out;
}

}  // namespace gridshell::fem
