#include "common.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <thread>

#include <unistd.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>

#include "gridshell/core/error.h"
#include "gridshell/core/progress_display.h"
#include "gridshell/figures/figures.h"
#include "gridshell/io/files.h"
#include "gridshell/io/json.h"
#include "gridshell/report/design_folder.h"

namespace gridshell::app {

void add_surface_options(CLI::App* sub, SurfaceOptions& o) {
  sub->add_option("--supports", o.supports,
                  "red | boundary | FILE.json (list of vertex ids); default: red vertices if the "
                  "file has any, else the built-in's own, else the whole boundary")
      ->default_str("auto");
  sub->add_option("--up", o.up, "the input's up axis: z, y or -y")->default_str("z");
  sub->add_option("--scale", o.scale, "multiply input coordinates by S")->default_str("1");
}

void add_run_options(CLI::App* sub, RunOptions& o) {
  sub->add_option("-o,--out", o.out_dir, "output folder (created if missing)")
      ->default_str(o.out_dir);
  sub->add_option("--seed", o.seed, "random seed: same inputs and seed give identical outputs")
      ->default_str("1");
  sub->add_option("--threads", o.threads, "worker threads (0 = all cores)")->default_str("0");
  sub->add_flag("--quiet", o.quiet, "no progress on stderr");
  sub->add_option("--config", "repeat a run: read options from a config.json written earlier");
}

void add_figure_option(CLI::App* sub, RunOptions& o) {
  sub->add_option("--figures", o.figures,
                  "size WxH in pixels of the PNG figures in DIR/figures/, or none")
      ->default_str(o.figures);
}

void add_load_check_options(CLI::App* sub, LoadCheckOptions& o) {
  sub->add_option("--steel", o.steel, "member checks: steel grade S235 | S275 | S355")
      ->default_str(o.steel);
  // No default string: config.json then leaves --loads out, and --config resolves it alike.
  sub->add_option("--loads", o.loads,
                  "grid-shell analysis: paper (the bars' weight spread over the surface, + "
                  "--area-load) | eurocode (G1 bars, G2 --glass, Q --snow; structure = ULS "
                  "1.35 G + 1.5 Q, combinations adds SLS G + Q); default paper, eurocode with "
                  "--size");
  sub->add_option("--glass", o.glass, "--loads eurocode: glass and cladding in kN/m² of surface")
      ->default_str("0.4");
  sub->add_option("--snow", o.snow,
                  "--loads eurocode: characteristic snow s_k in kN/m² of plan (times the shape "
                  "factor of the roof slope)")
      ->default_str("1.0");
  sub->add_option("--load-case", o.load_cases,
                  "--loads eurocode: a load case from a file, NAME=FILE.csv (repeatable; "
                  "NAME:permanent=FILE.csv for a permanent one): vertex,pressure_kN_m2 on the "
                  "input surface's vertices (analyze also joint,fx_kN,fy_kN,fz_kN or "
                  "panel,pressure_kN_m2); pressure normal to the roof, positive pushing onto it; "
                  "variable (psi0 0.6, gamma_Q 1.5) unless marked (docs/checks.md)");
  sub->add_option("--deflection-limit", o.deflection_limit,
                  "serviceability: delta passes when at most span / this (span = largest plan "
                  "extent)")
      ->default_str("300");
}

void add_member_options(CLI::App* sub, MemberOptions& o) {
  sub->add_option("--section", o.section,
                  "member section: 'CHS 88.9x4.0', 'RHS 120x60x4', 'SHS 100x5', 'bar 37' (mm; "
                  "add 'cold' for cold-formed EN 10219, default hot-finished EN 10210); default "
                  "the solid bar of --diameter");
  sub->add_option("--buckling-length-factor", o.buckling_length_factor,
                  "member checks: buckling length = this × member length (joint to joint)")
      ->default_str("1");
}

void add_sizing_options(CLI::App* sub, SizingArgs& o) {
  sub->add_flag("--size", o.size,
                "size every member to EN 1993-1-1: the lightest section of --sections passing "
                "every check, delta and lambda under every combination (docs/sizing.md)");
  sub->add_option("--sections", o.sections,
                  "--size: the sections to choose from: chs | rhs | bar | 'chs cold' | "
                  "'rhs cold' | FILE (one designation per line)")
      ->default_str("chs");
  sub->add_option("--section-groups", o.groups,
                  "--size: at most this many distinct sections (0: each member its own)")
      ->default_str("0");
  sub->add_option("--lambda-min", o.lambda_min,
                  "--size: smallest critical load factor of every ULS combination")
      ->default_str("1");
  sub->add_option("--carbon-factor", o.carbon_factor,
                  "embodied carbon of the steel in kgCO2e/kg (default: ICE v3.0, steel "
                  "section, world average)")
      ->default_str(fmt::format("{}", o.carbon_factor));
}

std::vector<CLI::Option*> add_field_ratio_options(CLI::App* sub, FieldOptions& field,
                                                  const std::string& prefix) {
  return {
      sub->add_option("-D,--D", field.D,
                      prefix + "density ratio: the densest cells are D× smaller across")
          ->default_str(fmt::format("{}", field.D)),
      sub->add_option("-A,--A", field.A, prefix + "anisotropy ratio: cells up to A× longer along u")
          ->default_str(fmt::format("{}", field.A))};
}

std::vector<CLI::Option*> add_field_convention_options(CLI::App* sub, DesignSettings& d,
                                                       const std::string& prefix) {
  return {sub->add_option("--stress-measure", d.measure,
                          prefix + "magnitude (the paper) | tension (compression counts as none) | "
                                   "compression (tension counts as none): which stress drives u, d "
                                   "and a")
              ->default_str(d.measure),
          sub->add_option("--stretch", d.stretch,
                          prefix + "along (the paper) | across: cells long along u or across it")
              ->default_str(d.stretch),
          sub->add_option("--density,--density-trend", d.density,
                          prefix + "rising (the paper) | falling: small cells where the stress is "
                                   "high, or where it is low (--density-trend: the same option)")
              ->default_str(d.density)};
}

RunGuard apply_run_options(const RunOptions& o) {
  if (o.threads < 0) throw Error("--threads", "must be ≥ 0");
  figures::parse_figure_options(o.figures);
  const std::size_t n = o.threads > 0 ? static_cast<std::size_t>(o.threads)
                                      : std::max(1u, std::thread::hardware_concurrency());
  RunGuard guard;
  guard.threads =
      std::make_shared<tbb::global_control>(tbb::global_control::max_allowed_parallelism, n);
  // GRIDSHELL_PROGRESS_AFTER: seconds a stage runs before it is shown (default 1; tests use 0
  // so that what they check does not depend on how fast the machine is).
  double show_after = 1.0;
  if (const char* e = std::getenv("GRIDSHELL_PROGRESS_AFTER")) {
    char* end = nullptr;
    const double v = std::strtod(e, &end);
    if (end != e && *end == '\0' && std::isfinite(v) && v >= 0) show_after = v;
  }
  auto display =
      std::make_shared<ProgressDisplay>(stderr, isatty(fileno(stderr)) != 0, show_after);
  auto logger = std::make_shared<spdlog::logger>("gridshell", log_sink(display));
  logger->set_pattern("%v");
  logger->set_level(o.quiet ? spdlog::level::warn : spdlog::level::info);
  if (std::getenv("GRIDSHELL_DEBUG_LOG") != nullptr) logger->set_level(spdlog::level::debug);
  spdlog::set_default_logger(logger);
  if (!o.quiet) guard.progress = ProgressDisplay::callback(display);
  return guard;
}

nlohmann::json resolved_config(const CLI::App* sub) {
  nlohmann::json options = nlohmann::json::object();
  nlohmann::json positional = nlohmann::json::array();
  for (const CLI::Option* opt : sub->get_options()) {
    const std::string name = opt->get_single_name();
    if (name == "help" || name == "config") continue;
    if (opt->get_positional()) {
      for (const auto& r : opt->results()) positional.push_back(r);
      continue;
    }
    if (opt->get_type_size() == 0 || opt->get_expected_max() == 0) {  // a flag
      options[name] = opt->count() > 0;
    } else if (opt->count() > 0) {
      options[name] = opt->results().size() == 1 ? nlohmann::json(opt->results()[0])
                                                 : nlohmann::json(opt->results());
    } else if (!opt->get_default_str().empty() && opt->get_excludes().empty()) {
      // (Options that exclude others, e.g. --objective and -D, are written only when given:
      // their defaults together would not parse again.)
      options[name] = opt->get_default_str();
    }
  }
  return {{"command", sub->get_name()}, {"positional", positional}, {"options", options}};
}

void write_config(const std::string& dir, const CLI::App* sub) {
  io::write_file_atomic(std::filesystem::path(dir) / "config.json",
                        resolved_config(sub).dump(2) + "\n");
}

void warn_if_panels_kept_free(const nlohmann::json& flat_info) {
  if (flat_info.is_object() && flat_info.value("panels", "") == std::string("free"))
    spdlog::warn("{}: keeping the free panels",
                 flat_info.value("failure", std::string("--panels flat")));
}

void warn_if_length_missed(double total_length, double target, double tolerance,
                           const std::string& what) {
  if (!(target > 0) || !(total_length > 0)) return;
  const double miss = total_length / target - 1;
  if (std::abs(miss) > tolerance)
    spdlog::warn(
        "--length {:.6g} m: {} has {:.6g} m of beams ({:+.1f} %, beyond the {:.0f} % tolerance)",
        target, what.empty() ? "the grid-shell" : what, total_length, 100 * miss, 100 * tolerance);
}

void write_report(const std::string& dir, const nlohmann::json& report) {
  io::write_file_atomic(std::filesystem::path(dir) / "report.json", report.dump(2) + "\n");
}

void write_report_page(const std::string& dir, report::ReportInput page,
                       const nlohmann::json& report, const CLI::App* sub) {
  report::write_report_page(dir, std::move(page), report, resolved_config(sub));
}

std::vector<std::string> expand_config(const std::vector<std::string>& args, const CLI::App& cli) {
  std::string path;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--config" && i + 1 < args.size()) path = args[i + 1];
    if (args[i].rfind("--config=", 0) == 0) path = args[i].substr(9);
  }
  if (path.empty()) return args;
  nlohmann::json cfg;
  try {
    cfg = io::parse_json(io::read_file(path), path);
  } catch (const nlohmann::json::exception&) {
    throw Error(path, "not a valid config.json");
  }
  if (!cfg.is_object() || !cfg.contains("options") || !cfg["options"].is_object())
    throw Error(path, "not a gridshell config.json (no \"options\" object)");
  std::vector<std::string> out;
  bool has_command = args.size() > 1 && args[1].rfind('-', 0) != 0;
  out.push_back(args.empty() ? "gridshell" : args[0]);
  if (!has_command && cfg.contains("command")) out.push_back(cfg["command"].get<std::string>());
  std::vector<std::string> given(args.begin() + 1, args.end());
  // Drop --config itself.
  std::vector<std::string> kept;
  for (std::size_t i = 0; i < given.size(); ++i) {
    if (given[i] == "--config") {
      ++i;
      continue;
    }
    if (given[i].rfind("--config=", 0) == 0) continue;
    kept.push_back(given[i]);
  }
  out.insert(out.end(), kept.begin(), kept.end());
  const std::string command = out.size() > 1 ? out[1] : "";
  const CLI::App* sub = nullptr;
  for (const CLI::App* s : cli.get_subcommands([](const CLI::App*) { return true; }))
    if (s->get_name() == command) sub = s;
  if (!sub) throw Error(path, fmt::format("config is for an unknown command '{}'", command));
  auto is_given = [&](const std::string& name) {
    const CLI::Option* opt = sub->get_option_no_throw("--" + name);
    if (!opt) opt = sub->get_option_no_throw("-" + name);
    std::vector<std::string> flags;
    if (opt) {
      for (const auto& l : opt->get_lnames()) flags.push_back("--" + l);
      for (const auto& sn : opt->get_snames()) flags.push_back("-" + sn);
    } else {
      flags.push_back("--" + name);
    }
    for (const auto& a : kept)
      for (const auto& f : flags)
        if (a == f || a.rfind(f + "=", 0) == 0) return true;
    return false;
  };
  // Positional arguments: only if none was given after the command.
  std::size_t positional_given = 0;
  for (std::size_t i = 1; i < kept.size(); ++i)
    if (kept[i].rfind('-', 0) != 0 && (kept[i - 1].rfind('-', 0) != 0 || i == 1))
      ++positional_given;
  if (kept.size() <= 1 || positional_given == 0)
    if (cfg.contains("positional"))
      for (const auto& p : cfg["positional"]) out.push_back(p.get<std::string>());
  for (const auto& [name, value] : cfg["options"].items()) {
    if (is_given(name)) continue;
    // A one-letter name is a short flag (design's -D) unless the command has it as a long one
    // (sweep's --D).
    const bool is_short = name.size() == 1 && sub->get_option_no_throw("--" + name) == nullptr;
    const std::string flag = is_short ? "-" + name : "--" + name;
    if (value.is_boolean()) {
      if (value.get<bool>()) out.push_back(flag);
    } else if (value.is_array()) {
      for (const auto& v : value) {
        out.push_back(flag);
        out.push_back(v.is_string() ? v.get<std::string>() : v.dump());
      }
    } else {
      out.push_back(flag);
      out.push_back(value.is_string() ? value.get<std::string>() : value.dump());
    }
  }
  return out;
}

}  // namespace gridshell::app
