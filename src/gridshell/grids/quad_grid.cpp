#include "gridshell/grids/quad_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include <fmt/format.h>

#include "gridshell/core/error.h"
#include "gridshell/grids/plane_cut.h"
#include "gridshell/grids/regions.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

double total_edge_length(const PolyMesh& mesh) {
  Topology t = build_topology(mesh);
  double len = 0;
  for (const auto& e : t.edges) len += (mesh.vertex(e[0]) - mesh.vertex(e[1])).norm();
  return len;
}

namespace {

/// Beams shorter than `min_length` with an end on the boundary — a grid line crossing the
/// boundary just beside a sharp corner or beside another line's crossing — are collapsed into
/// their boundary end (mesh/topology.h); such stubs (down to 0.3 mm on Aquadom) make the frame's
/// stiffness ill-conditioned. `rank` per polygon vertex: 0 interior, 1 boundary, 2 corner.
/// Unused vertices are dropped.
void collapse_stubs_and_compact(RegionMesh& rm, const std::vector<int>& rank, double min_length) {
  PolyMesh& m = rm.mesh;
  std::vector<Vec3> pos(m.num_vertices());
  for (int v = 0; v < m.num_vertices(); ++v) pos[v] = m.vertex(v);
  gridshell::collapse_boundary_stubs(m.faces, pos, rank, min_length);
  std::vector<int> id(m.num_vertices(), -1);
  for (const auto& f : m.faces)
    for (int v : f) id[v] = 0;
  int n = 0;
  for (int v = 0; v < m.num_vertices(); ++v)
    if (id[v] == 0) {
      m.V.row(n) = m.V.row(v);
      rm.source_vertex[n] = rm.source_vertex[v];
      id[v] = n++;
    }
  m.V.conservativeResize(n, 3);
  rm.source_vertex.resize(n);
  for (auto& f : m.faces)
    for (int& v : f) v = id[v];
}

}  // namespace

GridShell quad_grid(const Surface& surface, const QuadGridOptions& o) {
  if (!(o.spacing > 0) || !std::isfinite(o.spacing))
    throw Error("quad grid", "spacing must be positive");
  const double diag = bbox_diagonal(surface.mesh.V);
  if (o.spacing < diag / 2000) throw Error("quad grid", "spacing too small for the surface");
  const Vec3 du(std::cos(o.angle), std::sin(o.angle), 0),
      dw(-std::sin(o.angle), std::cos(o.angle), 0);
  const Vec3 centre =
      0.5 * (surface.mesh.V.colwise().minCoeff() + surface.mesh.V.colwise().maxCoeff()).transpose();
  double umin = 1e300, umax = -1e300, wmin = 1e300, wmax = -1e300;
  for (int v = 0; v < surface.mesh.num_vertices(); ++v) {
    const Vec3 p = surface.mesh.vertex(v) - centre;
    umin = std::min(umin, p.dot(du)), umax = std::max(umax, p.dot(du));
    wmin = std::min(wmin, p.dot(dw)), wmax = std::max(wmax, p.dot(dw));
  }
  CutMesh cut = make_cut_mesh(surface);
  const double snap = 1e-10 * diag;
  const double h = o.spacing;
  // Lines at centre + (k + 1/2) h so that the centre lies in a cell middle.
  for (const auto& [dir, lo, hi] : {std::tuple{du, umin, umax}, std::tuple{dw, wmin, wmax}}) {
    for (int k = static_cast<int>(std::floor(lo / h - 0.5));
         k <= static_cast<int>(std::ceil(hi / h)); ++k) {
      const double offset = (k + 0.5) * h;
      if (offset <= lo || offset >= hi) continue;
      cut_along_plane(cut, Plane{centre + offset * dir, dir}, snap);
    }
  }
  std::vector<int> label(cut.mesh.num_faces());
  for (int f = 0; f < cut.mesh.num_faces(); ++f) {
    Vec3 c = Vec3::Zero();
    for (int k = 0; k < 3; ++k) c += cut.mesh.vertex(cut.mesh.F(f, k)) / 3;
    const int i = static_cast<int>(std::floor((c - centre).dot(du) / h + 0.5));
    const int j = static_cast<int>(std::floor((c - centre).dot(dw) / h + 0.5));
    label[f] = (i + 5000) * 10000 + (j + 5000);  // |i|, |j| ≤ 2000 (spacing ≥ diag/2000)
  }
  RegionOptions ro;
  ro.min_area = o.min_cell_fraction * h * h;
  RegionMesh rm = extract_regions(cut.mesh, label, ro);
  Topology ct = build_topology(cut.mesh);
  {
    const std::vector<char> corner =
        boundary_corners(cut.mesh.V, ct.boundary_loops, ro.corner_angle_deg);
    std::vector<int> rank(rm.mesh.num_vertices(), 0);
    for (int v = 0; v < rm.mesh.num_vertices(); ++v) {
      const int s = rm.source_vertex[v];
      rank[v] = corner[s] ? 2 : ct.on_boundary[s] ? 1 : 0;
    }
    collapse_stubs_and_compact(rm, rank, o.min_edge_fraction * h);
  }
  GridShell g;
  g.mesh = std::move(rm.mesh);
  // Supports: joints sitting on supported (cut-mesh) vertices; isolated interior supports of
  // the input go to the nearest joint.
  std::vector<char> is_support(g.mesh.num_vertices(), 0);
  for (int v = 0; v < g.mesh.num_vertices(); ++v)
    if (cut.support[rm.source_vertex[v]]) is_support[v] = 1;
  for (int v = 0; v < cut.mesh.num_vertices(); ++v) {
    if (!cut.support[v] || ct.on_boundary[v]) continue;
    int best = -1;
    double bd = std::numeric_limits<double>::max();
    for (int w = 0; w < g.mesh.num_vertices(); ++w) {
      const double d = (g.mesh.vertex(w) - cut.mesh.vertex(v)).norm();
      if (d < bd) bd = d, best = w;
    }
    if (best >= 0) is_support[best] = 1;
  }
  for (int v = 0; v < g.mesh.num_vertices(); ++v)
    if (is_support[v]) g.supports.push_back(v);
  return g;
}

GridShell quad_grid_for_length(const Surface& surface, double length, QuadGridOptions o,
                               double tolerance) {
  if (!(length > 0) || !std::isfinite(length)) throw Error("--length", "must be positive");
  // First guess: a square grid of spacing h over area A has about 2A/h of beams.
  const double area = surface_area(surface.mesh);
  o.spacing = 2 * area / length;
  GridShell best;
  double best_err = 1e300;
  double h0 = 0, l0 = 0;
  for (int it = 0; it < 12; ++it) {
    GridShell g = quad_grid(surface, o);
    const double l = total_edge_length(g.mesh);
    const double err = std::abs(l - length) / length;
    if (err < best_err) best_err = err, best = std::move(g);
    if (err <= tolerance) return best;
    // Secant on log(length) vs log(spacing); start with the 1/h law.
    double slope = -1;
    if (h0 > 0 && std::abs(std::log(o.spacing / h0)) > 1e-9)
      slope = std::clamp(std::log(l / l0) / std::log(o.spacing / h0), -3.0, -0.3);
    h0 = o.spacing, l0 = l;
    o.spacing = o.spacing * std::exp(std::log(length / l) / slope);
  }
  if (best_err <= 0.05) return best;
  throw Error("--length", fmt::format("quad grid could not reach length {} m (best {:.1f}% off)",
                                      length, 100 * best_err));
}

}  // namespace gridshell
