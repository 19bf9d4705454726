#include "gridshell/pipeline/baseline.h"

#include <cmath>
#include <optional>

#include <spdlog/spdlog.h>

#include "gridshell/core/error.h"
#include "gridshell/grids/dual.h"
#include "gridshell/grids/quad_grid.h"
#include "gridshell/grids/recover_quads.h"
#include "gridshell/optimize/projector.h"
#include "gridshell/pipeline/baseline_field.h"

namespace gridshell {

namespace {

/// quad: the square grid in plan at the length or the spacing.
GridShell quad_baseline(const Surface& surface, const BaselineOptions& o) {
  QuadGridOptions qo;
  qo.angle = o.angle_deg * 3.14159265358979323846 / 180;
  if (o.length > 0) {
    spdlog::info("[baseline] quad grid at total length {} m", o.length);
    return quad_grid_for_length(surface, o.length, qo);
  }
  if (!(o.spacing > 0)) throw Error("--length", "quad needs --length L (m) or --spacing S (m)");
  qo.spacing = o.spacing;
  return quad_grid(surface, qo);
}

/// The word of the design's field in report.json `quad_aniso.field` (as the option gave it).
std::string field_word(const DesignOptions& field) {
  return field.field == FieldInput::file      ? field.field_file
         : field.field == FieldInput::uniform ? "uniform"
                                              : "stress";
}

/// report.json's `quad_aniso` block: the extraction's figures and the quad mesh's statistics.
nlohmann::json quad_aniso_stats(const QuadAnisoResult& q, const QuadMeshStats& st,
                                const BaselineOptions& o, int analysis_triangles) {
  return {{"spacing_deformed_m", q.spacing},
          {"fits", q.fits},
          {"grids", q.grids},
          {"starts", q.starts},
          {"spacing_factor_p10", q.spacing_factor_p10},
          {"spacing_factor_p90", q.spacing_factor_p90},
          {"deformed_triangles", q.deformed_triangles},
          {"analysis_triangles", analysis_triangles},
          {"folded_edges", q.folded_edges},
          {"field", field_word(o.field)},
          {"D", o.field.field_options.D},
          {"A", o.field.field_options.A},
          {"interior_joints", st.interior_joints},
          {"valence4_share", st.valence4_share},
          {"interior_faces", st.interior_faces},
          {"quad_share", st.quad_share},
          {"non_simple_faces", st.non_simple_faces},
          {"overlaps", st.overlaps},
          {"min_edge_ratio", st.min_edge_ratio},
          {"min_area_ratio", st.min_area_ratio},
          {"strong_beams", st.strong_beams},
          {"aligned_share", st.aligned_share},
          {"aspect_quads", st.aspect_quads},
          {"median_aspect", st.median_aspect},
          {"median_aspect_all", st.median_aspect_all},
          {"coverage", st.coverage}};
}

/// quad-aniso: quads following the design's field, built on the design's analysis surface and
/// moved onto the input.
void quad_aniso_baseline(const Surface& surface, const BaselineOptions& o, Baseline& b) {
  const std::optional<Surface> coarse = baseline_surface(surface, o.field, o.length);
  const Surface& on = coarse ? *coarse : surface;  // what the field and the grid are built on
  const Field field = baseline_field(on, o.field);
  QuadAnisoOptions qo;
  qo.length = o.length;
  qo.spacing = o.spacing;
  qo.seed = o.seed;
  qo.max_scale_change = o.max_size_change;
  QuadAnisoResult q = quad_aniso(on, field, qo);
  b.out.mesh = std::move(q.grid.mesh);
  b.out.supports = std::move(q.grid.supports);  // coarse keeps the input's supports
  if (coarse) move_onto_input(b.out.mesh, coarse->mesh, surface.mesh);
  const QuadMeshStats st = quad_mesh_stats(b.out.mesh, on.mesh, field);
  b.quad_stats = quad_aniso_stats(q, st, o, on.mesh.num_faces());
}

/// voronoi-iso: the isotropic centroidal Voronoi tessellation (D = A = 1), regularized as design
/// does (and with flat panels made by the design).
void voronoi_iso_baseline(const Surface& surface, const BaselineOptions& bo, Baseline& b) {
  DesignOptions o;
  o.field = FieldInput::uniform;
  o.field_options.D = o.field_options.A = 1;
  o.analyze = analysis::AnalysisLevel::none;
  o.tessellation.seed = bo.seed;
  o.tessellation.length = bo.length;
  o.tessellation.radius = bo.radius;
  o.tessellation.cells = bo.cells;
  o.panels = bo.panels;
  DesignResult r = run_design(surface, o);
  b.flat_info = r.details.value("flat_panels", nlohmann::json());
  b.out.mesh = std::move(r.mesh);
  b.out.raw = std::move(r.raw);
  b.out.supports = std::move(r.supports);
  b.out.planarity = r.metrics.planarity;
  b.out.regularity = r.metrics.regularity;
}

/// The grid of `o.kind`.
void baseline_grid(const Surface& surface, const BaselineOptions& o, Baseline& b) {
  if (o.kind == BaselineKind::quad) {
    GridShell g = quad_baseline(surface, o);
    b.out.mesh = std::move(g.mesh);
    b.out.supports = std::move(g.supports);
  } else if (o.kind == BaselineKind::quad_aniso) {
    quad_aniso_baseline(surface, o, b);
  } else if (o.kind == BaselineKind::original) {
    // The surface file's own grid-shell (Botanic.ply: Tang's quads as triangle pairs).
    RecoveredQuads q = recover_quads(surface.mesh);
    spdlog::info("[baseline] original: {} quads, {} triangles left",
                 q.mesh.num_faces() - q.triangles, q.triangles);
    b.out.mesh = std::move(q.mesh);
    b.out.supports = surface.supports;
  } else if (o.kind == BaselineKind::voronoi_iso) {
    voronoi_iso_baseline(surface, o, b);
  } else {
    TriBaselineOptions to;
    to.tessellation.seed = o.seed;
    to.tessellation.radius = o.radius;
    to.tessellation.cells = o.cells;
    to.length = o.length;
    GridShell g = tri_baseline(surface, to);
    b.out.mesh = std::move(g.mesh);
    b.out.supports = std::move(g.supports);
  }
}

}  // namespace

Baseline make_baseline(const Surface& surface, const BaselineOptions& o) {
  if (!(o.max_size_change >= 1) || !std::isfinite(o.max_size_change))
    throw Error("--max-size-change", "must be a number ≥ 1");
  Baseline b;
  Stopwatch watch;
  baseline_grid(surface, o, b);
  b.timings.add("grid", watch.lap());
  const SurfaceProjector projector(surface.mesh);
  GridShellOutput& out = b.out;
  if (o.panels == PanelMode::flat && o.kind != BaselineKind::voronoi_iso) {
    FlatPanelAttempt flat = attempt_flat_panels(out.mesh, out.supports, surface.mesh, projector);
    if (flat.flat) {
      if (out.raw.num_faces() == 0) out.raw = out.mesh;
      out.mesh = std::move(flat.flat->mesh);
      out.supports = std::move(flat.flat->supports);
      out.d_target = per_flat_panel(out.d_target, flat.flat->source_face);
      out.a_target = per_flat_panel(out.a_target, flat.flat->source_face);
      out.planarity.clear();
      out.regularity.clear();
    }
    b.flat_info = std::move(flat.info);
    b.timings.add("flat_panels", watch.lap());
  }
  if (out.raw.num_faces() == 0) out.raw = out.mesh;
  if (out.planarity.empty()) {
    const MeshMetrics m = mesh_metrics(out.mesh);
    out.planarity = m.planarity;
    out.regularity = m.regularity;
  }
  b.panels = panel_shape(out.mesh, &projector);
  return b;
}

}  // namespace gridshell
