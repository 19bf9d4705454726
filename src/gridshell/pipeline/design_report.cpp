#include "gridshell/pipeline/design_report.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "gridshell/analysis/combination_runs.h"
#include "gridshell/core/error.h"
#include "gridshell/fabrication/fabrication_files.h"
#include "gridshell/pipeline/buildability_report.h"
#include "gridshell/pipeline/frame_output.h"
#include "gridshell/pipeline/structure.h"
#include "gridshell/sections/sections.h"

namespace gridshell {

namespace {
nlohmann::json optional_number(const std::optional<double>& v) {
  return v && std::isfinite(*v) ? nlohmann::json(*v) : nlohmann::json(nullptr);
}
}  // namespace

namespace {
/// structure.imperfection: the unfavourable imperfection's mode (1-based, as modes.csv), sign,
/// amplitude, every one tried, and the note when λ_imperfect > λ_perfect.
nlohmann::json imperfection_block(const analysis::FrameResult& r) {
  nlohmann::json imp;
  imp["mode"] = r.imperfection_mode + 1;
  imp["sign"] = r.imperfection_sign;
  imp["amplitude_m"] = r.imperfection_amplitude_m;
  nlohmann::json tried = nlohmann::json::array();
  for (const auto& t : r.imperfections_tried) {
    tried.push_back(
        {{"mode", t.mode + 1}, {"sign", t.sign}, {"lambda", optional_number(t.lambda)}});
    if (t.lambda_above) tried.back()["lambda_above"] = *t.lambda_above;
  }
  imp["tried"] = tried;
  if (!r.imperfection_note.empty()) imp["note"] = r.imperfection_note;
  return imp;
}
}  // namespace

nlohmann::json structure_block(const analysis::FrameResult& r) {
  nlohmann::json st;
  st["delta_max_m"] = r.delta_max_m;
  st["lambda_linear_buckling"] = optional_number(r.lambda_linear_buckling);
  st["lambda_nonlinear"] = optional_number(r.lambda_nonlinear);
  st["limit_type"] = fem::to_string(r.limit_type);
  st["lambda_displacement_limit"] = optional_number(r.lambda_displacement_limit);
  st["displacement_limit_m"] =
      r.displacement_limit_m > 0 ? nlohmann::json(r.displacement_limit_m) : nlohmann::json();
  st["mass_kg"] = r.mass_kg;
  st["total_length_m"] = r.total_length_m;
  st["buckling_lambdas"] = r.buckling_lambdas;
  st["delta_node"] = r.delta_node;
  st["equilibrium_error"] = r.equilibrium_error;
  st["nonlinear_stop_reason"] = r.nonlinear_stop_reason;
  st["elements"] = r.num_elements;
  st["dofs"] = r.num_dofs;
  st["timings_s"] = r.timings;
  add_checks_block(st, r);
  if (r.imperfection_mode >= 0) st["imperfection"] = imperfection_block(r);
  return st;
}

void add_checks_block(nlohmann::json& st, const analysis::FrameResult& r) {
  // Serviceability.
  st["span_m"] = r.span_m;
  st["delta_limit_m"] = r.delta_limit_m;
  st["delta_pass"] = r.delta_pass;
  // Member checks (linear, λ = 1).
  const checks::MemberChecks& c = r.checks;
  st["utilisation_max"] = c.section_max;
  st["utilisation_beam"] =
      c.section_worst >= 0 ? nlohmann::json(c.section_worst) : nlohmann::json();
  st["buckling_utilisation_max"] = c.buckling_max;
  st["buckling_utilisation_beam"] =
      c.buckling_worst >= 0 ? nlohmann::json(c.buckling_worst) : nlohmann::json();
  // The EN 1993-1-1 clause that governs each (checks/member_checks.h, hollow_checks.h).
  st["utilisation_check"] = c.section_governing;
  st["buckling_check"] = c.buckling_governing;
  // Stability: read together (λ_LBA alone overstates a grid-shell's capacity).
  st["lambda_lba"] = optional_number(r.lambda_linear_buckling);
  st["lambda_perfect"] = optional_number(r.lambda_perfect);
  st["lambda_imperfect"] = optional_number(r.lambda_imperfect);
  st["imperfection_sensitivity"] = r.lambda_perfect && r.lambda_imperfect && *r.lambda_perfect > 0
                                       ? nlohmann::json(*r.lambda_imperfect / *r.lambda_perfect)
                                       : nlohmann::json();
  st["imperfection_amplitude_m"] =
      r.lambda_imperfect ? nlohmann::json(r.imperfection_amplitude_m) : nlohmann::json();
  st["lambda_y"] = optional_number(r.lambda_yield);
  const bool path = !r.lambda_yield_path.empty();
  st["lambda_y_path"] = path ? nlohmann::json(r.lambda_yield_path) : nlohmann::json();
  st["path_utilisation_max"] = path ? nlohmann::json(r.path_utilisation_max) : nlohmann::json();
  st["lambda_y_perfect"] = optional_number(r.lambda_yield_perfect);
  st["lambda_y_linear"] = optional_number(r.lambda_yield_linear);
}

nlohmann::json combination_block(const analysis::FrameResult& r, double gamma_g, double gamma_q) {
  nlohmann::json all = nlohmann::json::object();
  add_checks_block(all, r);
  nlohmann::json c;
  c["gamma_G"] = gamma_g;
  c["gamma_Q"] = gamma_q;
  c["delta_max_m"] = r.delta_max_m;
  for (const char* key :
       {"delta_limit_m", "delta_pass", "utilisation_max", "utilisation_beam",
        "buckling_utilisation_max", "buckling_utilisation_beam", "lambda_lba", "lambda_perfect",
        "lambda_imperfect", "imperfection_sensitivity", "lambda_y", "lambda_y_path",
        "path_utilisation_max", "lambda_y_perfect", "lambda_y_linear"})
    c[key] = all[key];
  return c;
}

namespace {
/// One eurocode combination's block: the figures of `r`, its factors, and its governing λ.
nlohmann::json eurocode_block(const analysis::LoadCombination& c, const analysis::FrameResult& r,
                              bool nonlinear) {
  double gamma_g = 0, gamma_q = 0;
  for (const auto& [name, f] : c.factors) {
    if (name == "G1") gamma_g = f;
    if (name == c.leading) gamma_q = f;
  }
  nlohmann::json b = combination_block(r, gamma_g, gamma_q);
  b["uls"] = c.uls;
  b["leading"] = c.leading;
  for (const auto& [name, f] : c.factors) b["factors"][name] = f;
  if (c.uls) {
    const auto [lambda, source] = analysis::combination_lambda(r);
    b["lambda"] = optional_number(lambda);
    b["lambda_source"] = source;
    b["nonlinear_followed"] = nonlinear;
    if (r.imperfection_mode >= 0) b["imperfection"] = imperfection_block(r);
  }
  return b;
}
}  // namespace

nlohmann::json governing_block(const nlohmann::json& combinations) {
  nlohmann::json g;
  double u = -1, l = std::numeric_limits<double>::infinity(), d = -1;
  const auto number = [](const nlohmann::json& c, const char* key) -> std::optional<double> {
    if (c.contains(key) && c[key].is_number()) return c[key].get<double>();
    return std::nullopt;
  };
  for (const auto& [name, c] : combinations.items()) {
    const bool named_sls = name.rfind("SLS", 0) == 0;
    const bool uls = c.contains("uls") ? c["uls"].get<bool>() : !named_sls;
    const bool sls = !uls || combinations.size() == 1;
    std::optional<double> lambda = number(c, "lambda");
    if (!c.contains("lambda")) {  // the smaller non-linear λ, else λ_LBA
      for (const char* key : {"lambda_imperfect", "lambda_perfect"})
        if (number(c, key) && (!lambda || *number(c, key) < *lambda)) lambda = number(c, key);
      if (!lambda) lambda = number(c, "lambda_lba");
    }
    if (uls && number(c, "utilisation_max") && *number(c, "utilisation_max") > u) {
      u = *number(c, "utilisation_max");
      g["utilisation"] = name;
    }
    if (uls && lambda && *lambda < l) {
      l = *lambda;
      g["lambda"] = name;
    }
    if (sls && number(c, "delta_max_m") && *number(c, "delta_max_m") > d) {
      d = *number(c, "delta_max_m");
      g["delta"] = name;
    }
  }
  bool pass = true;
  if (g.contains("lambda")) {
    g["lambda_value"] = l;
    g["lambda_pass"] = l >= 1;
    pass = pass && l >= 1;
  }
  if (g.contains("utilisation")) {
    g["utilisation_value"] = u;
    g["utilisation_pass"] = u <= 1;
    pass = pass && u <= 1;
  }
  if (g.contains("delta")) {
    g["delta_m"] = d;
    const nlohmann::json& c = combinations.at(g["delta"].get<std::string>());
    if (c.contains("delta_limit_m") && c["delta_limit_m"].is_number()) {
      const bool ok = d <= c["delta_limit_m"].get<double>();
      g["delta_pass"] = ok;
      pass = pass && ok;
    }
  }
  g["pass"] = pass;
  return g;
}

nlohmann::json combinations_block(const PolyMesh& mesh, const std::vector<int>& supports,
                                  const analysis::GridshellFrameOptions& frame,
                                  const analysis::FrameAnalysisOptions& options,
                                  const analysis::FrameResult& primary,
                                  const analysis::CombinationRunsResult* done) {
  nlohmann::json block;
  if (frame.loads == analysis::LoadModel::paper) {
    block["paper"] = combination_block(primary, 1, 0);
    block["paper"].erase("gamma_G");  // the paper's load: the structure's own weight, λ-scaled
    block["paper"].erase("gamma_Q");
    return block;
  }
  const fem::FrameModel model = analysis::gridshell_frame(mesh, supports, frame);
  const std::vector<analysis::LoadCase> cases =
      analysis::eurocode_cases(mesh, analysis::bar_weights_per_m(model, frame), frame);
  const std::vector<analysis::LoadCombination> combos = analysis::eurocode_combinations(cases);
  std::vector<analysis::CombinationRun> runs;
  for (const analysis::LoadCombination& c : combos) runs.push_back({c.uls, c.name == "ULS"});
  const analysis::CombinationRunsResult analysed =
      done ? analysis::CombinationRunsResult{}
           : analysis::run_combinations(
                 runs, primary, [&](std::size_t k, analysis::AnalysisLevel level) {
                   analysis::GridshellFrameOptions f = frame;
                   f.combination_name = combos[k].name;
                   spdlog::info("[analysis] {} combination: {}", combos[k].name, to_string(level));
                   return analyze_gridshell(mesh, supports, level, f, options);
                 });
  const analysis::CombinationRunsResult& results = done ? *done : analysed;
  if (results.results.size() != combos.size())
    throw Error("combinations", "the analysed combinations do not match the load model");
  for (std::size_t k = 0; k < combos.size(); ++k)
    block[combos[k].name] = eurocode_block(combos[k], results.results[k], results.nonlinear[k]);
  return block;
}

GridShellOutput design_output(const DesignResult& r) {
  GridShellOutput out;
  out.mesh = r.mesh;
  out.raw = r.raw;
  out.supports = r.supports;
  out.d_target = r.d_target;
  out.a_target = r.a_target;
  out.planarity = r.metrics.planarity;
  out.regularity = r.metrics.regularity;
  if (r.structure) add_structure(out, *r.structure);
  return out;
}

nlohmann::json design_report(const DesignResult& r, const DesignOptions& options) {
  nlohmann::json report;
  nlohmann::json mesh = mesh_block(design_output(r));
  mesh["planarity_mean_raw"] = r.raw_metrics.planarity_mean;
  mesh["regularity_mean_raw"] = r.raw_metrics.regularity_mean;
  mesh["edge_length_cv_raw"] = r.raw_metrics.edge_length_cv;
  mesh["total_length_raw_m"] = r.raw_metrics.total_length;
  const Tessellation& t = r.tessellation;
  mesh["hex_share_interior_raw"] = t.quality.hex_share_interior;
  mesh["radius_m"] = t.radius;
  mesh["lloyd_iterations"] = t.iterations;
  mesh["lloyd_converged"] = t.converged;
  mesh["support_mesh_vertices"] = t.support_vertices;
  mesh["length_runs"] = t.length_runs;
  if (options.tessellation.length > 0) {
    mesh["target_length_m"] = options.tessellation.length;
    mesh["length_error"] = r.metrics.total_length / options.tessellation.length - 1;
  }
  const bool flat = r.details.contains("flat_panels") &&
                    r.details["flat_panels"].value("panels", "") == std::string("flat");
  add_panel_keys(mesh, r.panels, flat ? PanelMode::flat : PanelMode::free);
  report["mesh"] = mesh;
  report["buildability"] =
      buildability_block(r.mesh, member_designations(analysed_frame(options, r)));
  report["design"] = r.details;
  report["design"]["panels_requested"] = to_string(options.panels);
  report["design"]["regularized"] = options.finish == Finish::regularize;
  report["design"]["planarized"] = options.finish == Finish::planarize;
  report["design"]["restretch"] = options.regularize_options.restretch;
  report["design"]["size_evening"] = options.regularize_options.size_evening;
  report["design"]["analysis"] = to_string(options.analyze);
  if (r.structure) {
    report["structure"] = structure_block(*r.structure);
    report["structure"]["section"] = section_block(analysed_frame(options, r));
  }
  return report;
}

void add_panel_keys(nlohmann::json& mesh, const PanelShape& s, PanelMode built) {
  mesh["panels"] = to_string(built);
  mesh["out_of_plane_max_m"] = s.out_of_plane_max;
  mesh["out_of_plane_median_m"] = s.out_of_plane_median;
  mesh["surface_distance_max_m"] = s.surface_distance_max;
  mesh["surface_distance_mean_m"] = s.surface_distance_mean;
  mesh["nonconvex_panels"] = s.nonconvex;
  mesh["self_intersecting_panels"] = s.self_intersecting;
  mesh["panel_angle_min_deg"] = s.min_angle_deg;
}

nlohmann::json timings_block(const Timings& timings, const Timings& extra, double total) {
  Timings all = extra;
  for (const auto& [stage, s] : timings) all.add(stage, s);
  nlohmann::json block = all;
  block["total"] = total;
  return block;
}

nlohmann::json fabrication_report(const std::filesystem::path& dir, const PolyMesh& mesh,
                                  const std::vector<int>& supports,
                                  const analysis::FrameResult* structure,
                                  const analysis::GridshellFrameOptions& frame,
                                  const fabrication::SheetOptions& sheet,
                                  const fabrication::BeamResults* envelope) {
  fabrication::FabricationFileOptions o;
  o.sheet = sheet;
  o.bar_diameter = frame.diameter;
  o.bar_density = frame.density;
  const fem::FrameSection section = analysis::member_section(frame);
  o.section = section.name == "bar" ? std::string() : section.name;
  o.section_area = section.A;
  for (const sections::Section& s : frame.member_sections) {
    o.beam_sections.push_back(sections::designation(s));
    o.beam_areas.push_back(sections::properties(s).A);
  }
  fabrication::BeamResults beams;
  if (structure) {
    beams.axial_force = structure->axial_force;
    for (const checks::MemberCheck& c : structure->checks.members) {
      beams.utilisation.push_back(c.section);
      beams.buckling_utilisation.push_back(c.buckling);
      beams.governing.emplace_back(c.buckling > c.section ? c.buckling_governing
                                                          : c.section_governing);
    }
  }
  return fabrication::write_fabrication_files(dir, mesh, supports, envelope ? *envelope : beams, o);
}

nlohmann::json section_block(const analysis::GridshellFrameOptions& frame) {
  if (!frame.member_sections.empty()) {  // sized: the distinct sections (report.json `mass`)
    std::vector<std::string> names;
    for (const sections::Section& s : frame.member_sections)
      names.push_back(sections::designation(s));
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    return {{"designation",
             fmt::format("sized: {} section{}", names.size(), names.size() == 1 ? "" : "s")},
            {"sized", true},
            {"designations", names}};
  }
  const fem::FrameSection s = analysis::member_section(frame);
  const sections::Section& p = *s.profile;
  const sections::SectionProperties q = sections::properties(p);
  nlohmann::json j;
  j["designation"] = sections::designation(p);
  j["shape"] = sections::to_string(p.shape);
  if (p.shape != sections::Shape::bar) j["process"] = sections::to_string(p.process);
  j["standard"] = sections::is_standard(p);
  j["A_m2"] = q.A;
  j["mass_kg_per_m"] = q.mass;
  j["Iy_m4"] = q.Iy;
  j["Iz_m4"] = q.Iz;
  j["It_m4"] = q.It;
  return j;
}

double add_analysed_report(const std::filesystem::path& dir, const AnalysedGridshell& a,
                           nlohmann::json& report) {
  if (!a.mesh || !a.supports || !a.frame || !a.options || !a.structure ||
      (a.sized && !a.sizing_options))
    throw Error("report", "an analysed grid-shell without its mesh, frame or analysis");
  const analysis::GridshellFrameOptions& frame = *a.frame;
  report["structure"]["steel"] = a.steel;
  report["structure"]["loads"] = to_string(frame.loads);
  Stopwatch combinations;
  report["structure"]["combinations"] =
      combinations_block(*a.mesh, *a.supports, frame, *a.options, *a.structure,
                         a.sized ? &a.sized->final : nullptr);
  const double combinations_s = combinations.seconds();
  report["structure"]["governing"] = governing_block(report["structure"]["combinations"]);
  report["mass"] = steel_block(*a.mesh, frame, a.carbon_factor);
  if (a.sized) {
    report["sizing"] = sizing_block(*a.sized, *a.mesh, frame, *a.sizing_options, a.carbon_factor);
    report["sizing"]["sections_list"] = a.sections;
    if (!a.sized->sized) spdlog::warn("[sizing] not sized: {}", a.sized->failure);
  }
  write_frame_json(dir, analysis::gridshell_frame(*a.mesh, *a.supports, frame), frame, *a.options,
                   a.level);
  return combinations_s;
}

}  // namespace gridshell
