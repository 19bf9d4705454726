#include "gridshell/grids/quad_aniso.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "gridshell/core/error.h"
#include "gridshell/grids/quad_aniso_internal.h"
#include "gridshell/grids/supports.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/optimize/projector.h"

namespace gridshell {

namespace {

using namespace quad_aniso_internal;

/// Throws Error for a field of the wrong size and for options out of range.
void check_options(const TriMesh& mesh, const Field& field, const QuadAnisoOptions& o) {
  if (field.size() != mesh.num_faces())
    throw Error("quad-aniso", "the field does not have one entry per triangle");
  if (!(o.length > 0) && !(o.spacing > 0))
    throw Error("--length", "quad-aniso needs --length L (m) or a spacing");
  if (!(o.resolution >= 1)) throw Error("quad-aniso", "resolution must be ≥ 1");
  if (!(o.direction_smoothing > 0) || !std::isfinite(o.direction_smoothing))
    throw Error("quad-aniso", "direction_smoothing must be positive");
  if (!(o.integrable_scale >= 0) || !std::isfinite(o.integrable_scale))
    throw Error("quad-aniso", "integrable_scale must be ≥ 0");
  if (!(o.max_scale_change >= 1) || !std::isfinite(o.max_scale_change))
    throw Error("quad-aniso", "max_scale_change must be ≥ 1");
  if (!(o.start_cells >= 0) || !std::isfinite(o.start_cells))
    throw Error("quad-aniso", "start_cells must be ≥ 0");
  if (o.gap_joints < 0) throw Error("quad-aniso", "gap_joints must be ≥ 0");
  if (!(o.min_face_area >= 0 && o.min_face_area < 1))
    throw Error("quad-aniso", "min_face_area must be in [0, 1)");
}

/// The area of M′ (M's triangles scaled by d² / a).
double deformed_area(const TriMesh& mesh, const Field& field) {
  double area_def = 0;
  for (int f = 0; f < mesh.num_faces(); ++f)
    area_def += triangle_area(mesh.vertex(mesh.F(f, 0)), mesh.vertex(mesh.F(f, 1)),
                              mesh.vertex(mesh.F(f, 2))) *
                field.d[f] * field.d[f] / field.a[f];
  return area_def;
}

bool is_isotropic(const Field& field) {
  for (int f = 0; f < field.size(); ++f)
    if (field.d[f] != 1 || field.a[f] != 1) return false;
  return true;
}

/// M (refined as M′) and M′ with the field per refined triangle, and M′'s folded edges.
struct MetricMeshes {
  TriMesh rest, def;
  Field rest_field;
  int folded_edges = 0;
};

/// M′ with edges ≤ `max_edge`: for an isotropic field M itself, split until its edges are short
/// enough (the field's directions carried to the pieces); otherwise deform_metric.
MetricMeshes metric_meshes(const TriMesh& mesh, const Field& field, double max_edge,
                           const QuadAnisoOptions& o) {
  MetricMeshes m;
  if (is_isotropic(field)) {
    m.rest = m.def = mesh;
    std::vector<int> parent(mesh.num_faces());
    std::iota(parent.begin(), parent.end(), 0);
    for (int round = 0; round < 32; ++round) {
      std::vector<int> p;
      if (split_long_edges(m.rest, m.def, max_edge, p) == 0) break;
      std::vector<int> composed(p.size());
      for (size_t k = 0; k < p.size(); ++k) composed[k] = parent[p[k]];
      parent = std::move(composed);
    }
    for (int p : parent) {
      m.rest_field.u.push_back(field.u[p]);
      m.rest_field.d.push_back(1);
      m.rest_field.a.push_back(1);
    }
  } else {
    DeformOptions dopt = o.deform;
    dopt.max_edge = max_edge;
    spdlog::info("[metric] deforming {} triangles (edges of M' ≤ {:.3g} m)", mesh.num_faces(),
                 max_edge);
    Deformed d = deform_metric(mesh, field, dopt);
    m.folded_edges = d.folded_edges;
    m.rest = std::move(d.rest);
    m.def = std::move(d.deformed);
    m.rest_field = std::move(d.field);
  }
  return m;
}

}  // namespace

double quad_grid_quality(const QuadMeshStats& st) {
  const double aligned = st.strong_beams > 0 ? st.aligned_share : 1.0;
  // Coverage over 1 (faces stacked; remove_overlaps leaves them out before a grid is scored, so
  // this is a guard) counts as much against as the same shortfall.
  const double covered = 1 - std::abs(1 - st.coverage);
  const int short_of_bars =
      (st.valence4_share < 0.85) + (st.quad_share < 0.85) + (aligned < 0.70) + (covered < 0.90);
  // A missed bar weighs more than the sum of the four shares can make up.
  return st.valence4_share + st.quad_share + aligned + covered - 4.0 * short_of_bars;
}

QuadAnisoResult quad_aniso(const Surface& surface, const Field& field, const QuadAnisoOptions& o) {
  const TriMesh& mesh = surface.mesh;
  check_options(mesh, field, o);
  const double area_def = deformed_area(mesh, field);
  // Square cells of side h on M′ have 2/h of beams per m²; lengths on M are about
  // √(area_M / area_M′) of those on M′.
  const double h =
      o.length > 0 ? 2 * std::sqrt(surface_area(mesh) * area_def) / o.length : o.spacing;
  QuadAnisoResult r;
  const MetricMeshes metric = metric_meshes(mesh, field, h / o.resolution, o);
  r.folded_edges = metric.folded_edges;
  r.deformed_triangles = metric.def.num_faces();
  const SurfaceProjector proj(mesh);
  const double tol = 1e-6 * bbox_diagonal(mesh.V);
  // A surface of several pieces (two roofs in one file) gets a grid on each: per piece, the
  // grid's largest component on it is kept.
  const SurfacePieces pieces = surface_pieces(mesh);
  const MetricFrames frames =
      metric_frames(metric.rest, metric.def, metric.rest_field, h, o);  // the h M′ is refined for
  // One lattice start at one spacing: extracted on M′, cleaned up on M, measured and scored.
  CandidatePool pool([&](double spacing, int start) {
    QuadAnisoOptions so = o;
    so.seed = o.seed + 7919 * static_cast<std::uint64_t>(start);
    Candidate c;
    c.spacing = spacing;
    c.grid = clean_up_on_surface(
        quad_mesh_from_frames(frames, metric.rest, metric.def, spacing, so), mesh, proj, pieces, o);
    c.score = quad_grid_quality(quad_mesh_stats(c.grid, mesh, field));
    c.length = total_edge_length(c.grid);
    c.error = o.length > 0 ? c.length / o.length - 1 : 0;
    return c;
  });
  const int starts = std::max(1, o.starts);
  const SpacingFit fit = fit_spacing(pool, h, starts, o);
  r.fits = fit.fits;
  starts_across_target(pool, fit.next_spacing, starts, o);
  r.starts = starts_at_chosen(pool, area_def, starts, o);
  r.grids = pool.size();
  const Candidate* best = pool.choose(o.length_tolerance);
  const double limit = std::max(o.length_tolerance, o.length_limit);
  if (o.length > 0 && std::abs(best->error) > limit)
    throw Error("quad-aniso", fmt::format("total length not within {:.0f}% of {} m after {} grids",
                                          100 * limit, o.length, r.grids));
  r.spacing = best->spacing;
  r.spacing_factor_p10 = frames.scale_p10;
  r.spacing_factor_p90 = frames.scale_p90;
  PolyMesh best_grid = best->grid;
  r.grid.mesh = std::move(best_grid);
  r.grid.supports = transfer_supports(r.grid.mesh.V, surface, tol);
  return r;
}

}  // namespace gridshell
