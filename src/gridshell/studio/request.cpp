#include "gridshell/studio/request.h"

#include <chrono>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "gridshell/core/error.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/pipeline/design_report.h"
#include "gridshell/pipeline/design_settings.h"
#include "gridshell/report/design_folder.h"
#include "gridshell/report/report_html.h"
#include "gridshell/surfaces/builtin.h"

namespace gridshell::studio {

namespace {

/// The largest cell count a request may ask for (a design of 5000 cells takes about a minute).
constexpr int kMaxCells = 5000;
/// The largest D and A (the page's sliders end at 4; the objective search's at 4 too).
constexpr double kMaxRatio = 10;

double parse_number(const std::string& text, const std::string& subject, const std::string& what) {
  std::size_t used = 0;
  double x = 0;
  try {
    x = std::stod(text, &used);
  } catch (const std::exception&) {
    throw Error(subject, what);
  }
  if (used != text.size() || !std::isfinite(x)) throw Error(subject, what);
  return x;
}

std::string number_text(double x) {
  return fmt::format("{}", x);
}

}  // namespace

StudioRequest parse_request(const Params& params) {
  std::map<std::string, std::string> p;
  for (const auto& [name, value] : params) p[name] = value;
  StudioRequest r;
  for (const auto& [name, value] : p) {
    if (name == "surface") {
      if (value.empty()) throw Error("surface", "no surface given");
      r.surface = value.rfind("builtin:", 0) == 0 ? "builtin:" + canonical_builtin(value.substr(8))
                                                  : value;
    } else if (name == "D") {
      r.D = parse_number(value, "-D", "must be a number ≥ 1");
      if (r.D > kMaxRatio) throw Error("-D", fmt::format("at most {} in the studio", kMaxRatio));
    } else if (name == "A") {
      r.A = parse_number(value, "-A", "must be a number ≥ 1");
      if (r.A > kMaxRatio) throw Error("-A", fmt::format("at most {} in the studio", kMaxRatio));
    } else if (name == "cells") {
      const double c = parse_number(value, "--cells", "must be positive");
      if (!(c >= 1) || c != std::floor(c)) throw Error("--cells", "must be positive");
      if (c > kMaxCells) throw Error("--cells", fmt::format("at most {} in the studio", kMaxCells));
      r.cells = static_cast<int>(c);
    } else if (name == "length") {
      r.length = parse_number(value, "--length", "must be positive");
      if (!(r.length > 0)) throw Error("--length", "must be positive");
    } else if (name == "objective") {
      if (!value.empty() && value != "none") r.objective = parse_objective(value);
    } else if (name == "symmetry") {
      r.symmetry = parse_symmetry(value);
    } else if (name == "panels") {
      r.panels = parse_panel_mode(value);
    } else if (name == "analyze") {
      r.analyze = analysis::parse_analysis_level(value);
    } else if (name == "seed") {
      const double s = parse_number(value, "--seed", "must be a whole number ≥ 0");
      if (!(s >= 0) || s != std::floor(s) || s > 9e15)
        throw Error("--seed", "must be a whole number ≥ 0");
      r.seed = static_cast<std::uint64_t>(s);
    } else {
      throw Error(name,
                  "unknown parameter (surface, D, A, cells, length, objective, symmetry, "
                  "panels, analyze, seed)");
    }
  }
  if (p.count("length") && p.count("cells"))
    throw Error("--radius/--cells/--length", "give at most one of them");
  if (r.length > 0) r.cells = 0;
  design_options(r);  // parses the rest and checks (build_design_options)
  return r;
}

void check_request_size(const StudioRequest& r, const Surface& surface) {
  if (!(r.length > 0)) return;
  const double area = surface_area(surface.mesh);
  const double D = r.objective ? std::max(r.D, 4.0) : r.D;
  const double max_length = std::sqrt(6 * area * kMaxCells / (std::sqrt(3.0) * D));
  if (r.length > max_length)
    throw Error("--length", fmt::format("at most {:.0f} m on this surface in the studio (about "
                                        "{} cells)",
                                        std::floor(max_length), kMaxCells));
}

std::string request_query(const StudioRequest& r) {
  std::string q = "surface=" + r.surface;
  if (r.objective) {
    q += std::string("&objective=") + to_string(*r.objective);
  } else {
    q += "&D=" + number_text(r.D) + "&A=" + number_text(r.A);
  }
  q += r.length > 0 ? "&length=" + number_text(r.length) : "&cells=" + std::to_string(r.cells);
  q += std::string("&symmetry=") + to_string(r.symmetry);
  if (r.panels == PanelMode::flat) q += "&panels=flat";
  q += std::string("&analyze=") + analysis::to_string(r.analyze);
  q += "&seed=" + std::to_string(r.seed);
  return q;
}

DesignOptions design_options(const StudioRequest& r) {
  // The command line's builder, so a request means what `gridshell design` with request_config
  // means.
  DesignSettings s;
  s.options.field_options.D = r.D;
  s.options.field_options.A = r.A;
  s.options.tessellation.cells = r.cells;
  s.options.tessellation.length = r.length;
  s.seed = r.seed;
  s.symmetry = to_string(r.symmetry);
  s.panels = to_string(r.panels);
  s.analyze = analysis::to_string(r.analyze);
  s.single_path = true;  // the studio follows the perfect path only (request_config says so)
  return build_design_options(s);
}

std::string design_cache_key(const StudioRequest& r) {
  StudioRequest shared = r;
  shared.D = shared.A = 1;
  shared.seed = 0;
  return request_query(shared);
}

StudioDesign design_request(const Surface& surface, const StudioRequest& request,
                            const StopRequest& stop, DesignCache* cache) {
  const auto start = std::chrono::steady_clock::now();
  StudioDesign d;
  d.request = request;
  DesignOptions options = design_options(request);
  if (request.objective) {
    ObjectiveOptions search;
    search.objective = *request.objective;
    search.stop = stop;
    d.search = design_for_objective(surface, options, search);
    d.result = std::move(d.search->design);
  } else {
    // The path's listener stops it at its next step (listening changes no result).
    if (stop)
      options.frame_analysis.arc.progress = [&stop](std::string_view, double, std::string_view) {
        if (stop()) throw Stopped{};
      };
    d.result = cache ? run_design(surface, options, *cache) : run_design(surface, options);
  }
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  d.report = design_report(d.result, design_options(request));
  d.report["surface"] = request.surface;
  if (d.search) d.report["objective"] = d.search->report();
  d.report["timings_s"] = timings_block(d.result.timings, {}, d.seconds);
  return d;
}

nlohmann::json request_config(const StudioRequest& r, const std::string& surface_arg) {
  nlohmann::json options = nlohmann::json::object();
  if (r.objective) {
    options["objective"] = to_string(*r.objective);
  } else {
    options["D"] = number_text(r.D);
    options["A"] = number_text(r.A);
  }
  if (r.length > 0) {
    options["length"] = number_text(r.length);
  } else {
    options["cells"] = std::to_string(r.cells);
  }
  options["symmetry"] = to_string(r.symmetry);
  if (r.panels == PanelMode::flat) options["panels"] = "flat";
  options["analyze"] = analysis::to_string(r.analyze);
  if (r.analyze == analysis::AnalysisLevel::nonlinear) options["single-path"] = true;
  options["seed"] = std::to_string(r.seed);
  return {{"command", "design"}, {"positional", {surface_arg}}, {"options", options}};
}

nlohmann::json design_answer(const StudioDesign& d, const std::string& surface_arg) {
  const DesignResult& r = d.result;
  const analysis::FrameResult* structure = r.structure ? &*r.structure : nullptr;
  report::ReportInput view = report::gridshell_report_input(r.mesh, r.supports, structure);
  view.density = r.d_target;
  view.report = d.report;
  view.config = request_config(d.request, surface_arg);
  view.title = "gridshell studio: " + surface_arg;

  nlohmann::json vertices = nlohmann::json::array();
  for (Eigen::Index v = 0; v < r.mesh.V.rows(); ++v)
    vertices.push_back({r.mesh.V(v, 0), r.mesh.V(v, 1), r.mesh.V(v, 2)});
  nlohmann::json beams = nlohmann::json::array();
  for (const auto& b : view.beams) beams.push_back({b[0], b[1]});
  nlohmann::json answer;
  answer["request"] = request_query(d.request);
  answer["mesh"] = {{"vertices", vertices}, {"faces", r.mesh.faces}, {"supports", r.supports}};
  answer["beams"] = beams;
  answer["axial_force"] = view.axial_force;  // [N] per beam, tension positive (empty: none)
  answer["report"] = d.report;
  answer["config"] = view.config;
  answer["view"] = nlohmann::json::parse(report::report_data_json(view, {}));
  return answer;
}

void write_design_folder(const std::filesystem::path& dir, const StudioDesign& d,
                         const Surface& surface, const std::string& surface_arg) {
  const DesignOptions options = design_options(d.request);
  report::DesignFolderInput folder;
  folder.surface = &surface;
  folder.options = &options;
  folder.result = &d.result;
  folder.search = d.search ? &*d.search : nullptr;
  folder.surface_name = d.request.surface;
  folder.title = fmt::format("gridshell studio {}: {}; {} cells, {:.0f} m of beams; seed {}",
                             surface_arg, request_query(d.request), d.result.mesh.num_faces(),
                             d.result.metrics.total_length, d.request.seed);
  folder.config = request_config(d.request, surface_arg);
  folder.seconds_before = d.seconds;
  report::write_design_folder(dir, folder);
}

}  // namespace gridshell::studio
