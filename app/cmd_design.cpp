// gridshell design [SURFACE] -D 3 -A 3 [--length L | --radius R | --cells N] -o DIR: the whole
// pipeline of the paper (stress → field → metric → tessellation → symmetry → regularization →
// analysis), each stage timed in report.json.

#include <algorithm>
#include <chrono>
#include <optional>
#include <filesystem>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common.h"
#include "gridshell/checks/member_checks.h"
#include "gridshell/core/error.h"
#include "gridshell/figures/figures.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/objective.h"
#include "gridshell/report/design_folder.h"

namespace gridshell::app {

namespace {

struct DesignArgs {
  std::string surface = kDefaultSurface;
  SurfaceOptions surface_options;
  RunOptions run;
  /// Every design setting (pipeline/design_settings.h): the words, and the numbers in
  /// `design.options` (D and A in its field_options); build_design_options turns them into the
  /// pipeline's DesignOptions.
  DesignSettings design;
  std::string objective = "balanced";
  std::string sheet = fabrication::kDefaultSheet;  ///< panels nested on sheets of W x H m
  bool search = true;  ///< no -D/-A/convention/--field given: search for the objective
};

/// The figures' subtitle: what was run.
std::string design_title(const DesignArgs& a, const DesignResult& r,
                         const ObjectiveResult* searched) {
  const nlohmann::json f = r.details.value("field", nlohmann::json::object());
  std::string field = f.value("kind", a.design.field);
  if (f.contains("D")) field += fmt::format(" D={} A={}", f["D"].dump(), f["A"].dump());
  if (searched)
    field = fmt::format("{} (chosen by --objective {})",
                        searched->candidates[searched->chosen].setting.label(), a.objective);
  return fmt::format(
      "gridshell design {}: field {}; {} cells, {:.0f} m of beams; analysis {}; "
      "seed {}",
      a.surface, field, r.mesh.num_faces(), r.metrics.total_length, a.design.analyze, a.run.seed);
}

int run_design_cmd(const DesignArgs& a, const CLI::App* sub) {
  const auto guard = apply_run_options(a.run);
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  // Every option word is parsed here, before any work.
  const std::optional<FieldSource> response = parse_frame_source(a.design.field);
  ObjectiveOptions objective;
  objective.objective = parse_objective(a.objective);
  objective.progress = guard.progress;
  DesignSettings settings = a.design;
  settings.seed = a.run.seed;
  // --objective mass sizes every candidate: it implies --size (and so eurocode loads unless
  // --loads is given).
  settings.sizing.size =
      settings.sizing.size || (a.search && objective.objective == Objective::mass);
  DesignOptions options = build_design_options(settings);
  options.frame_analysis.arc.progress = guard.progress;
  const fabrication::SheetOptions sheet = fabrication::parse_sheet(a.sheet);
  spdlog::info("[load] {}", a.surface);
  const Surface surface = load_surface(a.surface, a.surface_options);
  attach_load_case_surface(options.frame, surface.mesh);
  const double t_load = std::chrono::duration<double>(Clock::now() - start).count();
  std::optional<ObjectiveResult> searched;
  if (a.search) searched = design_for_objective(surface, options, objective);
  const DesignResult r = searched   ? std::move(searched->design)
                         : response ? design_from_frame_response(surface, options, *response)
                                    : run_design(surface, options);
  warn_if_panels_kept_free(r.details.value("flat_panels", nlohmann::json()));
  warn_if_length_missed(r.metrics.total_length, options.tessellation.length,
                        options.tessellation.length_tolerance);

  report::DesignFolderInput folder;
  folder.surface = &surface;
  folder.options = &options;
  folder.result = &r;
  folder.search = searched ? &*searched : nullptr;
  folder.surface_name = a.surface;
  folder.title = design_title(a, r, folder.search);
  folder.config = resolved_config(sub);
  folder.sheet = sheet;
  folder.figures = figures::parse_figure_options(a.run.figures);
  folder.steel = a.design.checks.steel;
  folder.sections = a.design.sizing.sections;
  folder.carbon_factor = a.design.sizing.carbon_factor;
  folder.timings_before = {{"load", t_load}};
  folder.seconds_before = std::chrono::duration<double>(Clock::now() - start).count();
  const std::filesystem::path dir(a.run.out_dir);
  const nlohmann::json report = report::write_design_folder(dir, folder);
  const nlohmann::json& timings = report["timings_s"];
  spdlog::info("[done] {} joints, {} panels, {:.1f} m of beams in {:.1f} s -> {}",
               r.mesh.num_vertices(), r.mesh.num_faces(), r.metrics.total_length,
               timings["total"].get<double>(), dir.string());
  return 0;
}

}  // namespace

void register_design(CLI::App& app, Action& action) {
  auto a = std::make_shared<DesignArgs>();
  CLI::App* sub = app.add_subcommand(
      "design",
      "The paper's pipeline: shell stress → field → metric → centroidal Voronoi tessellation → "
      "regularization → steel-frame analysis");
  sub->add_option("surface", a->surface,
                  "PLY/OBJ/OFF file or builtin:NAME (default builtin:funicular)")
      ->default_str(kDefaultSurface);
  DesignSettings& d = a->design;
  auto* field =
      sub->add_option("--field", d.field,
                      "stress (shell analysis of the surface), uniform (isotropic cells), "
                      "frame-mode / frame-energy (strain energy of the isotropic design's frame "
                      "in its buckling modes / under the load), or a field file (BLK, or CSV "
                      "vertex,s1,s2,d1x,d1y,d1z)")
          ->default_str("stress");
  auto* objective =
      sub->add_option("--objective", a->objective,
                      "lambda | delta | balanced: search the field settings (D, A, conventions, "
                      "frame-response fields) at equal length and keep the design with the "
                      "highest lambda_LBA, the lowest delta, or a gain in one with the other no "
                      "more than 2% worse; mass: size every candidate (fields and 0.75/1/1.33x "
                      "the cell count, at level buckling) and keep the lightest that passes, "
                      "sized again at --analyze (implies --size); used unless -D/-A/--field/a "
                      "convention is given")
          ->default_str("balanced");
  std::vector<CLI::Option*> exact = add_field_ratio_options(sub, d.options.field_options);
  for (CLI::Option* o : add_field_convention_options(sub, d)) exact.push_back(o);
  auto* radius = sub->add_option("--radius", d.options.tessellation.radius,
                                 "cell size R in metres on M' (≈ beam length where d = 1)");
  auto* cells = sub->add_option("--cells", d.options.tessellation.cells, "number of cells");
  auto* length = sub->add_option("--length", d.options.tessellation.length,
                                 "target total beam length in metres (held within 5%)");
  radius->excludes(cells)->excludes(length);
  cells->excludes(length);
  sub->add_option("--symmetry", d.symmetry,
                  "x | y | xy: exact mirror symmetry about the bounding-box mid-planes");
  sub->add_option("--analysis-resolution", d.resolution,
                  "cells (stress, field, metric and tessellation on a coarsened copy when the "
                  "input is much finer than the cells need; the joints on the input) | input")
      ->default_str("cells");
  sub->add_flag("--no-regularize", d.no_regularize,
                "keep the raw tessellation (not with --planarize: an error)");
  sub->add_option("--panels", d.panels,
                  "flat: every panel exactly planar (joints at plane intersections, "
                  "docs/panels.md) | free: joints on the surface")
      ->default_str("free");
  sub->add_flag("--planarize", d.planarize,
                "ShapeUp planarity projection instead of regularization (not with "
                "--no-regularize: an error)");
  sub->add_option("--restretch", d.options.regularize_options.restretch,
                  "regularization: how much of each cell's stretch its target keeps, 0 (regular "
                  "polygons) … 1 (the paper's stretched regular polygons)")
      ->default_str("0.7")
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--size-evening", d.options.regularize_options.size_evening,
                  "regularization: how far cell sizes are evened out, 0 (keep the density "
                  "field's sizes) … 1 (pull all towards their mean); evening makes beam lengths "
                  "uniform but gives back stiffness: 0 for structure-first designs")
      ->default_str("0.8")
      ->check(CLI::Range(0.0, 1.0));
  sub->add_option("--analyze", d.analyze, "none | linear | buckling | nonlinear")
      ->default_str("nonlinear");
  sub->add_option("--area-load", d.options.frame.area_load_kN_m2,
                  "analysis: extra panel/snow load in kN/m² on top of the bars' weight")
      ->default_str("0");
  sub->add_option("--elements", d.options.frame.elements, "analysis: beam elements per bar")
      ->default_str("2");
  sub->add_option("--diameter", d.options.frame.diameter, "analysis: solid bar diameter (m)")
      ->default_str("0.037");
  sub->add_option("--displacement-limit", d.options.frame_analysis.displacement_limit,
                  "analysis: lambda_displacement_limit is the load factor at which the non-linear "
                  "path's largest displacement reaches this many metres (0 = span / 100)")
      ->default_str("0");
  add_load_check_options(sub, d.checks);
  add_member_options(sub, d.members);
  add_sizing_options(sub, d.sizing);
  sub->add_flag("--single-path", d.single_path,
                "non-linear analysis: follow only the perfect path (no lambda_imperfect; half "
                "the cost)");
  sub->add_option("--sheet", a->sheet,
                  "fabrication: sheet size WxH in metres on which the flattened panels are "
                  "nested (panels.svg)")
      ->default_str(fabrication::kDefaultSheet);
  sub->footer(
      "Default size when none of --radius/--cells/--length is given: 300 cells.\n"
      "Writes gridshell_raw.obj, gridshell.obj, gridshell.ply, gridshell.vtp, field.vtp,\n"
      "cells.csv, joints.csv, beams.csv, panels.csv, panels.svg, figures/*.png (top,\n"
      "perspective, field, buckling_mode, load_path: docs/figures.md), report.json,\n"
      "config.json and report.html (open it first: the 3D view, key figures and figures,\n"
      "offline) in the output folder.");
  exact.push_back(field);
  for (CLI::Option* o : exact) objective->excludes(o);
  add_surface_options(sub, a->surface_options);
  add_run_options(sub, a->run);
  add_figure_option(sub, a->run);
  sub->callback([a, sub, exact, &action] {
    a->search = std::none_of(exact.begin(), exact.end(), [](CLI::Option* o) { return o->count(); });
    action = [a, sub] { return run_design_cmd(*a, sub); };
  });
}

}  // namespace gridshell::app
