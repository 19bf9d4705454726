// gridshell baseline SURFACE --kind quad|quad-aniso|tri|voronoi-iso|original --length L -o DIR:
// the comparison grid-shells of the paper at equal total length, with the same outputs as design.

#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common.h"
#include "gridshell/core/error.h"
#include "gridshell/figures/figures.h"
#include "gridshell/grids/baseline_kind.h"
#include "gridshell/grids/dual.h"
#include "gridshell/grids/quad_aniso.h"
#include "gridshell/grids/quad_grid.h"
#include "gridshell/grids/recover_quads.h"
#include "gridshell/grids/supports.h"
#include "gridshell/io/files.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/flat_panels.h"
#include "gridshell/optimize/projector.h"
#include "gridshell/pipeline/baseline_field.h"
#include "gridshell/pipeline/buildability_report.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/design_report.h"
#include "gridshell/pipeline/frame_output.h"
#include "gridshell/pipeline/gridshell_output.h"

namespace gridshell::app {

namespace {

struct BaselineArgs {
  std::string surface = kDefaultSurface;
  std::string kind = "quad";
  double length = 0, spacing = 0, angle_deg = 0, radius = 0;
  int cells = 0;
  std::string analyze = "nonlinear";
  std::string sheet = "2.5x1.25";
  std::string panels = "free";  ///< --panels flat | free (as design)
  // quad-aniso: the field of design
  double D = 3, A = 3;
  double max_size_change = QuadAnisoOptions{}.max_scale_change;
  std::string field = "stress", measure = "magnitude", stretch = "along", density = "rising";
  SurfaceOptions surface_options;
  RunOptions run;
  LoadCheckOptions checks;  ///< --steel, --loads, --glass, --snow, --deflection-limit (as design)
  MemberOptions members;    ///< --section, --buckling-length-factor (as design)
  SizingArgs sizing;        ///< --size, --sections, --section-groups, … (as design)
};

int run_baseline(const BaselineArgs& a, const CLI::App* sub) {
  auto guard = apply_run_options(a.run);
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  nlohmann::json timings;
  auto lap = [&](const char* stage, Clock::time_point since) {
    timings[stage] = std::chrono::duration<double>(Clock::now() - since).count();
  };
  const analysis::AnalysisLevel level = analysis::parse_analysis_level(a.analyze);
  const fabrication::SheetOptions sheet = fabrication::parse_sheet(a.sheet);
  const BaselineKind kind = parse_baseline_kind(a.kind);
  const PanelMode panels = parse_panel_mode(a.panels);
  analysis::GridshellFrameOptions frame;
  analysis::FrameAnalysisOptions options;
  apply_load_check_options(a.checks, frame, options, a.sizing.size);
  apply_member_options(a.members, frame, options);
  StructureOptions structure_options;
  structure_options.level = level;
  apply_sizing_options(a.sizing, structure_options);
  DesignOptions field_options;  // quad-aniso: the design's field
  field_options.field = parse_field_input(a.field, &field_options.field_file);
  field_options.D = a.D, field_options.A = a.A;
  field_options.field_options.measure = parse_stress_measure(a.measure);
  field_options.field_options.stretch = parse_stretch_axis(a.stretch);
  field_options.field_options.density = parse_density_trend(a.density);
  if (!(a.max_size_change >= 1) || !std::isfinite(a.max_size_change))
    throw Error("--max-size-change", "must be a number ≥ 1");
  Surface surface = load_surface(a.surface, a.surface_options);
  attach_load_case_surface(frame, surface.mesh);
  lap("load", t0);
  GridShellOutput out;
  nlohmann::json quad_stats, flat_info;
  const auto t1 = Clock::now();
  if (kind == BaselineKind::quad) {
    QuadGridOptions qo;
    qo.angle = a.angle_deg * 3.14159265358979323846 / 180;
    GridShell g;
    if (a.length > 0) {
      spdlog::info("[baseline] quad grid at total length {} m", a.length);
      g = quad_grid_for_length(surface, a.length, qo);
    } else {
      if (!(a.spacing > 0)) throw Error("--length", "quad needs --length L (m) or --spacing S (m)");
      qo.spacing = a.spacing;
      g = quad_grid(surface, qo);
    }
    out.mesh = std::move(g.mesh);
    out.supports = std::move(g.supports);
  } else if (kind == BaselineKind::quad_aniso) {
    const std::optional<Surface> coarse = baseline_surface(surface, field_options, a.length);
    const Surface& on = coarse ? *coarse : surface;  // what the field and the grid are built on
    const Field field = baseline_field(on, field_options);
    QuadAnisoOptions qo;
    qo.length = a.length;
    qo.spacing = a.spacing;
    qo.seed = a.run.seed;
    qo.max_scale_change = a.max_size_change;
    QuadAnisoResult q = quad_aniso(on, field, qo);
    out.mesh = std::move(q.grid.mesh);
    out.supports = std::move(q.grid.supports);  // coarse keeps the input's supports
    if (coarse) move_onto_input(out.mesh, coarse->mesh, surface.mesh);
    const QuadMeshStats st = quad_mesh_stats(out.mesh, on.mesh, field);
    quad_stats = {{"spacing_deformed_m", q.spacing},
                  {"fits", q.fits},
                  {"grids", q.grids},
                  {"starts", q.starts},
                  {"spacing_factor_p10", q.spacing_factor_p10},
                  {"spacing_factor_p90", q.spacing_factor_p90},
                  {"deformed_triangles", q.deformed_triangles},
                  {"analysis_triangles", on.mesh.num_faces()},
                  {"folded_edges", q.folded_edges},
                  {"field", a.field},
                  {"D", a.D},
                  {"A", a.A},
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
  } else if (kind == BaselineKind::original) {
    // The surface file's own grid-shell (Botanic.ply: Tang's quads as triangle pairs).
    RecoveredQuads q = recover_quads(surface.mesh);
    spdlog::info("[baseline] original: {} quads, {} triangles left",
                 q.mesh.num_faces() - q.triangles, q.triangles);
    out.mesh = std::move(q.mesh);
    out.supports = surface.supports;
  } else if (kind == BaselineKind::voronoi_iso) {
    // The isotropic centroidal Voronoi tessellation (D = A = 1), regularized as design does.
    DesignOptions o;
    o.field = FieldInput::uniform;
    o.D = o.A = 1;
    o.analyze = analysis::AnalysisLevel::none;
    o.tessellation.seed = a.run.seed;
    o.tessellation.length = a.length;
    o.tessellation.radius = a.radius;
    o.tessellation.cells = a.cells;
    o.panels = panels;
    DesignResult r = run_design(surface, o);
    flat_info = r.details.value("flat_panels", nlohmann::json());
    out.mesh = std::move(r.mesh);
    out.raw = std::move(r.raw);
    out.supports = std::move(r.supports);
    out.planarity = r.metrics.planarity;
    out.regularity = r.metrics.regularity;
  } else {
    TriBaselineOptions to;
    to.tessellation.seed = a.run.seed;
    to.tessellation.radius = a.radius;
    to.tessellation.cells = a.cells;
    to.length = a.length;
    GridShell g = tri_baseline(surface, to);
    out.mesh = std::move(g.mesh);
    out.supports = std::move(g.supports);
  }
  lap("grid", t1);
  const SurfaceProjector projector(surface.mesh);
  if (panels == PanelMode::flat && kind != BaselineKind::voronoi_iso) {
    const auto t = Clock::now();
    FlatPanelAttempt flat = attempt_flat_panels(out.mesh, out.supports, surface.mesh, projector);
    if (flat.flat) {
      if (out.raw.num_faces() == 0) out.raw = out.mesh;
      out.mesh = std::move(flat.flat->mesh);
      out.supports = std::move(flat.flat->supports);
      out.planarity.clear();
      out.regularity.clear();
    }
    flat_info = std::move(flat.info);
    lap("flat_panels", t);
  }
  if (out.raw.num_faces() == 0) out.raw = out.mesh;
  if (out.planarity.empty()) {
    const MeshMetrics m = mesh_metrics(out.mesh);
    out.planarity = m.planarity;
    out.regularity = m.regularity;
  }
  std::optional<analysis::FrameResult> structure;
  std::optional<sizing::SizingResult> sized;
  if (level != analysis::AnalysisLevel::none) {
    const auto t2 = Clock::now();
    spdlog::info("[analysis] {} frame: {} joints", a.analyze, out.mesh.num_vertices());
    options.arc.progress = guard.progress;
    GridshellStructure s =
        analyze_structure(out.mesh, out.supports, frame, options, structure_options);
    structure = std::move(s.result);
    sized = std::move(s.sizing);
    frame = std::move(s.frame);
    lap("analysis", t2);
  }
  if (structure) add_structure(out, *structure);
  io::ensure_directory(a.run.out_dir);
  write_gridshell_files(a.run.out_dir, out);
  nlohmann::json report;
  report["kind"] = a.kind;
  report["surface"] = a.surface;
  report["mesh"] = mesh_block(out);
  add_panel_keys(report["mesh"], panel_shape(out.mesh, &projector),
                 flat_info.is_object() && flat_info.value("panels", "") == std::string("flat")
                     ? PanelMode::flat
                     : PanelMode::free);
  if (!flat_info.is_null()) report["flat_panels"] = flat_info;
  const std::optional<fabrication::BeamResults> envelope =
      sized ? std::optional(member_envelope(*sized)) : std::nullopt;
  report["fabrication"] =
      fabrication_report(a.run.out_dir, out.mesh, out.supports, structure ? &*structure : nullptr,
                         frame, sheet, envelope ? &*envelope : nullptr);
  if (a.length > 0) {
    report["mesh"]["target_length_m"] = a.length;
    report["mesh"]["length_error"] = report["mesh"]["total_length_m"].get<double>() / a.length - 1;
  }
  if (structure) {
    report["structure"] = structure_block(*structure);
    report["structure"]["steel"] = a.checks.steel;
    report["structure"]["section"] = section_block(frame);
    report["structure"]["loads"] = to_string(frame.loads);
    report["structure"]["combinations"] = combinations_block(
        out.mesh, out.supports, frame, options, *structure, sized ? &sized->final : nullptr);
    report["structure"]["governing"] = governing_block(report["structure"]["combinations"]);
    report["mass"] = steel_block(out.mesh, frame, a.sizing.carbon_factor);
    if (sized) {
      report["sizing"] = sizing_block(*sized, out.mesh, frame, structure_options.sizing_options,
                                      a.sizing.carbon_factor);
      report["sizing"]["sections_list"] = a.sizing.sections;
      if (!sized->sized) spdlog::warn("[sizing] not sized: {}", sized->failure);
    }
    write_frame_json(a.run.out_dir, analysis::gridshell_frame(out.mesh, out.supports, frame),
                     frame, options, level);
  }
  report["buildability"] = buildability_block(out.mesh, member_designations(frame));
  if (!quad_stats.is_null()) report["quad_aniso"] = quad_stats;
  const auto t3 = Clock::now();
  report["figures"] = figures::write_figures(
      a.run.out_dir,
      {.title = fmt::format("gridshell baseline {} --kind {}: {} cells, {:.0f} m of beams; "
                            "analysis {}; seed {}",
                            a.surface, a.kind, out.mesh.num_faces(),
                            report["mesh"]["total_length_m"].get<double>(), a.analyze, a.run.seed),
       .gridshell = &out.mesh,
       .supports = out.supports,
       .structure = structure ? &*structure : nullptr,
       .surface = &surface.mesh},
      figures::parse_figure_options(a.run.figures));
  lap("figures", t3);
  timings["total"] = std::chrono::duration<double>(Clock::now() - t0).count();
  report["timings_s"] = timings;
  write_config(a.run.out_dir, sub);
  write_report(a.run.out_dir, report);
  report::ReportInput page =
      report::gridshell_report_input(out.mesh, out.supports, structure ? &*structure : nullptr);
  page.density = out.d_target;
  if (structure) page.beam_sections = member_designations(frame);  // sized: one per beam
  if (envelope) {  // sized: the envelope over the ULS combinations, as beams.csv has it
    page.utilisation = envelope->utilisation;
    page.buckling_utilisation = envelope->buckling_utilisation;
  }
  write_report_page(a.run.out_dir, std::move(page), report, sub);
  spdlog::info("[baseline] {} joints, {} panels, {:.1f} m of beams -> {}", out.mesh.num_vertices(),
               out.mesh.num_faces(), report["mesh"]["total_length_m"].get<double>(), a.run.out_dir);
  return 0;
}

}  // namespace

void register_baseline(CLI::App& app, Action& action) {
  auto a = std::make_shared<BaselineArgs>();
  CLI::App* sub = app.add_subcommand(
      "baseline",
      "Comparison grid-shells of the paper (quad, quad-aniso, tri, voronoi-iso, original)");
  sub->add_option("surface", a->surface, "PLY/OBJ/OFF file or builtin:NAME")
      ->default_str(kDefaultSurface);
  sub->add_option("--kind", a->kind, "quad | quad-aniso | tri | voronoi-iso | original")
      ->default_str("quad");
  sub->add_option("--length", a->length, "target total beam length (m), held within 5%");
  sub->add_option("--spacing", a->spacing,
                  "quad: grid spacing in plan (m) instead of --length (quad-aniso: on M')");
  sub->add_option("-D", a->D, "quad-aniso: density ratio of the field (as design)")
      ->default_str("3");
  sub->add_option("-A", a->A, "quad-aniso: anisotropy ratio of the field (as design)")
      ->default_str("3");
  sub->add_option("--field", a->field, "quad-aniso: stress | uniform | FILE (as design)")
      ->default_str("stress");
  sub->add_option("--stress-measure", a->measure, "quad-aniso: magnitude | tension | compression")
      ->default_str("magnitude");
  sub->add_option("--stretch", a->stretch, "quad-aniso: along | across")->default_str("along");
  sub->add_option("--density", a->density, "quad-aniso: rising | falling")->default_str("rising");
  sub->add_option("--max-size-change", a->max_size_change,
                  "quad-aniso: cells may depart from the size d asks for by this factor so the "
                  "lattice follows turning directions with fewer irregular joints (1: exactly d)")
      ->default_str(fmt::format("{}", QuadAnisoOptions{}.max_scale_change));
  sub->add_option("--angle", a->angle_deg, "quad: rotation of the grid in plan (degrees)")
      ->default_str("0");
  sub->add_option("--radius", a->radius, "voronoi-iso/tri: cell size R (m) instead of --length");
  sub->add_option("--cells", a->cells, "voronoi-iso/tri: number of cells instead of --length");
  sub->add_option("--analyze", a->analyze, "none | linear | buckling | nonlinear")
      ->default_str("nonlinear");
  sub->add_option("--panels", a->panels,
                  "flat: every panel exactly planar (docs/panels.md) | free (as design)")
      ->default_str("free");
  sub->add_option("--sheet", a->sheet,
                  "fabrication: sheet size WxH in metres on which the panels are nested")
      ->default_str("2.5x1.25");
  sub->footer(
      "Writes the files of design (without field.vtp and field.png): gridshell_raw.obj,\n"
      "gridshell.obj, gridshell.ply, gridshell.vtp, cells.csv, joints.csv, beams.csv,\n"
      "panels.csv, panels.svg, figures/*.png (docs/figures.md), report.json, config.json\n"
      "and report.html (open it first: the 3D view, key figures and figures, offline).");
  add_load_check_options(sub, a->checks);
  add_member_options(sub, a->members);
  add_sizing_options(sub, a->sizing);
  add_surface_options(sub, a->surface_options);
  add_run_options(sub, a->run);
  add_figure_option(sub, a->run);
  sub->callback([a, sub, &action] { action = [a, sub] { return run_baseline(*a, sub); }; });
}

}  // namespace gridshell::app
