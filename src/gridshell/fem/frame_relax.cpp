#include "gridshell/fem/frame_relax.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/SparseCholesky>

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

// The region's equations: local index per free dof of its nodes, and the elements that touch it.
struct Region {
  std::vector<int> nodes, elements;
  std::vector<int> local;  // per free dof: local index or −1
  std::vector<int> dofs;   // local index → free dof
};

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
  return g;
}

// The region's residual λ f − f_int over its free dofs and its tangent K (every other node
// held).
Eigen::VectorXd region_residual(const FrameMesh& mesh, const Region& g, const FrameState& st,
                                double lambda, Eigen::SparseMatrix<double>& K) {
  const int m = static_cast<int>(g.dofs.size());
  Eigen::VectorXd res(m);
  for (int a = 0; a < m; ++a) res(a) = lambda * mesh.load(g.dofs[a]);
  std::vector<Eigen::Triplet<double>> trip;
  for (int k : g.elements) {
    const FrameMesh::Element& e = mesh.elements[k];
    Vec12 f;
    double N;
    const Mat12 Ke = element_tangent(e, st, f, N);
    int idx[12];
    for (int q = 0; q < 12; ++q) {
      const int v = q < 6 ? e.i : e.j, d = mesh.dof[v][q % 6];
      idx[q] = d >= 0 ? g.local[d] : -1;
    }
    for (int q = 0; q < 12; ++q) {
      if (idx[q] < 0) continue;
      res(idx[q]) -= f(q);
      for (int p = 0; p < 12; ++p)
        if (idx[p] >= 0) trip.emplace_back(idx[q], idx[p], Ke(q, p));
    }
  }
  K.resize(m, m);
  K.setFromTriplets(trip.begin(), trip.end());
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

}  // namespace

LocalRelaxResult relax_locally(const FrameMesh& mesh,
                               const std::vector<std::vector<int>>& node_elements, double lambda,
                               const Eigen::VectorXd& r, FrameState& state, Eigen::VectorXd& du,
                               const LocalRelaxOptions& opt) {
  LocalRelaxResult out;
  const int n = static_cast<int>(mesh.X.rows());
  const int max_core = std::max(1, static_cast<int>(opt.max_core_fraction * n));
  std::vector<int> core = residual_core(mesh, r, opt.share, max_core);
  if (core.empty()) return out;
  out.core = static_cast<int>(core.size());
  const Region g =
      make_region(mesh, node_elements, grow_region(mesh, node_elements, core, opt.rings));
  out.nodes = static_cast<int>(g.nodes.size());
  if (g.dofs.empty()) return out;
  Eigen::SparseMatrix<double> K;
  Eigen::VectorXd res = region_residual(mesh, g, state, lambda, K);
  out.before = out.after = res.norm();
  const double target = opt.reduction * out.before;
  // Newton on the region from `state`; the iterate with the smallest residual is kept (a first
  // step may overshoot where held neighbours stiffen the region by membrane action).
  FrameState it_state = state;
  Eigen::VectorXd it_du = du;
  double it_norm = out.before;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  for (int it = 0; it < opt.max_iterations && it_norm > target; ++it) {
    ldlt.compute(K);
    if (ldlt.info() != Eigen::Success || (ldlt.vectorD().array() <= 0).any()) break;
    const Eigen::VectorXd x = ldlt.solve(res);
    if (!x.allFinite()) break;
    apply_local(mesh, g, x, it_state, it_du);
    res = region_residual(mesh, g, it_state, lambda, K);
    it_norm = res.norm();
    if (!std::isfinite(it_norm)) break;
    if (it_norm < out.after) {
      state = it_state;
      du = it_du;
      out.after = it_norm;
      out.relaxed = true;
      out.iterations = it + 1;
    }
  }
  return out;
}

}  // namespace gridshell::fem
