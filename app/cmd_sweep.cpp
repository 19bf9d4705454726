// gridshell sweep SURFACE --D 1:4 --A 1:4 --repeats 3 --length L [--shard K/N] -o DIR: the
// paper's tuning experiment. Every (D, A, repeat) case is designed at the same total length and
// analysed; cases run in parallel (TBB) and each has its own deterministic seed, so shards or
// thread counts never change a row.

#include <atomic>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <optional>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common.h"
#include "gridshell/core/error.h"
#include "gridshell/core/timings.h"
#include "gridshell/field/field_io.h"
#include "gridshell/figures/figures.h"
#include "gridshell/io/files.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/objective.h"
#include "gridshell/pipeline/sweep.h"
#include "mpi.h"

namespace gridshell::app {

namespace {

struct SweepArgs {
  std::string surface = kDefaultSurface;
  std::string D = "1:4", A = "1:4", shard;
  /// What every case shares (design's words: --field, the conventions, --analyze,
  /// --analysis-resolution, the load model, members, --single-path); a case sets D, A, seed.
  DesignSettings design;
  int repeats = 3;
  double length = 0;
  int cells = 0;
  SurfaceOptions surface_options;
  RunOptions run;
};

/// What every case shares (a case sets D, A and its seed), every option parsed and checked
/// before any work.
DesignOptions sweep_design_options(const SweepArgs& a) {
  if (!(a.length > 0) && a.cells <= 0)
    throw Error("--length", "give the common total beam length L (m) (or --cells N)");
  if (parse_frame_source(a.design.field))
    throw Error("--field", "a sweep takes stress | uniform | FILE");
  DesignSettings settings = a.design;
  settings.options.tessellation.length = a.length;
  settings.options.tessellation.cells = a.length > 0 ? 0 : a.cells;
  // with the default D = A: the cases' D and A are checked with the cases
  DesignOptions o = build_design_options(settings);
  for (const analysis::FileLoadCase& c : o.frame.load_cases)  // (names end up in sweep.csv)
    if (c.name.size() > SweepGoverning::kMaxLoadCaseName || c.name.find(',') != std::string::npos)
      throw Error("--load-case",
                  fmt::format("'{}': a sweep takes names of at most {} characters, no commas",
                              c.name, SweepGoverning::kMaxLoadCaseName));
  // The paper's table reads δ and λ only: with `nonlinear` that is the perfect path to its first
  // critical point (no imperfect path, no steps past it: arc_length stops there), so the
  // stability block's second path is not asked for. The Eurocode verdict is design's, which
  // follows the imperfect paths too (unless --single-path, as in design).
  o.frame_analysis.stability =
      o.frame.loads == analysis::LoadModel::eurocode && !a.design.single_path;
  o.frame_analysis.imperfection = false;
  o.frame_analysis.path_goal = analysis::PathGoal::critical;
  return o;
}

/// One case's row, and the seconds of its stages.
struct CaseRun {
  SweepRow row;
  Timings timings;
};

/// Designs case `c` (`base` with its D, A and seed) and analyses it; with --loads eurocode
/// judges it by design's rule: every combination (combinations_block) and the governing
/// verdicts (governing_block), as `gridshell design` writes them in report.json.
CaseRun run_case(const Surface& surface, const DesignOptions& base, const SweepCase& c,
                 const GivenStress* stress, DesignCache& cache) {
  DesignOptions o = base;
  o.field_options.D = c.D, o.field_options.A = c.A;
  o.tessellation.seed = c.seed;
  const DesignResult r = stress ? run_design(surface, o, *stress, cache)
                                : run_design(surface, o, cache);
  CaseRun out;
  out.row.c = c;
  out.row.cells = r.mesh.num_faces();
  out.row.total_length = r.metrics.total_length;
  warn_if_length_missed(r.metrics.total_length, o.tessellation.length,
                        o.tessellation.length_tolerance,
                        fmt::format("case D = {:g}, A = {:g}, repeat {}", c.D, c.A, c.repeat));
  for (const auto& [stage, seconds] : r.timings) out.timings.add("cases_" + stage, seconds);
  if (!r.structure) return out;
  out.row.delta = r.structure->delta_max_m;
  out.row.lambda =
      r.structure->lambda_nonlinear.value_or(r.structure->lambda_linear_buckling.value_or(0.0));
  for (const auto& [stage, seconds] : r.structure->timings)
    if (stage != "total") out.timings.add("cases_analysis_" + stage, seconds);
  if (o.frame.loads != analysis::LoadModel::eurocode) return out;
  Stopwatch watch;
  const nlohmann::json combinations =
      combinations_block(r.mesh, r.supports, o.frame, o.frame_analysis, *r.structure);
  out.row.governing = sweep_governing(governing_block(combinations));
  out.timings.add("cases_combinations", watch.seconds());
  return out;
}

/// The log line of a finished case.
std::string case_summary(const SweepRow& row) {
  std::string s = fmt::format("lambda = {:.4g}, delta = {:.4g} m", row.lambda, row.delta);
  const SweepGoverning& g = row.governing;
  if (!g.judged) return s;
  if (g.utilisation.known) s += fmt::format(", utilisation {:.3g}", g.utilisation.value);
  if (g.lambda.known) s += fmt::format(", governing lambda {:.4g}", g.lambda.value);
  if (g.delta.known) s += fmt::format(", governing delta {:.4g} m", g.delta.value);
  return s + (g.pass ? ": pass" : ": fail");
}

int run_sweep_cases(const SweepArgs& a, const CLI::App* sub, const MpiSession& mpi) {
  RunOptions run = a.run;
  if (mpi.active() && run.threads == 0) run.threads = mpi.threads_per_rank();
  const auto guard = apply_run_options(run);
  const Stopwatch total;
  DesignOptions options = sweep_design_options(a);
  std::vector<SweepCase> cases =
      sweep_cases(parse_range(a.D, "--D"), parse_range(a.A, "--A"), a.repeats, a.run.seed);
  for (const auto& c : cases)
    if (c.D < 1 || c.A < 1) throw Error("--D/--A", "values must be ≥ 1");
  const std::size_t all = cases.size();
  if (!a.shard.empty()) cases = shard_cases(cases, a.shard);
  if (mpi.active()) {  // rank r takes every size-th case of the (sharded) list
    std::vector<SweepCase> mine;
    for (std::size_t i = static_cast<std::size_t>(mpi.rank()); i < cases.size();
         i += static_cast<std::size_t>(mpi.size()))
      mine.push_back(cases[i]);
    cases = std::move(mine);
  }
  const Surface surface = load_surface(a.surface, a.surface_options);
  attach_load_case_surface(options.frame, surface.mesh);
  // What does not change between cases is computed once: the analysis surface and the stress
  // (or the file's), and per (D, A) the field and M′ (the repeats differ only in the seed).
  DesignCache cache;
  std::optional<GivenStress> stress;
  if (options.field == FieldInput::file)
    stress = GivenStress{read_field_file(options.field_file, surface.mesh), {}};
  spdlog::info("[sweep] {} of {} cases on {}{}", cases.size(), all, a.surface,
               mpi.active() ? fmt::format(" (MPI rank {} of {})", mpi.rank(), mpi.size()) : "");
  std::atomic<int> finished{0};
  // Seconds per stage summed over this process's cases (thread-seconds: cases run in parallel),
  // the frame analysis split into its parts: where a sweep's time goes (docs/performance.md).
  Timings case_timings;
  std::mutex case_timings_mutex;
  const auto mine = run_sweep(cases, [&](const SweepCase& c) {
    const Stopwatch case_clock;
    CaseRun done = run_case(surface, options, c, stress ? &*stress : nullptr, cache);
    {
      const std::lock_guard<std::mutex> lock(case_timings_mutex);
      for (const auto& [stage, seconds] : done.timings) case_timings.add(stage, seconds);
    }
    const int k = ++finished;
    spdlog::info("[sweep] {}/{}: D = {}, A = {}, repeat {}: {} ({:.1f} s)", k, cases.size(), c.D,
                 c.A, c.repeat, case_summary(done.row), case_clock.seconds());
    report_progress(guard.progress, "sweep", static_cast<double>(k) / cases.size(),
                    fmt::format("{}/{} cases", k, cases.size()));
    return done.row;
  });
  const std::vector<SweepRow> rows = mpi.gather(mine);
  if (mpi.rank() != 0) return 0;  // rank 0 writes every output
  const std::filesystem::path dir(a.run.out_dir);
  io::ensure_directory(dir);
  io::write_file_atomic(dir / "sweep.csv", sweep_csv(rows));
  io::write_file_atomic(dir / "lambda.svg",
                        sweep_heatmap_svg(rows, "mean buckling factor λ over (D, A)",
                                          [](const SweepRow& r) { return r.lambda; }));
  io::write_file_atomic(dir / "delta.svg",
                        sweep_heatmap_svg(rows, "mean deflection δ (m) over (D, A)",
                                          [](const SweepRow& r) { return r.delta; }));
  nlohmann::json report;
  const Stopwatch figures_clock;
  report["figures"] = figures::write_sweep_figures(
      dir, rows,
      fmt::format(
          "gridshell sweep {}: D {}, A {}, repeats {}, {}; field {}; analysis {}; seed {}",
          a.surface, a.D, a.A, a.repeats,
          a.length > 0 ? fmt::format("length {:g} m", a.length) : fmt::format("{} cells", a.cells),
          a.design.field, a.design.analyze, a.run.seed),
      figures::parse_figure_options(a.run.figures));
  const double figures_s = figures_clock.seconds();
  report["surface"] = a.surface;
  report["loads"] = analysis::to_string(options.frame.loads);
  report["points"] = sweep_points_json(rows);
  report["cases"] = rows.size();
  report["cases_total"] = all;
  report["shard"] = a.shard.empty() ? "1/1" : a.shard;
  report["mpi_ranks"] = mpi.size();
  case_timings.add("figures", figures_s);
  case_timings.add("total", total.seconds());
  report["timings_s"] = case_timings;
  write_config(a.run.out_dir, sub);
  write_report(a.run.out_dir, report);
  return 0;
}

int run_sweep_cmd(const SweepArgs& a, const CLI::App* sub) {
  const MpiSession mpi;
  if (!mpi.active()) return run_sweep_cases(a, sub, mpi);
  // Under MPI a failing rank must end all of them, or the others wait forever in the gather.
  try {
    return run_sweep_cases(a, sub, mpi);
  } catch (const Error& e) {
    std::cerr << "gridshell: error: " << e.message() << "\n";
    mpi.abort(2);
  } catch (const std::exception& e) {
    std::cerr << "gridshell: internal error: " << e.what() << "\n";
    mpi.abort(1);
  }
}

}  // namespace

void register_sweep(CLI::App& app, Action& action) {
  auto a = std::make_shared<SweepArgs>();
  CLI::App* sub = app.add_subcommand(
      "sweep", "The tuning experiment: designs over a (D, A) grid at equal length, analysed");
  sub->add_option("surface", a->surface, "PLY/OBJ/OFF file or builtin:NAME")
      ->default_str(kDefaultSurface);
  DesignSettings& d = a->design;
  // -D/-A as in design, --D/--A as the CONTRACT spells them here: both accepted.
  sub->add_option("--D,-D", a->D, "density ratios a:b[:step]")->default_str("1:4");
  sub->add_option("--A,-A", a->A, "anisotropy ratios a:b[:step]")->default_str("1:4");
  sub->add_option("--repeats", a->repeats, "repeats per (D, A) with different seeds")
      ->default_str("3");
  sub->add_option("--length", a->length, "common total beam length (m)");
  sub->add_option("--cells", a->cells, "number of cells instead of --length");
  sub->add_option("--shard", a->shard, "K/N: run only shard K of N (cases K-1, K-1+N, ...)");
  sub->add_option("--field", d.field, "stress | uniform | FILE (as in design)")
      ->default_str(d.field);
  add_field_convention_options(sub, d);
  add_member_options(sub, d.members);
  sub->add_option("--analyze", d.analyze, "linear | buckling | nonlinear")->default_str(d.analyze);
  sub->add_option("--analysis-resolution", d.resolution, "cells | input (as in design)")
      ->default_str(d.resolution);
  add_load_check_options(sub, d.checks);
  sub->add_flag("--single-path", d.single_path,
                "--loads eurocode: follow only the perfect non-linear path (as design "
                "--single-path; without it each case is judged with the imperfect paths too)");
  sub->footer(
      "Writes sweep.csv (D,A,repeat,seed,cells,total_length,lambda,delta; with --loads\n"
      "eurocode also governing_utilisation,governing_lambda,governing_delta,pass and the\n"
      "governing combinations: each case judged as design judges it), lambda.svg,\n"
      "delta.svg, figures/lambda_heatmap.png, figures/delta_heatmap.png, report.json (points:\n"
      "the rows, with design's structure.governing block per case) and config.json.\n"
      "Under `mpirun -n K` (MPI build) the ranks share\n"
      "the cases and rank 0 writes the outputs; rows equal those of a single process.");
  add_surface_options(sub, a->surface_options);
  add_run_options(sub, a->run);
  add_figure_option(sub, a->run);
  sub->callback([a, sub, &action] { action = [a, sub] { return run_sweep_cmd(*a, sub); }; });
}

}  // namespace gridshell::app
