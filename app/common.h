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
#include "gridshell/pipeline/design_settings.h"
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

/// The CLI11 options of the load model and member checks (pipeline/design_settings.h):
/// --steel, --loads, --glass, --snow, --deflection-limit, --load-case.
void add_load_check_options(CLI::App* sub, LoadCheckOptions& options);
/// --section, --buckling-length-factor.
void add_member_options(CLI::App* sub, MemberOptions& options);
/// --size, --sections, --section-groups, --lambda-min, --carbon-factor.
void add_sizing_options(CLI::App* sub, SizingArgs& options);

/// -D/--D and -A/--A (both spellings, in design, baseline and sweep): the field's density and
/// anisotropy ratios, stored in `field` (FieldOptions::D, A: their one place). `prefix` starts
/// the help (e.g. "quad-aniso: "). Returns the two options.
std::vector<CLI::Option*> add_field_ratio_options(CLI::App* sub, FieldOptions& field,
                                                  const std::string& prefix = "");
/// The field's conventions into `design`'s words: --stress-measure, --stretch and
/// --density-trend (also spelt --density, as before; `stress --density` is the shell's mass
/// density, there also spelt --material-density). Returns the three options.
std::vector<CLI::Option*> add_field_convention_options(CLI::App* sub, DesignSettings& design,
                                                       const std::string& prefix = "");

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

/// One warning when the written grid-shell asked for flat panels and kept its free ones:
/// `flat_info` is report.json's `flat_panels` (design.flat_panels for `design`). The flat stage
/// itself logs at info level, so the objective search's other candidates stay quiet.
void warn_if_panels_kept_free(const nlohmann::json& flat_info);

/// Warns, once per command, when the grid-shell's total beam length misses `--length` (target
/// > 0) by more than `tolerance` (relative): a target shorter than the boundary and the fewest
/// cells allow, or longer than the surface's mesh can carry. `what` names the grid-shell when a
/// command writes several (a sweep's case); empty: the command's one.
void warn_if_length_missed(double total_length, double target, double tolerance,
                           const std::string& what = {});

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
