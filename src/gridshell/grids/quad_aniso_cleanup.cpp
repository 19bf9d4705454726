#include "gridshell/grids/quad_aniso_internal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <utility>
#include <vector>

#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/overlaps.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/projector.h"

namespace gridshell::quad_aniso_internal {

namespace {

/// Whether a face of the grid spans a hole (or a notch) of M: at least a third of the sample
/// points inside it (its centroid, and the points halfway from it to each corner and to each
/// side's middle) lie over the void — closer to M's boundary than to any interior point of M,
/// and off M by more than 2 % of the face's mean side. The extraction walks faces around M′'s
/// holes like any other loop of beams; a hole smaller than a few cells would otherwise get a
/// panel over it. (A face along a boundary that curves into M has the void only between its
/// side and the boundary, outside the samples.)
bool spans_void(const std::vector<Vec3>& p, const std::vector<int>& face,
                const SurfaceProjector& proj) {
  if (!proj.has_boundary()) return false;
  const size_t n = face.size();
  Vec3 c = Vec3::Zero();
  double side = 0;
  for (size_t k = 0; k < n; ++k) {
    c += p[face[k]];
    side += (p[face[k]] - p[face[(k + 1) % n]]).norm();
  }
  c /= static_cast<double>(n);
  side /= static_cast<double>(n);
  std::vector<Vec3> samples{c};
  for (size_t k = 0; k < n; ++k) {
    samples.push_back(0.5 * (c + p[face[k]]));
    samples.push_back(0.5 * c + 0.25 * (p[face[k]] + p[face[(k + 1) % n]]));
  }
  int void_samples = 0;
  for (const Vec3& x : samples) {
    const double to_surface = (proj.closest_point(x) - x).norm();
    if (to_surface > 0.02 * side &&
        (proj.closest_boundary_point(x) - x).norm() <= to_surface + 1e-9 * proj.diagonal())
      ++void_samples;
  }
  return 3 * void_samples >= static_cast<int>(samples.size());
}

/// The same for face `face` of `g`.
bool spans_void(const PolyMesh& g, const std::vector<int>& face, const SurfaceProjector& proj) {
  std::vector<Vec3> corners;
  for (int v : face) corners.push_back(g.vertex(v));
  std::vector<int> local(face.size());
  std::iota(local.begin(), local.end(), 0);
  return spans_void(corners, local, proj);
}

/// The area of each face of `g`, and their median (0 without faces).
std::vector<double> face_areas(const PolyMesh& g) {
  std::vector<double> areas;
  for (int f = 0; f < g.num_faces(); ++f) areas.push_back(polygon_area(g, f));
  return areas;
}

double median_area(std::vector<double> areas) {
  if (areas.empty()) return 0;
  std::nth_element(areas.begin(), areas.begin() + areas.size() / 2, areas.end());
  return areas[areas.size() / 2];
}

/// The point of segment [a, b] nearest x, as the parameter along it (0 at a, 1 at b).
double segment_parameter(const Vec3& x, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double l2 = d.squaredNorm();
  return l2 > 0 ? std::clamp((x - a).dot(d) / l2, 0.0, 1.0) : 0.0;
}

/// Douglas–Peucker: the points of the polyline `path` (ends excluded) that stay when it is
/// simplified to within `tolerance`, in order.
void simplify_path(const std::vector<Vec3>& path, int first, int last, double tolerance,
                   std::vector<int>& kept) {
  if (last - first < 2) return;
  int worst = -1;
  double worst_d = tolerance;
  for (int i = first + 1; i < last; ++i) {
    const double t = segment_parameter(path[i], path[first], path[last]);
    const double d = (path[i] - (path[first] + t * (path[last] - path[first]))).norm();
    if (d > worst_d) worst_d = d, worst = i;
  }
  if (worst < 0) return;
  simplify_path(path, first, worst, tolerance, kept);
  kept.push_back(worst);
  simplify_path(path, worst, last, tolerance, kept);
}

/// Gaps between the grid's boundary and M's: where the grid's boundary runs from a joint on M's
/// boundary (s0) through at most `max_inner` joints off it to the next joint on M's boundary
/// (s1) while M's boundary between them (s0 to s1 in the same sense) bends away from the
/// grid's — a corner of M cut off by one beam, or a notch of a few cells where the lattice's
/// seam meets the boundary — the gap becomes a face: M's boundary from s0 to s1, simplified to
/// within a quarter of the gap's chord (Douglas–Peucker; its corners become joints), then the
/// grid's boundary back. Gaps whose face would have more than `max_sides` sides, would not be a
/// simple polygon or would lie over the void are left open.
void fill_boundary_gaps(PolyMesh& g, const Points& mv, const std::vector<std::vector<int>>& m_loops,
                        int max_inner, int max_sides, const SurfaceProjector& proj) {
  struct Spot {
    int loop = -1, edge = 0;
    double t = 0, distance = std::numeric_limits<double>::infinity();
  };
  auto locate = [&](const Vec3& x) {
    Spot best;
    for (int l = 0; l < static_cast<int>(m_loops.size()); ++l) {
      const auto& loop = m_loops[l];
      for (int e = 0; e < static_cast<int>(loop.size()); ++e) {
        const Vec3 a = mv.row(loop[e]).transpose();
        const Vec3 b = mv.row(loop[(e + 1) % loop.size()]).transpose();
        const double t = segment_parameter(x, a, b);
        const double d = (x - (a + t * (b - a))).norm();
        if (d < best.distance) best = {l, e, t, d};
      }
    }
    return best;
  };
  const double tol = 1e-6 * proj.diagonal();
  const Topology topo = build_topology(g);
  double mean_beam = 0;
  for (const auto& e : topo.edges) mean_beam += (g.vertex(e[0]) - g.vertex(e[1])).norm();
  mean_beam /= std::max(1, topo.num_edges());
  // A gap is a corner or a notch, about a cell: a face of more than twice the median face's
  // area would be a panel across a region the extraction left empty (a trapezoid's end, 40 % of
  // its roof, in one pentagon), not a gap.
  const double max_area = 2 * median_area(face_areas(g));
  std::vector<char> on_m_boundary(g.num_vertices(), 0);
  for (const auto& loop : topo.boundary_loops)
    for (int v : loop) on_m_boundary[v] = locate(g.vertex(v)).distance <= tol;
  for (const auto& loop : topo.boundary_loops) {
    const int n = static_cast<int>(loop.size());
    for (int i = 0; i < n; ++i) {
      if (!on_m_boundary[loop[i]]) continue;
      int j = (i + 1) % n, inner = 0;
      while (!on_m_boundary[loop[j]] && j != i) j = (j + 1) % n, ++inner;
      if (j == i || inner > max_inner) continue;
      bool regular = true;  // the joints off M's boundary become interior: valence 4 only
      for (int k = (i + 1) % n; k != j; k = (k + 1) % n)
        regular = regular && topo.vertex_neighbors[loop[k]].size() == 4;
      if (!regular) continue;
      const int s0 = loop[i], s1 = loop[j];
      const Spot a = locate(g.vertex(s0)), b = locate(g.vertex(s1));
      if (a.loop < 0 || a.loop != b.loop || a.distance > tol || b.distance > tol) continue;
      // M's boundary from s0 to s1, forward (M and the grid are oriented alike).
      const auto& ml = m_loops[a.loop];
      const int mn = static_cast<int>(ml.size());
      std::vector<Vec3> path{g.vertex(s0)};
      if (!(a.edge == b.edge && b.t >= a.t)) {
        for (int e = (a.edge + 1) % mn, steps = 0; steps < mn; e = (e + 1) % mn, ++steps) {
          path.push_back(mv.row(ml[e]).transpose());
          if (e == b.edge) break;
        }
      }
      path.push_back(g.vertex(s1));
      double m_length = 0, grid_length = 0;
      for (size_t k = 1; k < path.size(); ++k) m_length += (path[k] - path[k - 1]).norm();
      for (int k = i; k != j; k = (k + 1) % n)
        grid_length += (g.vertex(loop[(k + 1) % n]) - g.vertex(loop[k])).norm();
      if (m_length > 4 * grid_length) continue;  // the long way round: not this gap
      const double chord = (g.vertex(s1) - g.vertex(s0)).norm();
      std::vector<int> kept;  // new beams are at least a quarter of the mean beam long
      simplify_path(path, 0, static_cast<int>(path.size()) - 1, 0.25 * std::max(chord, mean_beam),
                    kept);
      if (inner == 0 && kept.empty()) continue;  // a beam along M's boundary
      const int sides = 2 + inner + static_cast<int>(kept.size());
      if (sides > max_sides || (kept.empty() && chord < 0.25 * mean_beam)) continue;
      const int first_new = g.num_vertices();
      std::vector<int> face{s0};
      g.V.conservativeResize(first_new + static_cast<int>(kept.size()), 3);
      for (size_t k = 0; k < kept.size(); ++k) {
        g.V.row(first_new + static_cast<int>(k)) = path[kept[k]].transpose();
        face.push_back(first_new + static_cast<int>(k));
      }
      face.push_back(s1);
      for (int k = (j - 1 + n) % n; k != i; k = (k - 1 + n) % n) face.push_back(loop[k]);
      g.faces.push_back(face);
      const double area = polygon_area(g, g.num_faces() - 1);
      g.faces.pop_back();
      if (area > max_area || !is_simple_polygon(g, face) || spans_void(g, face, proj)) {
        g.V.conservativeResize(first_new, 3);
        continue;
      }
      g.faces.push_back(std::move(face));
    }
  }
}

/// Faces that cover part of the roof twice (mesh/overlaps.h: beams that cross, a joint inside a
/// panel not its own) are left out, one overlap at a time: of the two sides of an overlap — the
/// faces on either crossing beam, or the panel over a joint — the side of the thinner faces
/// (lower mean 4π·area / perimeter²) goes. Folds come from a walk that went round the wrong way
/// where M′ is crushed, or from joints snapped onto M's boundary past their neighbours; the face
/// walked across cells is the long thin one over the others. A grid with two panels one over
/// the other, or two beams through one point without a joint, cannot be built: the hole left is
/// the lesser defect. Each round leaves out at least one face, so this ends.
void remove_overlaps(PolyMesh& g) {
  while (g.num_faces() > 0) {
    const Topology topo = build_topology(g);
    const Overlaps ov = find_overlaps(g, topo);
    if (ov.count() == 0) return;
    auto compactness = [&](int f) {
      const auto& poly = g.faces[f];
      double perimeter = 0;
      for (size_t k = 0; k < poly.size(); ++k)
        perimeter += (g.vertex(poly[k]) - g.vertex(poly[(k + 1) % poly.size()])).norm();
      return perimeter > 0 ? 4 * std::numbers::pi * polygon_area(g, f) / (perimeter * perimeter)
                           : 0.0;
    };
    auto mean_compactness = [&](const std::vector<int>& faces) {
      double sum = 0;
      for (int f : faces) sum += compactness(f);
      return faces.empty() ? std::numeric_limits<double>::infinity() : sum / faces.size();
    };
    std::vector<int> drop;
    double worst = std::numeric_limits<double>::infinity();
    auto propose = [&](const std::vector<int>& faces) {
      const double c = mean_compactness(faces);
      if (drop.empty() || c < worst) worst = c, drop = faces;
    };
    for (const auto& [e1, e2] : ov.crossing_edges) {
      const std::vector<int> side1 = topo.edge_faces[e1], side2 = topo.edge_faces[e2];
      propose(mean_compactness(side1) <= mean_compactness(side2) ? side1 : side2);
    }
    for (const auto& [v, f] : ov.covered_vertices) propose({f});
    std::sort(drop.begin(), drop.end());
    drop.erase(std::unique(drop.begin(), drop.end()), drop.end());
    for (auto it = drop.rbegin(); it != drop.rend(); ++it) g.faces.erase(g.faces.begin() + *it);
  }
}

/// A row of cells that ends inside the grid leaves an odd face there (a triangle, a pentagon) with
/// no odd partner inside: its partner is across the rim, where the boundary cut the lattice. On
/// the final grid (on M), odd faces are paired with odd faces of the rim (faces with a joint on
/// the boundary) by `pair_odd_faces`, so the defect moves to the rim.
void pair_with_rim(PolyMesh& g) {
  const Topology topo = build_topology(g);
  const int nv = g.num_vertices(), nf = g.num_faces();
  std::vector<Vec3> p(nv), normal(nv, Vec3::Zero());
  for (int v = 0; v < nv; ++v) p[v] = g.vertex(v);
  std::vector<char> on_rim(nf, 0);
  for (int f = 0; f < nf; ++f) {
    const Vec3 area = vector_area(g, f);
    for (int v : g.faces[f]) normal[v] += area, on_rim[f] |= topo.on_boundary[v];
  }
  for (Vec3& n : normal)
    if (n.norm() > 0) n.normalize();
  pair_odd_faces(g.faces, p, normal, 0, 2, on_rim);
}

/// Leaves out the faces of less than `fraction` of the median face area: slivers where the
/// joints of a boundary cell were all snapped onto a straight piece of M's boundary, or a gap
/// between the grid's boundary and M's was filled by a face of almost no area (without this step
/// 16 of 198 grids of the stats tables had one, Botanic (3, 3) at 2018 m among them). A panel of a
/// fiftieth of the others' area, or of none, is nothing anyone would cut glass for. Vertices are
/// not touched (largest_component drops the unused ones).
void drop_slivers(PolyMesh& g, double fraction) {
  const std::vector<double> areas = face_areas(g);
  const double limit = fraction * median_area(areas);
  std::vector<std::vector<int>> kept;
  for (int f = 0; f < g.num_faces(); ++f)
    if (areas[f] >= limit) kept.push_back(std::move(g.faces[f]));
  g.faces = std::move(kept);
}

/// Moves the grid's outer-boundary joints near M's boundary onto it, collapses the stubs this
/// makes, and drops unused joints, faces that are not simple polygons and faces over M's holes.
PolyMesh snap_to_boundary(const PolyMesh& mesh, const SurfaceProjector& proj, double snap) {
  const Topology topo = build_topology(mesh);
  std::vector<Vec3> p(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) p[v] = mesh.vertex(v);
  std::vector<int> rank(mesh.num_vertices(), 0);
  std::vector<double> lengths;
  for (const auto& e : topo.edges) lengths.push_back((p[e[0]] - p[e[1]]).norm());
  for (const auto& loop : topo.boundary_loops) {
    for (int v : loop) {
      double mean = 0;
      for (int u : topo.vertex_neighbors[v]) mean += (p[u] - p[v]).norm();
      mean /= std::max<size_t>(1, topo.vertex_neighbors[v].size());
      const Vec3 b = proj.closest_boundary_point(mesh.vertex(v));
      if ((b - mesh.vertex(v)).norm() <= snap * mean) p[v] = b, rank[v] = 1;
    }
  }
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  const double median = lengths.empty() ? 0 : lengths[lengths.size() / 2];
  std::vector<std::vector<int>> faces = mesh.faces;
  collapse_boundary_stubs(faces, p, rank, 0.25 * median);
  // Beams still shorter than 0.15 × median (lattice points that nearly coincide): each collapsed
  // into its boundary end, or to its midpoint; a face left with < 3 corners disappears.
  for (int pass = 0; pass < 3; ++pass) {  // a collapse can leave another stub
    std::vector<std::pair<double, std::array<int, 2>>> stubs;
    for (const auto& f : faces)
      for (size_t k = 0; k < f.size(); ++k) {
        const int a = f[k], b = f[(k + 1) % f.size()];
        const double l = (p[a] - p[b]).norm();
        if (l < 0.15 * median) stubs.push_back({l, {std::min(a, b), std::max(a, b)}});
      }
    std::sort(stubs.begin(), stubs.end());
    std::vector<int> into(mesh.num_vertices());
    std::iota(into.begin(), into.end(), 0);
    std::vector<char> touched(mesh.num_vertices(), 0);
    for (const auto& [l, e] : stubs) {
      int a = e[0], b = e[1];
      if (touched[a] || touched[b]) continue;
      if (rank[b] > rank[a]) std::swap(a, b);
      if (rank[a] == rank[b]) p[a] = 0.5 * (p[a] + p[b]);
      into[b] = a;
      touched[a] = touched[b] = 1;
    }
    for (auto& f : faces) {
      std::vector<int> g;
      for (int v : f)
        if (g.empty() || g.back() != into[v]) g.push_back(into[v]);
      while (g.size() > 1 && g.front() == g.back()) g.pop_back();
      f = g.size() >= 3 ? g : std::vector<int>{};
    }
  }
  PolyMesh out;
  std::vector<int> index(mesh.num_vertices(), -1);
  int count = 0;
  PolyMesh moved{mesh.V, {}};
  for (int v = 0; v < mesh.num_vertices(); ++v) moved.V.row(v) = p[v].transpose();
  for (auto& f : faces) {
    if (f.size() < 3 || !is_simple_polygon(moved, f))
      continue;  // a fold at the seam of the lattice
    if (spans_void(p, f, proj)) continue;
    for (int& v : f) {
      if (index[v] < 0) index[v] = count++;
      v = index[v];
    }
    out.faces.push_back(f);
  }
  out.V.resize(count, 3);
  std::vector<char> on_surface_boundary(count, 0);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (index[v] >= 0) {
      out.V.row(index[v]) = p[v].transpose();
      on_surface_boundary[index[v]] = rank[v] > 0;
    }
  // Holes left by the faces that were not kept (more than max_face_sides sides, folded or not
  // simple): a hole away from M's boundary whose loop is a simple polygon of ≤ 12 sides becomes
  // a face again (its beams are there anyway; the panel carries its share of the load).
  const Topology t = build_topology(out);
  for (const auto& loop : t.boundary_loops) {
    if (loop.size() > 12) continue;
    bool inner = true;
    for (int v : loop) inner = inner && !on_surface_boundary[v];
    std::vector<int> face(loop.rbegin(), loop.rend());
    if (inner && is_simple_polygon(out, face) && !spans_void(out, face, proj))
      out.faces.push_back(std::move(face));
  }
  return out;
}

/// The grid's largest connected part, per piece of M when M has several (its joints assigned to
/// the piece of the triangle nearest them).
PolyMesh keep_largest(const PolyMesh& grid, const SurfacePieces& pieces,
                      const SurfaceProjector& proj) {
  if (!pieces.several) return largest_component(grid);
  std::vector<int> piece(grid.num_vertices());
  for (int v = 0; v < grid.num_vertices(); ++v) {
    int triangle = -1;
    proj.closest_point_walk(grid.vertex(v), triangle);
    piece[v] = pieces.of_triangle[triangle];
  }
  return largest_component(grid, piece);
}

}  // namespace

SurfacePieces surface_pieces(const TriMesh& mesh) {
  SurfacePieces pieces;
  pieces.of_triangle.assign(mesh.num_faces(), 0);
  DisjointSets sets(mesh.num_vertices());
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 1; k < 3; ++k) sets.unite(mesh.F(f, 0), mesh.F(f, k));
  for (int f = 0; f < mesh.num_faces(); ++f) {
    pieces.of_triangle[f] = sets.find(mesh.F(f, 0));
    pieces.several |= pieces.of_triangle[f] != pieces.of_triangle[0];
  }
  return pieces;
}

PolyMesh clean_up_on_surface(PolyMesh grid, const TriMesh& mesh, const SurfaceProjector& proj,
                             const SurfacePieces& pieces, const QuadAnisoOptions& o) {
  for (int v = 0; v < grid.num_vertices(); ++v)
    grid.V.row(v) = proj.closest_point(grid.vertex(v)).transpose();
  // Flaps and pieces the extraction left apart (a quad cut off by a hole) would be
  // mechanisms, or nearly, in the analysis.
  grid = snap_to_boundary(grid, proj, o.boundary_snap);
  drop_slivers(grid, o.min_face_area);
  remove_hanging_faces(grid);
  grid = keep_largest(grid, pieces, proj);
  fill_boundary_gaps(grid, mesh.V, proj.boundary_loops(), o.gap_joints, o.max_face_sides, proj);
  drop_slivers(grid, o.min_face_area);  // a gap filled by a face of almost no area
  grid = keep_largest(grid, pieces, proj);
  pair_with_rim(grid);
  remove_overlaps(grid);
  return keep_largest(grid, pieces, proj);
}

}  // namespace gridshell::quad_aniso_internal
