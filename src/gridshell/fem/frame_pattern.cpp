#include "gridshell/fem/frame_pattern.h"

#include <algorithm>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>

namespace gridshell::fem {

namespace {
// How an element couples its two nodes: a truss only their translations, a beam every dof.
enum class Coupling : char { translation, full };

// Per node, the nodes it shares an element with (itself included), ascending, each with the
// strongest coupling of those elements.
std::vector<std::vector<std::pair<int, Coupling>>> node_couplings(const FrameMesh& mesh) {
  std::vector<std::vector<std::pair<int, Coupling>>> adj(mesh.X.rows());
  for (const auto& e : mesh.elements) {
    const Coupling c = e.truss ? Coupling::translation : Coupling::full;
    for (const int a : {e.i, e.j}) {
      adj[a].emplace_back(e.i, c);
      adj[a].emplace_back(e.j, c);
    }
  }
  tbb::parallel_for(0, static_cast<int>(adj.size()), [&](int v) {
    auto& list = adj[v];
    std::sort(list.begin(), list.end());
    // Sorted by (node, coupling): the last entry of a node holds its strongest coupling.
    size_t out = 0;
    for (size_t k = 0; k < list.size(); ++k)
      if (k + 1 == list.size() || list[k + 1].first != list[k].first) list[out++] = list[k];
    list.resize(out);
  });
  return adj;
}
}  // namespace

// Column c of node v holds, for every node u coupled to v (ascending), u's free dofs that the
// coupling reaches (dof numbers grow with the node and then the component, so the rows come out
// sorted). Every free dof has an element, so every diagonal entry is in the pattern.
SpMat frame_pattern(const FrameMesh& mesh) {
  const int n = static_cast<int>(mesh.X.rows());
  const auto adj = node_couplings(mesh);
  const auto couples = [&](int c, int u, Coupling k, int cu) {
    return mesh.dof[u][cu] >= 0 && (k == Coupling::full || (c < 3 && cu < 3));
  };
  std::vector<int> outer(mesh.num_dofs + 1, 0);
  for (int v = 0; v < n; ++v)
    for (int c = 0; c < 6; ++c) {
      const int col = mesh.dof[v][c];
      if (col < 0) continue;
      int count = 0;
      for (const auto& [u, k] : adj[v])
        for (int cu = 0; cu < 6; ++cu) count += couples(c, u, k, cu);
      outer[col + 1] = count;
    }
  for (int d = 0; d < mesh.num_dofs; ++d) outer[d + 1] += outer[d];
  SpMat K;
  K.resize(mesh.num_dofs, mesh.num_dofs);
  K.resizeNonZeros(outer.back());
  std::copy(outer.begin(), outer.end(), K.outerIndexPtr());
  std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
  tbb::parallel_for(0, n, [&](int v) {
    for (int c = 0; c < 6; ++c) {
      const int col = mesh.dof[v][c];
      if (col < 0) continue;
      int* rows = K.innerIndexPtr() + outer[col];
      for (const auto& [u, k] : adj[v])
        for (int cu = 0; cu < 6; ++cu)
          if (couples(c, u, k, cu)) *rows++ = mesh.dof[u][cu];
    }
  });
  return K;
}

}  // namespace gridshell::fem
