#include "gridshell/fem/supernodal_solve.h"

#include <algorithm>
#include <array>
#include <stdexcept>

#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

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

// Forward substitution through one supernode; its updates of the rows below go to x, except
// those of rows marked in `top_column`, which go to `accumulated` (when given). `t` holds nb.
void forward_supernode(const Supernode& S, double* x, double* t, const char* top_column,
                       double* accumulated) {
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
  if (accumulated) {
    for (int i = 0; i < nb; ++i) {
      if (top_column[rows[i]])
        accumulated[rows[i]] += t[i];
      else
        x[rows[i]] -= t[i];
    }
  } else {
    for (int i = 0; i < nb; ++i) x[rows[i]] -= t[i];
  }
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

// The elimination tree of the supernodes, with per subtree its entries and its first supernode
// (in postorder a subtree is the range first..root). Empty when the factor is not postordered.
struct SupernodeTree {
  std::vector<int> parent, first;
  std::vector<std::vector<int>> children;
  std::vector<double> entries;  ///< of the subtree
};

SupernodeTree supernode_tree(const cholmod_factor& L) {
  const int ns = static_cast<int>(L.nsuper);
  std::vector<int> column_super(L.n);
  for (int s = 0; s < ns; ++s) {
    const Supernode S = supernode(L, s);
    std::fill(column_super.begin() + S.k1, column_super.begin() + S.k1 + S.nc, s);
  }
  SupernodeTree tree;
  tree.parent.assign(ns, -1);
  tree.first.resize(ns);
  tree.children.resize(ns);
  tree.entries.assign(ns, 0.0);
  std::vector<int> count(ns, 1);
  for (int s = 0; s < ns; ++s) {
    const Supernode S = supernode(L, s);
    tree.first[s] = s;
    tree.entries[s] += static_cast<double>(S.nc) * S.nr;
    if (S.nr > S.nc) tree.parent[s] = column_super[S.rows[S.nc]];
  }
  for (int s = 0; s < ns; ++s) {
    const int p = tree.parent[s];
    if (p < 0) continue;
    if (p <= s) return {};
    tree.children[p].push_back(s);
    tree.entries[p] += tree.entries[s];
    tree.first[p] = std::min(tree.first[p], tree.first[s]);
    count[p] += count[s];
  }
  for (int s = 0; s < ns; ++s)
    if (s - tree.first[s] + 1 != count[s]) return {};
  return tree;
}

// Longest-processing-time assignment of subtrees (largest first) to two groups; returns the
// groups' entries.
std::array<double, 2> assign(std::vector<int>& subtrees, const SupernodeTree& tree,
                             std::vector<int> (&group)[2]) {
  std::sort(subtrees.begin(), subtrees.end(), [&](int a, int b) {
    return tree.entries[a] != tree.entries[b] ? tree.entries[a] > tree.entries[b] : a < b;
  });
  std::array<double, 2> load{0, 0};
  group[0].clear();
  group[1].clear();
  for (int s : subtrees) {
    const int g = load[1] < load[0] ? 1 : 0;
    group[g].push_back(s);
    load[g] += tree.entries[s];
  }
  return load;
}

}  // namespace

SupernodalTriangular::SupernodalTriangular(const cholmod_factor& L) : L_(L) {
  if (!L.is_super || !L.is_ll || L.xtype != CHOLMOD_REAL || L.itype != CHOLMOD_INT)
    throw std::invalid_argument("SupernodalTriangular: not a real supernodal LL' factor");
  n_ = static_cast<int>(L.n);
  nsuper_ = static_cast<int>(L.nsuper);
  for (int s = 0; s < nsuper_; ++s) {
    const Supernode S = supernode(L, s);
    max_below_ = std::max(max_below_, S.nr - S.nc);
    entries_ += static_cast<double>(S.nc) * S.nr;
  }
  for (auto& w : work_) w.resize(max_below_);
  const SupernodeTree tree = supernode_tree(L);
  if (tree.parent.empty()) return;
  // Grow a top from the roots until the subtrees hanging below it share out evenly (the larger
  // group ≤ 55 % of the two), giving up when the top would hold over a quarter of the entries.
  std::vector<int> subtrees, top, group[2];
  double top_entries = 0;
  for (int s = 0; s < nsuper_; ++s)
    if (tree.parent[s] < 0) subtrees.push_back(s);
  while (!subtrees.empty()) {
    const std::array<double, 2> load = assign(subtrees, tree, group);
    if (!group[1].empty() && std::max(load[0], load[1]) <= 0.55 * (load[0] + load[1])) {
      split_ = true;
      group_entries_[0] = load[0];
      group_entries_[1] = load[1];
      break;
    }
    const int largest = subtrees.front();  // sorted by assign
    top.push_back(largest);
    top_entries += tree.entries[largest] - [&] {
      double below = 0;
      for (int c : tree.children[largest]) below += tree.entries[c];
      return below;
    }();
    if (top_entries > 0.25 * entries_) break;
    subtrees.erase(subtrees.begin());
    subtrees.insert(subtrees.end(), tree.children[largest].begin(), tree.children[largest].end());
  }
  if (!split_) return;
  std::sort(top.begin(), top.end());
  top_ = top;
  top_column_.assign(n_, 0);
  for (int s : top_) {
    const Supernode S = supernode(L, s);
    std::fill(top_column_.begin() + S.k1, top_column_.begin() + S.k1 + S.nc, 1);
  }
  for (int g = 0; g < 2; ++g) {
    for (int root : group[g]) groups_[g].push_back({tree.first[root], root});
    std::sort(groups_[g].begin(), groups_[g].end(),
              [](const Range& a, const Range& b) { return a.first < b.first; });
    accumulated_[g].assign(n_, 0.0);
  }
}

double SupernodalTriangular::group_share(int group) const {
  return split_ && entries_ > 0 ? group_entries_[group] / entries_ : 0.0;
}

void SupernodalTriangular::forward_group(int group, double* x) const {
  for (const Range& r : groups_[group])
    for (int s = r.first; s <= r.last; ++s)
      forward_supernode(supernode(L_, s), x, work_[group].data(), top_column_.data(),
                        accumulated_[group].data());
}

void SupernodalTriangular::backward_group(int group, double* x) const {
  for (const Range& r : groups_[group])
    for (int s = r.last; s >= r.first; --s)
      backward_supernode(supernode(L_, s), x, work_[group].data());
}

void SupernodalTriangular::forward(double* x) const {
  if (!split_) {
    for (int s = 0; s < nsuper_; ++s)
      forward_supernode(supernode(L_, s), x, work_[0].data(), nullptr, nullptr);
    return;
  }
  tbb::this_task_arena::isolate(
      [&] { tbb::parallel_invoke([&] { forward_group(0, x); }, [&] { forward_group(1, x); }); });
  // The groups' updates of the top's rows, in a fixed order, then the top itself.
  for (int s : top_) {
    const Supernode S = supernode(L_, s);
    for (int k = S.k1; k < S.k1 + S.nc; ++k) {
      x[k] -= accumulated_[0][k];
      x[k] -= accumulated_[1][k];
      accumulated_[0][k] = accumulated_[1][k] = 0;
    }
  }
  for (int s : top_) forward_supernode(supernode(L_, s), x, work_[0].data(), nullptr, nullptr);
}

void SupernodalTriangular::backward(double* x) const {
  if (!split_) {
    for (int s = nsuper_ - 1; s >= 0; --s) backward_supernode(supernode(L_, s), x, work_[0].data());
    return;
  }
  for (auto it = top_.rbegin(); it != top_.rend(); ++it)
    backward_supernode(supernode(L_, *it), x, work_[0].data());
  tbb::this_task_arena::isolate(
      [&] { tbb::parallel_invoke([&] { backward_group(0, x); }, [&] { backward_group(1, x); }); });
}

}  // namespace gridshell::fem
