#pragma once
/// \file common.h
/// What every subcommand shares: the registration signature, surface options, output folder,
/// seed/threads/quiet, config.json writing, and report helpers.

#include <functional>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/core/progress.h"
#include "gridshell/pipeline/structure.h"
#include "gridshell/report/report_html.h"
#include "gridshell/surfaces/load.h"

namespace gridshell::app {

/// A subcommand's body; returns the process exit status. Errors are thrown as gridshell::Error.
using Action = std::function<int()>;

/// Options shared by the subcommands that write results.
struct RunOptions {
  std::string out_dir = "gridshell_out";
  std::uint64_t seed = 1;
  int threads = 0;  ///< 0 = all cores
  bool quiet = false;
  std::string figures = "1600x1200";  ///< --figures WxH | none (commands that draw figures)
};

void add_surface_options(CLI::App* sub, SurfaceOptions& options);
void add_run_options(CLI::App* sub, RunOptions& options);
/// --figures WxH|none: the size of the PNGs in DIR/figures/ (checked by apply_run_options).
void add_figure_option(CLI::App* sub, RunOptions& options);

/// The load model and member-check options of the commands that analyse a grid-shell (design,
/// analyze, baseline): --steel, --loads, --glass, --snow, --deflection-limit (docs/checks.md).
struct LoadCheckOptions {
  std::string steel = "S355";     ///< S235 | S275 | S355
  std::string loads;              ///< paper | eurocode; empty = paper, or eurocode with --size
  double glass = 0.4;             ///< eurocode G2 [kN/m² of surface]
  double snow = 1.0;              ///< eurocode Q: s_k [kN/m² of plan]
  double deflection_limit = 300;  ///< δ passes when at most span / this
  std::vector<std::string> load_cases;  ///< --load-case NAME=FILE.csv (repeatable)
};
void add_load_check_options(CLI::App* sub, LoadCheckOptions& options);
/// The members (docs/checks.md): --section "CHS 88.9x4.0" | "RHS 120x60x4" | "SHS 100x5" |
/// "bar 37" [cold] (sections/sections.h; empty = the solid bar of --diameter) and
/// --buckling-length-factor F (L_cr = F × member length, default 1).
struct MemberOptions {
  std::string section;
  double buckling_length_factor = 1;
};
void add_member_options(CLI::App* sub, MemberOptions& options);
/// Checks them (Error naming the option, exit 2, before any work) and sets frame.section and
/// analysis.checks.buckling_length_factor.
void apply_member_options(const MemberOptions& options, analysis::GridshellFrameOptions& frame,
                          analysis::FrameAnalysisOptions& analysis);
/// Parses and checks them (Error naming the option) and sets `frame`'s load model (no --loads:
/// eurocode when `sized`, else paper), glass, snow and file load cases (read here: a bad file is
/// an Error before any work), and `analysis`'s fy and deflection limit.
void apply_load_check_options(const LoadCheckOptions& options,
                              analysis::GridshellFrameOptions& frame,
                              analysis::FrameAnalysisOptions& analysis, bool sized = false);

/// Member sizing (docs/sizing.md): --size, --sections chs|rhs|bar|'chs cold'|FILE,
/// --section-groups N, --lambda-min, --carbon-factor.
struct SizingArgs {
  bool size = false;
  std::string sections = "chs";
  int groups = 0;
  double lambda_min = 1.0;
  double carbon_factor = 1.55;  ///< kgCO2e/kg (pipeline/structure.h kSteelCarbonFactor)
};
void add_sizing_options(CLI::App* sub, SizingArgs& options);
/// Checks them (Error naming the option, exit 2) and sets `structure`'s sizing mode and options
/// (the section list read here).
void apply_sizing_options(const SizingArgs& options, StructureOptions& structure);

/// Gives the file load cases on the input surface's vertices that surface (checks the ids).
void attach_load_case_surface(analysis::GridshellFrameOptions& frame, const TriMesh& surface);

/// What a run holds while it works: the thread limit, and the progress display on stderr.
struct RunGuard {
  std::shared_ptr<void> threads;
  Progress progress;  ///< for the library's options; empty with --quiet
};

/// Applies --threads and --quiet (logging level, progress) for the duration of a run.
RunGuard apply_run_options(const RunOptions& options);

/// The resolved parameters of `sub` (every option with its value), as written to config.json.
nlohmann::json resolved_config(const CLI::App* sub);

/// Writes DIR/config.json for `sub`, and DIR/report.json from `report`.
void write_config(const std::string& dir, const CLI::App* sub);
void write_report(const std::string& dir, const nlohmann::json& report);

/// Writes DIR/report.html (report/report_html.h) from `page` with `report` (report.json) and the
/// resolved config of `sub`; call it last, after the figures. Logs its size and time.
void write_report_page(const std::string& dir, report::ReportInput page,
                       const nlohmann::json& report, const CLI::App* sub);

/// Expands `--config FILE` in argv: options stored in FILE and not given on the command line are
/// appended. Throws Error for a bad file.
std::vector<std::string> expand_config(const std::vector<std::string>& args, const CLI::App& cli);

// Subcommand registration: each adds its CLI11 subcommand and sets `action` when chosen.
void register_info(CLI::App& app, Action& action);
void register_stress(CLI::App& app, Action& action);
void register_design(CLI::App& app, Action& action);
void register_analyze(CLI::App& app, Action& action);
void register_sweep(CLI::App& app, Action& action);
void register_baseline(CLI::App& app, Action& action);
void register_studio(CLI::App& app, Action& action);

}  // namespace gridshell::app
