#include "gridshell/voronoi/engine.h"

// Extraction: from the optimised seeds to the polygon mesh on M. The support mesh is refined
// across the cell borders, detached pieces of cells are merged away, Voronoi vertices are placed
// exactly in 3-label triangles and on boundary edges, the borders between them are traced into
// polygon edges, and the result is checked (every cell one disk, a manifold with the input's
// topology); a failure is repaired by refining around the offending cells.
// docs/voronoi.md "Method", Extraction.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>

#include <spdlog/spdlog.h>

#include "gridshell/mesh/topology.h"

namespace gridshell::voronoi {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// A vertex of the output: where it sits on the support mesh and what it is.
struct Node {
  int tri = 0;  ///< support triangle
  Vec3 bary{1, 0, 0};
  int kind = 0;        ///< 0 Voronoi vertex, 1 border meets boundary, 2 corner
  int u = -1, v = -1;  ///< support edge (boundary nodes) or vertex (corner: u)
};

/// The outcome of one extraction attempt.
struct Extraction {
  bool ok = false;
  std::vector<Node> nodes;
  std::vector<std::vector<int>> faces;  ///< per seed (empty: seed without region)
  std::vector<int> bad_labels;          ///< cells to refine around on failure
  std::string problem;
};

Vec3 clamp_bary(Vec3 b) {
  b = b.cwiseMax(0.0);
  const double s = b.sum();
  return s > 0 ? Vec3(b / s) : Vec3(1.0 / 3, 1.0 / 3, 1.0 / 3);
}

// ---------------------------------------------------------------------------------------------
// Refinement before extraction, and around bad cells

/// Refines the support mesh for extraction (labels current on return): the whole surface to
/// extraction_base·R, then the edges crossing cell borders, pass by pass, to extraction_edge·R.
void refine_for_extraction(Engine& E, const TessellationOptions& o, Clock::time_point t_extract) {
  const double R = E.R;
  compute_labels(E, 0, static_cast<int>(E.label.size()));
  if (o.extraction_base > 0) {
    // A cell corner can poke between the corners of a coarse triangle without labelling any of
    // them; the border refinement below would not see it. Sample the whole surface at
    // extraction_base·R first (as the old single-level engine did at 0.2 R).
    const int nv0 = E.S.deformed.num_vertices();
    refine_to_length(E.S, o.extraction_base * R);
    E.corner_vertex.resize(E.S.deformed.num_vertices(), 0);
    compute_labels(E, nv0);
  }
  const double he = o.extraction_edge * R;
  // Passes to bring the longest border edge down to `extraction_edge`, and a few more.
  double longest = 0;
  for (int t = 0; t < E.S.deformed.num_faces(); ++t)
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (E.S.deformed.vertex(E.S.deformed.F(t, k)) -
                                   E.S.deformed.vertex(E.S.deformed.F(t, (k + 1) % 3)))
                                      .squaredNorm());
  const int passes =
      std::max(o.extraction_passes,
               static_cast<int>(std::ceil(std::log2(std::max(1.0, std::sqrt(longest) / he)))) + 1);
  for (int pass = 0; pass < passes; ++pass) {
    const double h2 = he * he;
    const int nv0 = E.S.deformed.num_vertices();
    const int n = refine_support_mesh(E.S, [&](int a, int b) {
      return E.label[a] != E.label[b] &&
             (E.S.deformed.vertex(a) - E.S.deformed.vertex(b)).squaredNorm() > h2;
    });
    E.corner_vertex.resize(E.S.deformed.num_vertices(), 0);
    if (n == 0) break;
    compute_labels(E, nv0);  // the seeds did not move: only the new vertices need labels
  }
  spdlog::debug("extraction refinement: {} support vertices, {:.2f} s",
                E.S.deformed.num_vertices(), seconds_since(t_extract));
}

/// Repair: refines around the cells of a failed attempt (all cells when it named none), edges
/// down to `h`: the first pass every edge touching such a cell, then the border edges only.
void refine_around_bad_cells(Engine& E, const Extraction& X, double h) {
  std::vector<char> bad(E.seeds.size(), X.bad_labels.empty() ? 1 : 0);
  for (int l : X.bad_labels)
    if (l >= 0 && l < static_cast<int>(bad.size())) bad[l] = 1;
  for (int pass = 0; pass < 3; ++pass) {
    const double h2 = h * h;
    const int nv0 = E.S.deformed.num_vertices();
    const int n = refine_support_mesh(E.S, [&](int a, int b) {
      return (bad[E.label[a]] || bad[E.label[b]]) && (E.label[a] != E.label[b] || pass == 0) &&
             (E.S.deformed.vertex(a) - E.S.deformed.vertex(b)).squaredNorm() > h2;
    });
    E.corner_vertex.resize(E.S.deformed.num_vertices(), 0);
    if (n == 0) break;
    compute_labels(E, nv0);
  }
}

/// Makes every cell's region connected on the support mesh. The diagram is Euclidean in M′ (a
/// restricted Voronoi diagram), so where M′ bends sharply (a ridge, a narrow boundary lobe near a
/// support) the points nearest to one seed can fall into several pieces of the surface; such a
/// cell is not a disk, and refining does not change it. Each label keeps its largest connected
/// piece (vertices joined by support edges with that label; area on M′); every other piece (an
/// orphan) goes to the neighbouring cell it shares most support edges with, counting edges to kept
/// pieces only when there are any. Repeated until no orphan is left (at most 8 rounds). Sequential,
/// so deterministic. Returns the vertices relabelled.
int merge_orphan_pieces(Engine& E) {
  const auto& F = E.S.deformed.F;
  auto& L = E.label;
  const int nv = E.S.deformed.num_vertices();
  const int nt = static_cast<int>(F.rows());
  const int ns = static_cast<int>(E.seeds.size());
  int relabelled = 0;
  std::vector<double> area(nv);
  for (int round = 0; round < 8; ++round) {
    DisjointSets pieces(nv);  // a piece's root is its smallest vertex
    const auto find = [&](int v) { return pieces.find(v); };
    for (int t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k) {
        const int a = F(t, k), b = F(t, (k + 1) % 3);
        if (L[a] == L[b]) pieces.unite(a, b);
      }
    // Each label keeps its largest piece (area on M′; a vertex carries a third of its
    // triangles): the piece nearest to a fixed boundary seed can be a sliver.
    std::fill(area.begin(), area.end(), 0.0);
    for (int t = 0; t < nt; ++t) {
      const double third = triangle_area(E.S.deformed.vertex(F(t, 0)), E.S.deformed.vertex(F(t, 1)),
                                         E.S.deformed.vertex(F(t, 2))) /
                           3;
      for (int k = 0; k < 3; ++k) area[find(F(t, k))] += third;
    }
    std::vector<int> keep(ns, -1);
    std::vector<double> best(ns, -1.0);
    for (int v = 0; v < nv; ++v)
      if (find(v) == v && area[v] > best[L[v]]) {
        best[L[v]] = area[v];
        keep[L[v]] = v;
      }
    auto kept = [&](int v) { return find(v) == keep[L[v]]; };
    // Orphan pieces and their shared edges with other cells: (root, label) → (kept, any).
    std::map<std::pair<int, int>, std::pair<int, int>> shared;
    bool any_orphan = false;
    for (int t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k) {
        const int a = F(t, k), b = F(t, (k + 1) % 3);
        if (L[a] == L[b]) continue;
        for (const auto& [o, n] : {std::pair{a, b}, std::pair{b, a}}) {
          if (kept(o)) continue;
          any_orphan = true;
          auto& c = shared[{find(o), L[n]}];
          c.first += kept(n) ? 1 : 0;
          c.second += 1;
        }
      }
    if (!any_orphan) {
      // An orphan piece with no border (a whole component of the surface) has nowhere to go.
      break;
    }
    std::unordered_map<int, std::pair<std::pair<int, int>, int>> target;  // root → (score, label)
    for (const auto& [key, c] : shared) {
      const auto [root, l] = key;
      auto it = target.find(root);
      if (it == target.end() || c > it->second.first) target[root] = {c, l};
    }
    for (int v = 0; v < nv; ++v) {
      if (kept(v)) continue;
      const auto it = target.find(find(v));
      if (it == target.end()) continue;
      L[v] = it->second.second;
      ++relabelled;
    }
  }
  return relabelled;
}

// ---------------------------------------------------------------------------------------------
// One extraction attempt: nodes, borders, faces

/// A directed output edge with the cell on its left.
struct DirEdge {
  int from, to, cell;
};

/// The state of one extraction attempt (`extract`), filled step by step.
struct Tracer {
  const Engine& E;
  const Triangles& F;
  const std::vector<int>& L;  ///< labels of the support vertices
  Extraction X;
  std::unordered_map<int, int> tri_node;   ///< 3-label triangle → its Voronoi vertex
  std::unordered_map<int, int> edge_node;  ///< half-edge id 3t+k of a boundary edge → its node
  std::vector<DirEdge> dedges;             ///< output edges, each cell's walked around it

  /// Whether local edge k of triangle t joins two labels.
  bool mixed(int t, int k) const { return L[F(t, k)] != L[F(t, (k + 1) % 3)]; }
  /// Distinct labels at the corners of triangle t: 1, 2 or 3.
  int nlabels(int t) const {
    const int a = L[F(t, 0)], b = L[F(t, 1)], c = L[F(t, 2)];
    return (a == b && b == c) ? 1 : (a != b && b != c && a != c) ? 3 : 2;
  }
  int add_node(const Node& n) {
    X.nodes.push_back(n);
    return static_cast<int>(X.nodes.size()) - 1;
  }
};

/// Voronoi vertices: in every triangle with three labels, the point of its plane equidistant
/// from the three seeds (clamped into the triangle).
void add_voronoi_vertices(Tracer& tr) {
  const Engine& E = tr.E;
  const auto& F = tr.F;
  const auto& L = tr.L;
  const int nt = static_cast<int>(F.rows());
  for (int t = 0; t < nt; ++t) {
    if (tr.nlabels(t) != 3) continue;
    const Vec3 a = E.S.deformed.vertex(F(t, 0)), e1 = E.S.deformed.vertex(F(t, 1)) - a,
               e2 = E.S.deformed.vertex(F(t, 2)) - a;
    const Vec3 si = E.seeds[L[F(t, 0)]].pos, sj = E.seeds[L[F(t, 1)]].pos,
               sk = E.seeds[L[F(t, 2)]].pos;
    Eigen::Matrix2d A;
    Eigen::Vector2d rhs;
    const Vec3 dj = sj - si, dk = sk - si;
    A << 2 * e1.dot(dj), 2 * e2.dot(dj), 2 * e1.dot(dk), 2 * e2.dot(dk);
    rhs << sj.squaredNorm() - si.squaredNorm() - 2 * a.dot(dj),
        sk.squaredNorm() - si.squaredNorm() - 2 * a.dot(dk);
    Vec3 b(1.0 / 3, 1.0 / 3, 1.0 / 3);
    const double det = A.determinant();
    if (std::abs(det) > 1e-300) {
      const Eigen::Vector2d x = A.partialPivLu().solve(rhs);
      if (x.allFinite()) b = clamp_bary(Vec3(1 - x(0) - x(1), x(0), x(1)));
    }
    Node n;
    n.tri = t;
    n.bary = b;
    n.kind = 0;
    tr.tri_node[t] = tr.add_node(n);
  }
}

/// The nodes along one boundary loop, in loop order.
struct LoopNodes {
  std::vector<std::pair<int, int>> seq;  ///< (node, label after it)
  std::vector<double> seq_arc;           ///< arc length on M of each node along the loop
  std::vector<double> arc;               ///< arc length on M at each loop vertex (and the total)
};

/// Corners and the points where cell borders meet boundary loop l (exactly equidistant from
/// the two seeds on the boundary edge).
LoopNodes add_boundary_nodes(Tracer& tr, std::size_t l) {
  const Engine& E = tr.E;
  const auto& F = tr.F;
  const auto& L = tr.L;
  const auto& loop = E.adj.boundary_loops[l];
  const auto& edges = E.adj.boundary_loop_edges[l];
  LoopNodes ln;
  const int nl = static_cast<int>(loop.size());
  ln.arc.assign(nl + 1, 0.0);
  for (int k = 0; k < nl; ++k)
    ln.arc[k + 1] =
        ln.arc[k] + (E.S.rest.vertex(loop[(k + 1) % nl]) - E.S.rest.vertex(loop[k])).norm();
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const int v = loop[k];
    if (E.corner_vertex[v]) {
      const int t = edges[k][0], le = edges[k][1];
      Node n;
      n.tri = t;
      n.bary.setZero();
      n.bary(le) = 1;
      n.kind = 2;
      n.u = v;
      ln.seq.emplace_back(static_cast<int>(tr.X.nodes.size()), L[v]);
      ln.seq_arc.push_back(ln.arc[k]);
      tr.add_node(n);
    }
    const int t = edges[k][0], le = edges[k][1];
    if (tr.mixed(t, le)) {
      const int u = F(t, le), w = F(t, (le + 1) % 3);
      const Vec3 pu = E.S.deformed.vertex(u), pw = E.S.deformed.vertex(w);
      const Vec3 si = E.seeds[L[u]].pos, sj = E.seeds[L[w]].pos;
      const Vec3 d = sj - si;
      const double den = 2 * (pw - pu).dot(d);
      double s = 0.5;
      if (std::abs(den) > 1e-300) {
        s = (sj.squaredNorm() - si.squaredNorm() - 2 * pu.dot(d)) / den;
        if (!std::isfinite(s)) s = 0.5;
      }
      s = std::clamp(s, 0.0, 1.0);
      Node n;
      n.tri = t;
      n.bary.setZero();
      n.bary(le) = 1 - s;
      n.bary((le + 1) % 3) = s;
      n.kind = 1;
      n.u = u;
      n.v = w;
      tr.edge_node[3 * t + le] = static_cast<int>(tr.X.nodes.size());
      ln.seq.emplace_back(static_cast<int>(tr.X.nodes.size()), L[w]);
      ln.seq_arc.push_back(ln.arc[k] + s * (ln.arc[k + 1] - ln.arc[k]));
      tr.add_node(n);
    }
  }
  return ln;
}

/// The output's boundary edges along loop l, from node to node of `ln`. Long ones are divided
/// along the input boundary into pieces of about boundary_split·R (joints of valence 2 on the
/// edge beam).
void add_boundary_edges(Tracer& tr, std::size_t l, const LoopNodes& ln) {
  const Engine& E = tr.E;
  const auto& F = tr.F;
  const auto& edges = E.adj.boundary_loop_edges[l];
  const auto& seq = ln.seq;
  const auto& arc = ln.arc;
  const int nl = static_cast<int>(arc.size()) - 1;
  for (std::size_t m = 0; m < seq.size(); ++m) {
    const std::size_t m1 = (m + 1) % seq.size();
    int from = seq[m].first;
    if (E.boundary_split > 0) {
      const double a0 = ln.seq_arc[m];
      double a1 = ln.seq_arc[m1];
      if (a1 <= a0) a1 += arc[nl];
      const Node& na = tr.X.nodes[seq[m].first];
      const Node& nb = tr.X.nodes[seq[m1].first];
      const double chord = (E.rest_point(na.tri, na.bary) - E.rest_point(nb.tri, nb.bary)).norm();
      const int pieces = static_cast<int>(std::lround(chord / (E.boundary_split * E.R)));
      for (int q = 1; q < pieces; ++q) {
        double a = a0 + (a1 - a0) * q / pieces;
        if (a >= arc[nl]) a -= arc[nl];
        int k = static_cast<int>(std::upper_bound(arc.begin(), arc.end(), a) - arc.begin()) - 1;
        k = std::clamp(k, 0, nl - 1);
        const double len = arc[k + 1] - arc[k];
        const double u = len > 0 ? std::clamp((a - arc[k]) / len, 0.0, 1.0) : 0.0;
        Node n;
        n.tri = edges[k][0];
        const int le = edges[k][1];
        n.bary.setZero();
        n.bary(le) = 1 - u;
        n.bary((le + 1) % 3) = u;
        n.kind = 1;
        n.u = F(n.tri, le);
        n.v = F(n.tri, (le + 1) % 3);
        const int id = tr.add_node(n);
        tr.dedges.push_back({from, id, seq[m].second});
        from = id;
      }
    }
    tr.dedges.push_back({from, seq[m1].first, seq[m].second});
  }
}

/// Traces every border between two cells from node to node (a Voronoi vertex or a boundary
/// node) through the triangles it crosses, and adds it as two directed edges. Sets X.problem
/// when a border cannot be traced, closes on itself, or encloses a cell.
void trace_borders(Tracer& tr) {
  const Engine& E = tr.E;
  const auto& F = tr.F;
  const auto& L = tr.L;
  Extraction& X = tr.X;
  const int nt = static_cast<int>(F.rows());
  std::vector<char> visited(static_cast<std::size_t>(nt) * 3, 0);
  auto mark = [&](int t, int k) {
    visited[3 * t + k] = 1;
    const int u = E.adj.neighbor[t][k];
    if (u >= 0) visited[3 * u + E.adj.neighbor_edge[t][k]] = 1;
  };
  auto fail = [&](const std::string& what, std::initializer_list<int> labels) {
    X.problem = what;
    X.bad_labels.insert(X.bad_labels.end(), labels.begin(), labels.end());
  };
  // Walks from "inside triangle t, entered through local edge k" to the end node.
  auto walk = [&](int t, int k) -> int {
    for (int steps = 0; steps <= 3 * nt; ++steps) {
      if (tr.nlabels(t) == 3) return tr.tri_node.at(t);
      int k2 = -1;
      for (int q = 0; q < 3; ++q)
        if (q != k && tr.mixed(t, q)) k2 = q;
      if (k2 < 0) return -1;
      mark(t, k2);
      const int u = E.adj.neighbor[t][k2];
      if (u < 0) return tr.edge_node.at(3 * t + k2);
      k = E.adj.neighbor_edge[t][k2];
      t = u;
    }
    return -1;
  };
  auto add_chain = [&](int n0, int n1, int left, int right) {
    if (n1 < 0) {
      fail("a cell border could not be traced", {left, right});
      return;
    }
    if (n0 == n1) {
      fail("a cell border closes on itself", {left, right});
      return;
    }
    tr.dedges.push_back({n0, n1, left});
    tr.dedges.push_back({n1, n0, right});
  };
  for (int t = 0; t < nt && X.problem.empty(); ++t) {
    if (tr.nlabels(t) != 3) continue;
    const int n0 = tr.tri_node.at(t);
    for (int k = 0; k < 3; ++k) {
      if (visited[3 * t + k]) continue;
      const int u = F(t, k), w = F(t, (k + 1) % 3);
      mark(t, k);
      const int nb = E.adj.neighbor[t][k];
      const int n1 = nb < 0 ? tr.edge_node.at(3 * t + k) : walk(nb, E.adj.neighbor_edge[t][k]);
      add_chain(n0, n1, L[w], L[u]);
    }
  }
  for (const auto& [h, n0] : tr.edge_node) {
    if (!X.problem.empty()) break;
    const int t = h / 3, k = h % 3;
    if (visited[h]) continue;
    mark(t, k);
    add_chain(n0, walk(t, k), L[F(t, k)], L[F(t, (k + 1) % 3)]);
  }
  if (!X.problem.empty()) return;
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      if (tr.mixed(t, k) && !visited[3 * t + k]) {
        fail("a cell is enclosed by another one (closed border)",
             {L[F(t, k)], L[F(t, (k + 1) % 3)]});
        return;
      }
}

/// Each cell's directed edges must form exactly one cycle: its face. Sets X.ok, or X.problem.
void assemble_faces(Tracer& tr) {
  Extraction& X = tr.X;
  auto& dedges = tr.dedges;
  std::sort(dedges.begin(), dedges.end(), [](const DirEdge& a, const DirEdge& b) {
    return a.cell != b.cell ? a.cell < b.cell : a.from < b.from;
  });
  X.faces.assign(tr.E.seeds.size(), {});
  for (std::size_t i = 0; i < dedges.size();) {
    std::size_t j = i;
    while (j < dedges.size() && dedges[j].cell == dedges[i].cell) ++j;
    const int cell = dedges[i].cell;
    std::unordered_map<int, int> next;
    bool ok = true;
    for (std::size_t q = i; q < j; ++q)
      if (!next.emplace(dedges[q].from, dedges[q].to).second) ok = false;
    std::vector<int> face;
    if (ok) {
      int cur = dedges[i].from;
      for (std::size_t q = i; q < j; ++q) {
        face.push_back(cur);
        auto it = next.find(cur);
        if (it == next.end()) {
          ok = false;
          break;
        }
        cur = it->second;
      }
      if (ok && (cur != dedges[i].from || face.size() < 3)) ok = false;
    }
    if (!ok) {
      X.problem = "a cell is not a disk";
      X.bad_labels.push_back(cell);
      return;
    }
    X.faces[cell] = std::move(face);
    i = j;
  }
  X.ok = true;
}

/// One extraction attempt on the current labels: nodes, boundary edges, traced borders, faces.
Extraction extract(const Engine& E) {
  Tracer tr{E, E.S.deformed.F, E.label, {}, {}, {}, {}};
  add_voronoi_vertices(tr);
  for (std::size_t l = 0; l < E.adj.boundary_loops.size(); ++l) {
    const LoopNodes ln = add_boundary_nodes(tr, l);
    if (ln.seq.size() < 3) {
      tr.X.problem = "a boundary loop meets fewer than 3 cell borders";
      tr.X.bad_labels.push_back(tr.L[E.adj.boundary_loops[l][0]]);
      for (const auto& q : ln.seq) tr.X.bad_labels.push_back(q.second);
      return std::move(tr.X);
    }
    add_boundary_edges(tr, l, ln);
  }
  trace_borders(tr);
  if (!tr.X.problem.empty()) return std::move(tr.X);
  assemble_faces(tr);
  return std::move(tr.X);
}

// ---------------------------------------------------------------------------------------------
// From an extraction to the output

/// The polygon mesh of a successful extraction on M: stubs at the boundary collapsed, unused
/// nodes dropped (X.nodes and X.faces renumbered), seedless cells left out (`face_seed`: the
/// seed of each face). Checks that it is a manifold with the input's topology; if not, clears
/// X.ok and says why in X.problem.
PolyMesh build_mesh(const Engine& E, const Input& in, const TessellationOptions& o, Extraction& X,
                    std::vector<int>& face_seed, TessellationQuality& q) {
  if (o.stub_length > 0) {
    // Every output edge shorter than stub_length·R that ends on the boundary (a Voronoi vertex
    // just inside it, two boundary joints side by side) is collapsed into its boundary end (a
    // corner when there is one); faces keep ≥ 3 corners.
    std::vector<Vec3> pos(X.nodes.size());
    std::vector<int> rank(X.nodes.size());
    for (std::size_t n = 0; n < X.nodes.size(); ++n) {
      pos[n] = E.rest_point(X.nodes[n].tri, X.nodes[n].bary);
      rank[n] = X.nodes[n].kind;  // Voronoi vertex, boundary joint, corner
    }
    collapse_boundary_stubs(X.faces, pos, rank, o.stub_length * E.R);
  }
  // Keep the nodes that faces use, in order.
  std::vector<int> id(X.nodes.size(), -1);
  for (const auto& f : X.faces)
    for (int v : f) id[v] = 0;
  std::vector<Node> used;
  for (std::size_t n = 0; n < X.nodes.size(); ++n)
    if (id[n] >= 0) {
      id[n] = static_cast<int>(used.size());
      used.push_back(X.nodes[n]);
    }
  X.nodes = std::move(used);
  for (auto& f : X.faces)
    for (int& v : f) v = id[v];
  PolyMesh poly;
  poly.V.resize(static_cast<int>(X.nodes.size()), 3);
  for (std::size_t n = 0; n < X.nodes.size(); ++n)
    poly.V.row(static_cast<int>(n)) = E.rest_point(X.nodes[n].tri, X.nodes[n].bary).transpose();
  for (std::size_t i = 0; i < X.faces.size(); ++i)
    if (!X.faces[i].empty()) {
      poly.faces.push_back(X.faces[i]);
      face_seed.push_back(static_cast<int>(i));
    }
  q = measure_quality(poly);
  if (!q.manifold) {
    X.ok = false;
    X.problem = "the extracted mesh is not a valid manifold";
  } else if (q.euler != in.euler ||
             q.boundary_loops != static_cast<int>(in.boundary_loops.size())) {
    X.ok = false;
    X.problem = "the extracted mesh changed the topology of the surface";
  }
  return poly;
}

/// Per output vertex of T.mesh: boundary and corner flags, position on the original M, and the
/// supports (see `tessellate` in tessellation.h for the rule).
void set_vertex_data(const Engine& E, const Extraction& X, const Input& in, Tessellation& T) {
  const TriMesh& rest = in.rest;
  const auto& supported = in.supported;
  const int nn = T.mesh.num_vertices();
  T.on_boundary.assign(nn, 0);
  T.corner.assign(nn, 0);
  T.vertex_triangle.assign(nn, 0);
  T.vertex_bary.assign(nn, Vec3(1, 0, 0));
  std::vector<char> sup(nn, 0);
  for (int n = 0; n < nn; ++n) {
    const Node& nd = X.nodes[n];
    const auto [ot, ob] = to_original(E.S, nd.tri, nd.bary);
    T.vertex_triangle[n] = ot;
    T.vertex_bary[n] = ob;
    if (nd.kind == 2) {
      T.on_boundary[n] = 1;
      T.corner[n] = 1;
      sup[n] = supported[nd.u];
    } else if (nd.kind == 1) {
      T.on_boundary[n] = 1;
      // The original edge this support edge lies on.
      const auto ou = E.S.origin[nd.u], ow = E.S.origin[nd.v];
      int ids[4] = {ou[0], ou[1], ow[0], ow[1]};
      std::sort(ids, ids + 4);
      const int k = static_cast<int>(std::unique(ids, ids + 4) - ids);
      if (k == 2 && ids[0] >= 0) {
        const int a = ids[0], b = ids[1];
        const Vec3 pa = rest.vertex(a), pb = rest.vertex(b), p = T.mesh.vertex(n);
        const double s = (p - pa).dot(pb - pa) / std::max((pb - pa).squaredNorm(), 1e-300);
        // both ends supported, or the node lies in the supported end's half of the edge
        if ((supported[a] && supported[b]) || (supported[a] && s <= 0.5) ||
            (supported[b] && s >= 0.5))
          sup[n] = 1;
      }
    }
  }
  // Supported input vertices that the rule above cannot see: interior ones, and isolated
  // supported boundary vertices; their nearest output (boundary) vertex becomes a support.
  std::vector<int> prev(rest.num_vertices(), -1), nextv(rest.num_vertices(), -1);
  for (const auto& loop : in.boundary_loops)
    for (std::size_t k = 0; k < loop.size(); ++k) {
      nextv[loop[k]] = loop[(k + 1) % loop.size()];
      prev[loop[(k + 1) % loop.size()]] = loop[k];
    }
  for (int v = 0; v < rest.num_vertices(); ++v) {
    if (!supported[v]) continue;
    const bool on_b = nextv[v] >= 0;
    if (on_b && (supported[nextv[v]] || supported[prev[v]])) continue;
    int best = -1;
    double bd = std::numeric_limits<double>::infinity();
    for (int n = 0; n < nn; ++n) {
      if (on_b && !T.on_boundary[n]) continue;
      const double d = (T.mesh.vertex(n) - rest.vertex(v)).squaredNorm();
      if (d < bd) {
        bd = d;
        best = n;
      }
    }
    if (best >= 0) sup[best] = 1;
  }
  for (int n = 0; n < nn; ++n)
    if (sup[n]) T.supports.push_back(n);
}

}  // namespace

void extract_cells(Engine& E, const Input& in, const TessellationOptions& o, Tessellation& T) {
  const auto t_extract = Clock::now();
  // Seeds on M (before the mesh is refined further for extraction).
  std::vector<Vec3> seed_rest(E.seeds.size());
  for (std::size_t i = 0; i < E.seeds.size(); ++i)
    seed_rest[i] = E.rest_point(E.seeds[i].tri, E.seeds[i].bary);
  // Refine across borders, then extract; repair by refining around bad cells.
  refine_for_extraction(E, o, t_extract);
  double hr = o.extraction_edge * E.R;
  for (int attempt = 0;; ++attempt) {
    E.adj = build_triangle_adjacency(E.S.deformed.F, E.S.deformed.num_vertices());
    // Detached pieces of a cell's region (M′ bending back within a cell size) would make it
    // a non-disk that no refinement repairs: they join a neighbouring cell first.
    const int orphans = merge_orphan_pieces(E);
    if (orphans > 0)
      spdlog::debug("extraction: {} support vertices moved from detached cell pieces", orphans);
    Extraction X = extract(E);
    spdlog::debug("extract attempt {}: {} ({:.2f} s)", attempt, X.ok ? "ok" : X.problem,
                  seconds_since(t_extract));
    if (X.ok) {
      std::vector<int> face_seed;
      TessellationQuality q;
      PolyMesh poly = build_mesh(E, in, o, X, face_seed, q);
      if (X.ok) {
        T.mesh = std::move(poly);
        T.quality = q;
        set_vertex_data(E, X, in, T);
        for (int f : face_seed) T.seeds.push_back(seed_rest[f]);
        T.repairs = attempt;
        T.orphan_vertices = orphans;
        T.seconds_extraction = seconds_since(t_extract);
        return;
      }
    }
    if (attempt >= 4)
      throw ExtractionError("tessellation", "could not extract a valid polygon mesh (" + X.problem +
                                                "); try another --seed or size");
    spdlog::info("tessellation: repairing ({}), refining the support mesh", X.problem);
    hr *= 0.5;
    refine_around_bad_cells(E, X, hr);
  }
}

}  // namespace gridshell::voronoi
