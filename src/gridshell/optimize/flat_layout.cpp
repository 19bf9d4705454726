// The layout of flat panels (flat_panels_internal.h): which three planes meet at each joint.
#include <array>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/flat_panels_internal.h"

namespace gridshell::flat_detail {

namespace {

/// One use of vertex v by face f: its neighbours in f.
struct Corner {
  int face, slot, prev, next;
};

/// The corners around v in fan order (each one's `next` is the following one's `prev`); for a
/// boundary joint the fan starts at the face after the boundary. Throws for a non-manifold joint.
std::vector<Corner> fan(const std::vector<Corner>& around, bool boundary, int v) {
  const int k = static_cast<int>(around.size());
  int start = 0;
  if (boundary) {  // the corner whose prev is no other corner's next
    start = -1;
    for (int i = 0; i < k && start < 0; ++i) {
      bool follows = false;
      for (int j = 0; j < k; ++j) follows |= j != i && around[j].next == around[i].prev;
      if (!follows) start = i;
    }
    if (start < 0) throw FlatPanelsFailed(fmt::format("joint {} is not manifold", v));
  }
  std::vector<Corner> out{around[start]};
  std::vector<char> used(k, 0);
  used[start] = 1;
  while (static_cast<int>(out.size()) < k) {
    int found = -1;
    for (int j = 0; j < k; ++j)
      if (!used[j] && around[j].prev == out.back().next) found = j;
    if (found < 0) throw FlatPanelsFailed(fmt::format("joint {} is not manifold", v));
    used[found] = 1;
    out.push_back(around[found]);
  }
  return out;
}

/// Adds a fixed plane through x with normal n; returns its plane reference.
int add_fixed(Layout& L, const Vec3& n, const Vec3& x) {
  L.fixed_normal.push_back(n);
  L.fixed_offset.push_back(n.dot(x));
  return -static_cast<int>(L.fixed_normal.size());
}

/// The boundary plane(s) of boundary joint v: normal n_s × t (and t for a corner).
std::pair<Vec3, Vec3> boundary_frame(const PolyMesh& design, int v, int before, int after,
                                     const Vec3& surface_normal) {
  Vec3 t = design.vertex(after) - design.vertex(before);
  if (t.norm() <= 0) t = design.vertex(after) - design.vertex(v);
  t.normalize();
  Vec3 m = surface_normal.cross(t);
  if (m.norm() < 1e-6) m = t.unitOrthogonal();
  return {m.normalized(), t};
}


}  // namespace

/// The layout: which planes meet at each joint; joints of more than three planes split into fans.
Layout build_layout(const PolyMesh& design, const std::vector<Vec3>& vertex_normal,
                    const std::vector<char>& is_support) {
  const Topology topo = build_topology(design);
  const int nv = design.num_vertices();
  std::vector<std::vector<Corner>> around(nv);
  for (int f = 0; f < design.num_faces(); ++f) {
    const auto& face = design.faces[f];
    const int n = static_cast<int>(face.size());
    for (int k = 0; k < n; ++k)
      around[face[k]].push_back({f, k, face[(k + n - 1) % n], face[(k + 1) % n]});
  }
  Layout L;
  L.faces = design.faces;
  std::vector<std::vector<std::vector<int>>> replace(design.num_faces());
  for (int f = 0; f < design.num_faces(); ++f) replace[f].resize(design.faces[f].size());
  L.joints.resize(nv);  // joint v keeps id v; split parts are appended
  for (int v = 0; v < nv; ++v) {
    L.joints[v].source = v;
    L.joints[v].support = is_support[v];
    L.joints[v].pinned = is_support[v] && !topo.on_boundary[v];
    if (around[v].empty()) throw FlatPanelsFailed(fmt::format("joint {} is in no panel", v));
    const bool boundary = topo.on_boundary[v];
    const std::vector<Corner> c = fan(around[v], boundary, v);
    const int k = static_cast<int>(c.size());
    std::vector<std::array<int, 3>> parts;  // planes of each part, in order
    std::vector<std::vector<int>> part_of(k);  // per corner: the parts in face order
    if (!boundary) {
      if (k < 3) throw FlatPanelsFailed(fmt::format("interior joint {} has {} panels", v, k));
      // u_i = f1 ∩ f(i+1) ∩ f(i+2), i = 0 … k − 3 (0-based corners).
      for (int i = 0; i + 2 < k; ++i) parts.push_back({c[0].face, c[i + 1].face, c[i + 2].face});
      for (int i = static_cast<int>(parts.size()) - 1; i >= 0; --i) part_of[0].push_back(i);
      part_of[1] = {0};
      for (int j = 2; j + 1 < k; ++j) part_of[j] = {j - 2, j - 1};
      part_of[k - 1].push_back(k - 3);
    } else {
      const auto [m, t] = boundary_frame(design, v, c.front().prev, c.back().next, vertex_normal[v]);
      const int B = add_fixed(L, m, design.vertex(v));
      if (k == 1) {
        parts.push_back({c[0].face, B, add_fixed(L, t, design.vertex(v))});
        part_of[0] = {0};
      } else {
        // u_i = B ∩ f_i ∩ f(i+1), i = 0 … k − 2.
        for (int i = 0; i + 1 < k; ++i) parts.push_back({B, c[i].face, c[i + 1].face});
        part_of[0] = {0};
        for (int j = 1; j + 1 < k; ++j) part_of[j] = {j - 1, j};
        part_of[k - 1] = {k - 2};
      }
    }
    std::vector<double> along(parts.size(), 0.0);
    Vec3 tangent = Vec3::Zero();
    if (boundary && k >= 3) {  // the parts in order along the boundary, centred on the joint
      tangent = boundary_frame(design, v, c.front().prev, c.back().next, vertex_normal[v]).second;
      for (std::size_t i = 0; i < parts.size(); ++i)
        along[i] = static_cast<double>(i) - 0.5 * static_cast<double>(parts.size() - 1);
    }
    std::vector<int> ids(parts.size());
    for (std::size_t i = 0; i < parts.size(); ++i) {
      ids[i] = i == 0 ? v : static_cast<int>(L.joints.size());
      if (i > 0) L.joints.push_back({v, {0, 0, 0}, false, false});
      for (int s = 0; s < 3; ++s) L.joints[ids[i]].plane[s] = parts[i][s];
      L.joints[ids[i]].along = along[i];
      L.joints[ids[i]].tangent = tangent;
    }
    if (parts.size() > 1) ++L.split;
    for (int j = 0; j < k; ++j) {
      std::vector<int>& r = replace[c[j].face][c[j].slot];
      for (int p : part_of[j]) r.push_back(ids[p]);
    }
  }
  for (int f = 0; f < design.num_faces(); ++f) {
    L.faces[f].clear();
    for (const auto& r : replace[f]) L.faces[f].insert(L.faces[f].end(), r.begin(), r.end());
  }
  return L;
}

}  // namespace gridshell::flat_detail
