// gridshell baseline SURFACE --kind quad|quad-aniso|tri|voronoi-iso|original --length L -o DIR:
// the comparison grid-shells of the paper at equal total length, with the same outputs as design.

#include <cmath>
#include <filesystem>
#include <optional>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common.h"
#include "gridshell/core/error.h"
#include "gridshell/core/timings.h"
#include "gridshell/figures/figures.h"
#include "gridshell/grids/baseline_kind.h"
#include "gridshell/io/files.h"
#include "gridshell/pipeline/baseline.h"
#include "gridshell/pipeline/buildability_report.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/design_report.h"
#include "gridshell/pipeline/design_settings.h"
#include "gridshell/pipeline/frame_output.h"
#include "gridshell/pipeline/gridshell_output.h"
#include "gridshell/pipeline/objective.h"

namespace gridshell::app {

namespace {

struct BaselineArgs {
  std::string surface = kDefaultSurface;
  std::string kind = "quad";
  BaselineOptions baseline;  ///< the numbers: --length, --spacing, --angle, --radius, --cells, …
  /// quad-aniso: the design's field (-D, -A, --field and the conventions); --analyze, --panels,
  /// and the load model, members and sizing (as design)
  DesignSettings design;
  std::string sheet = fabrication::kDefaultSheet;
  SurfaceOptions surface_options;
  RunOptions run;
};

/// report.json's analysed keys (structure with its section; add_analysed_report: steel, loads,
/// combinations and the governing ones, mass, sizing when sized) and frame.json, as design.
void add_structure_report(const BaselineArgs& a, const GridShellOutput& out,
                          const analysis::GridshellFrameOptions& frame,
                          const analysis::FrameAnalysisOptions& options,
                          const StructureOptions& structure_options,
                          const analysis::FrameResult& structure,
                          const sizing::SizingResult* sized, nlohmann::json& report) {
  report["structure"] = structure_block(structure);
  report["structure"]["section"] = section_block(frame);
  AnalysedGridshell analysed;
  analysed.mesh = &out.mesh;
  analysed.supports = &out.supports;
  analysed.frame = &frame;
  analysed.options = &options;
  analysed.level = structure_options.level;
  analysed.structure = &structure;
  analysed.sized = sized;
  analysed.sizing_options = &structure_options.sizing_options;
  analysed.steel = a.design.checks.steel;
  analysed.sections = a.design.sizing.sections;
  analysed.carbon_factor = a.design.sizing.carbon_factor;
  add_analysed_report(a.run.out_dir, analysed, report);
}

int run_baseline(const BaselineArgs& a, const CLI::App* sub) {
  auto guard = apply_run_options(a.run);
  const Stopwatch total;
  Stopwatch clock;
  Timings timings;
  BaselineOptions bo = a.baseline;
  bo.kind = parse_baseline_kind(a.kind);
  bo.seed = a.run.seed;
  bo.panels = parse_panel_mode(a.design.panels);
  const fabrication::SheetOptions sheet = fabrication::parse_sheet(a.sheet);
  if (parse_frame_source(a.design.field))
    throw Error("--field", "a baseline takes stress | uniform | FILE");
  DesignSettings settings = a.design;
  // A baseline follows the perfect path only, except when sized: --size checks every ULS
  // combination's λ with the unfavourable imperfection (docs/sizing.md), as design does, so that
  // the patterns are sized to the same safety.
  settings.single_path = !settings.sizing.size;
  bo.field = build_design_options(settings);
  analysis::GridshellFrameOptions frame = bo.field.frame;
  const analysis::FrameAnalysisOptions& options = bo.field.frame_analysis;
  const analysis::AnalysisLevel level = bo.field.analyze;
  StructureOptions structure_options;
  structure_options.level = level;
  structure_options.sizing = bo.field.sizing;
  structure_options.sizing_options = bo.field.sizing_options;
  if (!(bo.max_size_change >= 1) || !std::isfinite(bo.max_size_change))
    throw Error("--max-size-change", "must be a number ≥ 1");
  Surface surface = load_surface(a.surface, a.surface_options);
  attach_load_case_surface(frame, surface.mesh);
  timings.add("load", clock.lap());
  Baseline baseline = make_baseline(surface, bo);
  for (const auto& [stage, seconds] : baseline.timings) timings.add(stage, seconds);
  clock.lap();  // the baseline's stages are timed in its own timings
  GridShellOutput& out = baseline.out;
  std::optional<analysis::FrameResult> structure;
  std::optional<sizing::SizingResult> sized;
  if (level != analysis::AnalysisLevel::none) {
    spdlog::info("[analysis] {} frame: {} joints", a.design.analyze, out.mesh.num_vertices());
    analysis::FrameAnalysisOptions analysis_options = options;
    analysis_options.arc.progress = guard.progress;
    GridshellStructure s =
        analyze_structure(out.mesh, out.supports, frame, analysis_options, structure_options);
    structure = std::move(s.result);
    sized = std::move(s.sizing);
    frame = std::move(s.frame);
    timings.add("analysis", clock.lap());
  }
  if (structure) add_structure(out, *structure);
  io::ensure_directory(a.run.out_dir);
  write_gridshell_files(a.run.out_dir, out);
  nlohmann::json report;
  report["kind"] = a.kind;
  report["surface"] = a.surface;
  report["mesh"] = mesh_block(out);
  const nlohmann::json& flat_info = baseline.flat_info;
  add_panel_keys(report["mesh"], baseline.panels,
                 flat_info.is_object() && flat_info.value("panels", "") == std::string("flat")
                     ? PanelMode::flat
                     : PanelMode::free);
  if (!flat_info.is_null()) report["flat_panels"] = flat_info;
  warn_if_panels_kept_free(flat_info);
  const std::optional<fabrication::BeamResults> envelope =
      sized ? std::optional(member_envelope(*sized)) : std::nullopt;
  report["fabrication"] =
      fabrication_report(a.run.out_dir, out.mesh, out.supports, structure ? &*structure : nullptr,
                         frame, sheet, envelope ? &*envelope : nullptr);
  if (bo.length > 0) {
    report["mesh"]["target_length_m"] = bo.length;
    report["mesh"]["length_error"] = report["mesh"]["total_length_m"].get<double>() / bo.length - 1;
    warn_if_length_missed(report["mesh"]["total_length_m"].get<double>(), bo.length, 0.05);
  }
  if (structure)
    add_structure_report(a, out, frame, options, structure_options, *structure,
                         sized ? &*sized : nullptr, report);
  report["buildability"] = buildability_block(out.mesh, member_designations(frame));
  if (!baseline.quad_stats.is_null()) report["quad_aniso"] = baseline.quad_stats;
  clock.lap();
  report["figures"] = figures::write_figures(
      a.run.out_dir,
      {.title = fmt::format("gridshell baseline {} --kind {}: {} cells, {:.0f} m of beams; "
                            "analysis {}; seed {}",
                            a.surface, a.kind, out.mesh.num_faces(),
                            report["mesh"]["total_length_m"].get<double>(), a.design.analyze,
                            a.run.seed),
       .gridshell = &out.mesh,
       .supports = out.supports,
       .structure = structure ? &*structure : nullptr,
       .surface = &surface.mesh},
      figures::parse_figure_options(a.run.figures));
  timings.add("figures", clock.lap());
  timings.add("total", total.seconds());
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
  BaselineOptions& bo = a->baseline;
  DesignSettings& d = a->design;
  sub->add_option("--length", bo.length, "target total beam length (m), held within 5%");
  sub->add_option("--spacing", bo.spacing,
                  "quad: grid spacing in plan (m) instead of --length (quad-aniso: on M')");
  add_field_ratio_options(sub, d.options.field_options, "quad-aniso: ");
  sub->add_option("--field", d.field, "quad-aniso: stress | uniform | FILE (as design)")
      ->default_str(d.field);
  add_field_convention_options(sub, d, "quad-aniso: ");
  sub->add_option("--max-size-change", bo.max_size_change,
                  "quad-aniso: cells may depart from the size d asks for by this factor so the "
                  "lattice follows turning directions with fewer irregular joints (1: exactly d)")
      ->default_str(fmt::format("{}", bo.max_size_change));
  sub->add_option("--angle", bo.angle_deg, "quad: rotation of the grid in plan (degrees)")
      ->default_str("0");
  sub->add_option("--radius", bo.radius, "voronoi-iso/tri: cell size R (m) instead of --length");
  sub->add_option("--cells", bo.cells, "voronoi-iso/tri: number of cells instead of --length");
  sub->add_option("--analyze", d.analyze, "none | linear | buckling | nonlinear")
      ->default_str(d.analyze);
  sub->add_option("--panels", d.panels,
                  "flat: every panel exactly planar (docs/panels.md) | free (as design)")
      ->default_str(d.panels);
  sub->add_option("--sheet", a->sheet,
                  "fabrication: sheet size WxH in metres on which the panels are nested")
      ->default_str(fabrication::kDefaultSheet);
  sub->footer(
      "Writes the files of design (without field.vtp and field.png): gridshell_raw.obj,\n"
      "gridshell.obj, gridshell.ply, gridshell.vtp, cells.csv, joints.csv, beams.csv,\n"
      "panels.csv, panels.svg, figures/*.png (docs/figures.md), report.json, config.json\n"
      "and report.html (open it first: the 3D view, key figures and figures, offline).");
  add_load_check_options(sub, d.checks);
  add_member_options(sub, d.members);
  add_sizing_options(sub, d.sizing);
  add_surface_options(sub, a->surface_options);
  add_run_options(sub, a->run);
  add_figure_option(sub, a->run);
  sub->callback([a, sub, &action] { action = [a, sub] { return run_baseline(*a, sub); }; });
}

}  // namespace gridshell::app
