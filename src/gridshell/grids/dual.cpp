#include "gridshell/grids/dual.h"

#include <cmath>

#include <spdlog/spdlog.h>

#include "gridshell/grids/supports.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

PolyMesh dual_triangulation(const PolyMesh& cells, const std::vector<Vec3>& seeds) {
  const Topology t = build_topology(cells);
  PolyMesh out;
  out.V.resize(cells.num_faces(), 3);
  for (int f = 0; f < cells.num_faces(); ++f) out.V.row(f) = seeds[f].transpose();
  for (int v = 0; v < cells.num_vertices(); ++v) {
    if (t.on_boundary[v] || t.vertex_faces[v].size() < 3) continue;
    // Order the faces around v: the face after f is the one containing v's outgoing edge in f
    // reversed (faces are consistently oriented).
    std::vector<int> ring;
    int f = t.vertex_faces[v][0];
    for (std::size_t guard = 0; guard <= t.vertex_faces[v].size(); ++guard) {
      ring.push_back(f);
      const auto& poly = cells.faces[f];
      const auto it = std::find(poly.begin(), poly.end(), v);
      const int prev = poly[(it - poly.begin() + poly.size() - 1) % poly.size()];
      // The neighbour across edge (prev, v).
      const int e = t.find_edge(prev, v);
      int g = -1;
      for (int h : t.edge_faces[e])
        if (h != f) g = h;
      if (g < 0 || g == ring.front()) break;
      f = g;
    }
    // The ring runs so that (ring[0], ring[k], ring[k+1]) keeps the cells' orientation.
    for (std::size_t k = 1; k + 1 < ring.size(); ++k)
      out.faces.push_back({ring[0], ring[k], ring[k + 1]});
  }
  return out;
}

GridShell tri_baseline(const Surface& surface, const TriBaselineOptions& o) {
  TessellationOptions t = o.tessellation;
  double target = o.length > 0 ? o.length / std::sqrt(3.0) : 0;
  const double tol = 1e-6 * bbox_diagonal(surface.mesh.V);
  GridShell g;
  for (int it = 0; it < o.max_fits; ++it) {
    t.length = target;
    Tessellation tess;
    for (int attempt = 0;; ++attempt) {  // as in design: another seed if extraction fails
      t.seed = o.tessellation.seed + 7919 * static_cast<std::uint64_t>(attempt);
      try {
        tess = tessellate(surface.mesh, surface.mesh, surface.supports, t);
        break;
      } catch (const ExtractionError&) {
        if (attempt == 2) throw;
      }
    }
    g.mesh = dual_triangulation(tess.mesh, tess.seeds);
    if (o.length <= 0) break;
    const double l = total_edge_length(g.mesh);
    spdlog::info("[baseline] tri: {:.1f} m of beams for {:.1f} m asked", l, o.length);
    if (std::abs(l - o.length) <= o.fit_tolerance * o.length) break;
    target *= o.length / l;
  }
  g.supports = transfer_supports(g.mesh.V, surface, std::max(tol, 1e-9));
  return g;
}

}  // namespace gridshell
