// gridshell analyze GRIDSHELL.obj|.ply|MODEL.json: the grid-shell as a rigid-jointed 3D frame —
// δ (linear), λ_LBA (linearised buckling) and λ (first critical point of the non-linear path).

#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common.h"
#include "gridshell/analysis/combination_runs.h"
#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/checks/member_checks.h"
#include "gridshell/core/error.h"
#include "gridshell/figures/figures.h"
#include "gridshell/io/files.h"
#include "gridshell/io/frame_model_json.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/overlaps.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/metrics.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/design_report.h"
#include "gridshell/pipeline/frame_output.h"

namespace gridshell::app {

namespace {

struct AnalyzeArgs {
  std::string input;
  SurfaceOptions surface_options;
  RunOptions run;
  std::string analyze = "auto";
  double area_load = 0;
  std::string self_weight = "surface";
  int elements = 2;
  double diameter = 0.037;
  int modes = 5;
  bool imperfection = false;
  double imperfection_amplitude = 0;
  double nonlinear_static = 0;
  int max_steps = 0;             ///< 0: MODEL.json's analysis.max_steps, else 300
  double stop_displacement = 0;  ///< 0: MODEL.json's, else automatic
  double stop_lambda = 0;        ///< 0: MODEL.json's, else automatic
  double displacement_limit = 0;
  std::string sheet = fabrication::kDefaultSheet;
  LoadCheckOptions checks;  ///< --steel, --loads, --glass, --snow, --deflection-limit
  MemberOptions members;    ///< --section (mesh input), --buckling-length-factor
  SizingArgs sizing;        ///< --size (mesh input), --sections, --section-groups, …
  bool single_path = false;
};

std::string lower_ext(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

/// Every option checked before any work.
void check_analyze_args(const AnalyzeArgs& a) {
  if (a.elements < 1 || a.elements > 1000) throw Error("--elements", "must be in 1..1000");
  if (!(a.area_load >= 0) || !std::isfinite(a.area_load))
    throw Error("--area-load", "must be a number >= 0 (kN/m²)");
  if (a.self_weight != "surface" && a.self_weight != "at-bars")
    throw Error("--self-weight", "must be 'surface' or 'at-bars'");
  if (!(a.diameter > 0) || !std::isfinite(a.diameter)) throw Error("--diameter", "must be > 0");
  if (a.modes < 1 || a.modes > 100) throw Error("--modes", "must be in 1..100");
  if (a.nonlinear_static < 0 || !std::isfinite(a.nonlinear_static))
    throw Error("--nonlinear-static", "must be > 0");
  if (a.max_steps < 0 || a.max_steps > 100000) throw Error("--max-steps", "must be in 1..100000");
  if (!(a.stop_displacement >= 0) || !std::isfinite(a.stop_displacement))
    throw Error("--stop-displacement", "must be a length > 0 (model units)");
  if (!(a.stop_lambda >= 0) || !std::isfinite(a.stop_lambda))
    throw Error("--stop-lambda", "must be a load factor > 0");
  if (!(a.displacement_limit >= 0) || !std::isfinite(a.displacement_limit))
    throw Error("--displacement-limit", "must be a length >= 0 (m; 0 = span / 100)");
  fabrication::parse_sheet(a.sheet);
  analysis::GridshellFrameOptions frame;
  analysis::FrameAnalysisOptions options;
  apply_load_check_options(a.checks, frame, options, a.sizing.size);
  apply_member_options(a.members, frame, options);
  StructureOptions structure;
  apply_sizing_options(a.sizing, structure);
  if (a.sizing.size && lower_ext(a.input) == ".json")
    throw Error("--size",
                "sizes a grid-shell mesh's members (PLY/OBJ/OFF); a MODEL.json keeps "
                "its sections");
  if (!a.members.section.empty() && lower_ext(a.input) == ".json")
    throw Error("--section", "a MODEL.json gives its own sections");
  if (frame.loads == analysis::LoadModel::eurocode && lower_ext(a.input) == ".json")
    throw Error("--loads", "eurocode load cases need a grid-shell mesh (MODEL.json has its loads)");
  if (a.analyze != "auto") {
    if (analysis::parse_analysis_level(a.analyze) == analysis::AnalysisLevel::none)
      throw Error("--analyze", "must be linear, buckling or nonlinear");
  }
}

/// The frame to analyse: a MODEL.json as it is (plus --area-load on its faces), or a grid-shell
/// mesh as the paper's steel frame; its supported nodes; what a MODEL.json asks to analyse.
struct LoadedFrame {
  fem::FrameModel model;
  std::vector<int> supports;
  io::ModelAnalysisRequest request;
  std::vector<io::ModelCombination> combinations;  ///< MODEL.json's; primary first
};

/// The grid-shell frame options the arguments ask for.
analysis::GridshellFrameOptions frame_options(const AnalyzeArgs& a, const PolyMesh* mesh) {
  analysis::GridshellFrameOptions go;
  go.diameter = a.diameter;
  go.elements = a.elements;
  go.self_weight_at_bars = a.self_weight == "at-bars";
  go.area_load_kN_m2 = a.area_load;
  analysis::FrameAnalysisOptions unused;
  apply_load_check_options(a.checks, go, unused, a.sizing.size);
  apply_member_options(a.members, go, unused);
  // `vertex` rows of a load case refer to the grid-shell's own joints (its panels triangulated:
  // convex ones fanned, concave ones filled inside their outline).
  if (mesh) attach_load_case_surface(go, triangulate(*mesh));
  return go;
}

LoadedFrame load_frame(const AnalyzeArgs& a) {
  LoadedFrame f;
  if (lower_ext(a.input) == ".json") {
    io::FrameModelFile file = io::read_frame_model(a.input, 1);
    f.model = std::move(file.model);
    f.request = file.analysis;
    f.combinations = std::move(file.combinations);
    if (a.area_load > 0) {
      if (!f.combinations.empty())
        throw Error("--area-load", "the model has load cases: give it as a surface load in one");
      if (f.model.faces.empty()) throw Error("--area-load", "the model has no faces to carry it");
      PolyMesh pm;
      pm.V = f.model.nodes;
      pm.faces = f.model.faces;
      const std::vector<double> trib = analysis::tributary_areas(pm);
      for (int v = 0; v < f.model.num_nodes(); ++v)
        if (trib[v] > 0)
          f.model.loads.push_back({v, Vec3(0, 0, -a.area_load * 1e3 * trib[v]), Vec3::Zero()});
    }
    for (const auto& s : f.model.supports) f.supports.push_back(s.node);
    return f;
  }
  PolySurface s = load_gridshell(a.input, a.surface_options);
  if (s.supports.empty())
    throw Error(a.input, "no support vertices: the grid-shell is a mechanism");
  // The frame is analysed as given; a grid that covers part of the roof twice is said so.
  if (const int overlaps = find_overlaps(s.mesh, build_topology(s.mesh)).count(); overlaps > 0)
    spdlog::warn(
        "{}: {} overlaps (beams that cross without a joint, joints inside a panel not "
        "their own): analysed as given, but not buildable as is",
        a.input, overlaps);
  f.model = analysis::gridshell_frame(s.mesh, s.supports, frame_options(a, &s.mesh));
  f.supports = s.supports;
  return f;
}

/// `--analyze auto`: what a MODEL.json's `analysis` asks, else the whole (non-linear) analysis.
analysis::AnalysisLevel analysis_level(const std::string& word,
                                       const io::ModelAnalysisRequest& request) {
  if (word != "auto") return analysis::parse_analysis_level(word);
  if (request.nonlinear.value_or(false)) return analysis::AnalysisLevel::nonlinear;
  if (request.buckling.value_or(false)) return analysis::AnalysisLevel::buckling;
  if (request.linear.has_value() || request.buckling.has_value() || request.nonlinear.has_value() ||
      request.nonlinear_static.has_value())
    return analysis::AnalysisLevel::linear;
  return analysis::AnalysisLevel::nonlinear;
}

analysis::FrameAnalysisOptions analysis_options(const AnalyzeArgs& a, analysis::AnalysisLevel level,
                                                const io::ModelAnalysisRequest& request) {
  analysis::FrameAnalysisOptions o;
  o.subject = a.input;
  o = analysis::at_level(o, level);
  o.buckling_modes = a.modes;
  o.imperfection = a.imperfection || a.imperfection_amplitude > 0;
  o.imperfection_amplitude = a.imperfection_amplitude;
  o.nonlinear_static =
      a.nonlinear_static > 0 ? a.nonlinear_static : request.nonlinear_static.value_or(0);
  // The path's stop rule: the command line, else MODEL.json's analysis keys, else automatic
  // (a general frame is followed to its first critical point: FrameAnalysisOptions::path_reach).
  const bool general = lower_ext(a.input) == ".json";
  o.arc.max_steps = a.max_steps > 0
                        ? a.max_steps
                        : request.max_steps.value_or(
                              general ? analysis::FrameAnalysisOptions::kGeneralMaxSteps : 300);
  o.arc.max_displacement =
      a.stop_displacement > 0 ? a.stop_displacement : request.stop_displacement.value_or(0);
  o.arc.max_lambda = a.stop_lambda > 0 ? a.stop_lambda : request.stop_lambda.value_or(1e9);
  if (general) o.path_reach = analysis::FrameAnalysisOptions::kGeneralPathReach;
  o.displacement_limit = a.displacement_limit;
  analysis::GridshellFrameOptions unused;
  apply_load_check_options(a.checks, unused, o, a.sizing.size);
  apply_member_options(a.members, unused, o);
  o.stability = !a.single_path;
  if (o.imperfection && !o.buckling) o.buckling = true;
  return o;
}

/// report.json's `structure.combinations` for a MODEL.json: without load cases {"model": the
/// analysis}; with them one block per combination with its factors, the primary from `primary`,
/// the others from a linear analysis each (δ, its limit, the member checks), as `design`'s SLS.
nlohmann::json model_combinations(const LoadedFrame& f, analysis::FrameAnalysisOptions options,
                                  const analysis::FrameResult& primary) {
  nlohmann::json block;
  const auto with_factors = [](nlohmann::json c, const io::ModelCombination* comb) {
    c.erase("gamma_G");
    c.erase("gamma_Q");
    if (comb)
      for (const auto& [name, factor] : comb->factors) c["factors"][name] = factor;
    return c;
  };
  if (f.combinations.empty()) {
    block["model"] = with_factors(combination_block(primary, 1, 1), nullptr);
    return block;
  }
  block[f.combinations.front().name] =
      with_factors(combination_block(primary, 1, 1), &f.combinations.front());
  // The other combinations by the design's rule (analysis/combination_runs.h), so that a
  // design's frame.json governs by the same combinations.
  std::vector<analysis::CombinationRun> runs;
  for (std::size_t k = 0; k < f.combinations.size(); ++k)
    runs.push_back({f.combinations[k].name.rfind("SLS", 0) != 0, k == 0});
  options.nonlinear_static = 0;
  const analysis::CombinationRunsResult done =
      analysis::run_combinations(runs, primary, [&](std::size_t k, analysis::AnalysisLevel level) {
        fem::FrameModel model = f.model;
        model.loads = f.combinations[k].loads;
        spdlog::info("[analysis] {} combination: {}", f.combinations[k].name, to_string(level));
        return analysis::analyze_frame(model, analysis::at_level(options, level));
      });
  for (std::size_t k = 1; k < f.combinations.size(); ++k)
    block[f.combinations[k].name] =
        with_factors(combination_block(done.results[k], 1, 1), &f.combinations[k]);
  return block;
}

/// frame.json: a grid-shell mesh's frame with its load cases (write_frame_json); a MODEL.json as
/// read, one load case per combination (its resolved loads) when it has combinations.
void write_analyze_frame_json(const AnalyzeArgs& a, const LoadedFrame& f,
                              const analysis::GridshellFrameOptions& frame,
                              const analysis::FrameAnalysisOptions& options,
                              analysis::AnalysisLevel level) {
  if (lower_ext(a.input) != ".json" || f.combinations.empty()) {
    analysis::GridshellFrameOptions paper = frame;
    if (lower_ext(a.input) == ".json") paper.loads = analysis::LoadModel::paper;
    write_frame_json(a.run.out_dir, f.model, paper, options, level);
    return;
  }
  std::vector<io::NodalLoadCase> cases;
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, double>>>> combos;
  for (const io::ModelCombination& c : f.combinations) {
    cases.push_back({c.name, true, c.loads});
    combos.push_back({c.name, {{c.name, 1.0}}});
  }
  nlohmann::json j = io::frame_model_to_json(f.model, cases, combos);
  io::write_file_atomic(std::filesystem::path(a.run.out_dir) / "frame.json", j.dump() + "\n");
}

/// The figures of an `analyze` run, drawn beside the other work: top.png and perspective.png
/// (they read only the linear axial forces) while the LBA and the path run, the others (the
/// buckling mode, the path) while the frame's files are written. Not movable (the analysis's
/// hook points to it); waits for its threads when destroyed.
class AnalyzeFigures {
 public:
  AnalyzeFigures(const AnalyzeArgs& a, const PolyMesh& mesh, analysis::AnalysisLevel level)
      : input_(a.input),
        level_(level),
        dir_(a.run.out_dir),
        options_(figures::parse_figure_options(a.run.figures)) {
    in_.gridshell = &mesh;
  }
  AnalyzeFigures(const AnalyzeFigures&) = delete;
  AnalyzeFigures& operator=(const AnalyzeFigures&) = delete;
  ~AnalyzeFigures() {
    if (linear_.valid()) linear_.wait();
    if (written_.valid()) written_.wait();
  }
  /// Sets `o.after_linear` to draw top.png and perspective.png on another thread.
  void draw_linear_beside(analysis::FrameAnalysisOptions& o, const fem::FrameModel& model,
                          const std::vector<int>& supports) {
    if (!options_.enabled) return;
    describe(model, supports);
    o.after_linear = [this](const analysis::FrameResult& linear) {
      if (linear_.valid()) return;  // the first analysis's: the model's own
      linear_view_.axial_force = linear.axial_force;
      figures::FigureInput in = in_;
      in.structure = &linear_view_;
      linear_ = std::async(std::launch::async,
                           [this, in] { return figures::encode_linear_figures(in, options_); });
    };
  }
  /// Draws and writes every figure of `r` not drawn yet, on another thread; `r` must stay as it
  /// is until written().
  void draw(const analysis::FrameResult& r, const fem::FrameModel& model,
            const std::vector<int>& supports) {
    describe(model, supports);
    in_.structure = &r;
    written_ = std::async(std::launch::async, [this] {
      const auto start = std::chrono::steady_clock::now();
      std::optional<figures::EncodedFigures> first;
      if (linear_.valid()) first = linear_.get();
      std::vector<std::string> paths = figures::write_figures(dir_, in_, options_, std::move(first));
      seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return paths;
    });
  }
  /// The figures' paths relative to the output folder (report.json's `figures`), once written.
  std::vector<std::string> written() { return written_.get(); }
  /// The time draw()'s thread took (with its wait for the first two figures); after written().
  double seconds() const { return seconds_; }

 private:
  void describe(const fem::FrameModel& model, const std::vector<int>& supports) {
    in_.supports = supports;
    in_.title = fmt::format("gridshell analyze {}: {} nodes, {} members; analysis {}", input_,
                            model.num_nodes(), model.members.size(), to_string(level_));
    in_.beams.clear();
    for (const fem::FrameMember& m : model.members) in_.beams.push_back({m.i, m.j});
  }
  std::string input_;
  analysis::AnalysisLevel level_;
  std::filesystem::path dir_;
  figures::FigureOptions options_;
  figures::FigureInput in_;
  analysis::FrameResult linear_view_;  ///< what the first two read: the linear axial forces
  double seconds_ = 0;
  std::future<figures::EncodedFigures> linear_;
  std::future<std::vector<std::string>> written_;
};

int run_analyze(const AnalyzeArgs& a, const CLI::App* sub) {
  const auto guard = apply_run_options(a.run);
  check_analyze_args(a);
  LoadedFrame f = load_frame(a);
  const analysis::AnalysisLevel level = analysis_level(a.analyze, f.request);
  io::ensure_directory(a.run.out_dir);
  analysis::FrameAnalysisOptions options = analysis_options(a, level, f.request);
  options.arc.progress = guard.progress;
  const bool gridshell_mesh = lower_ext(a.input) != ".json";  // members: its topology edges
  const PolyMesh mesh{f.model.nodes, f.model.faces};
  analysis::GridshellFrameOptions frame = frame_options(a, gridshell_mesh ? &mesh : nullptr);
  analysis::FrameResult r;
  std::optional<sizing::SizingResult> sized;
  AnalyzeFigures figures(a, mesh, level);
  if (!a.sizing.size) figures.draw_linear_beside(options, f.model, f.supports);
  if (a.sizing.size) {  // a grid-shell mesh (checked): sized, then its sized frame is the model
    StructureOptions so;
    so.level = level;
    apply_sizing_options(a.sizing, so);
    GridshellStructure s = analyze_structure(mesh, f.supports, frame, options, so);
    frame = std::move(s.frame);
    f.model = analysis::gridshell_frame(mesh, f.supports, frame);
    r = std::move(s.result);
    sized = std::move(s.sizing);
  } else {
    r = analysis::analyze_frame(f.model, options);
  }
  figures.draw(r, f.model, f.supports);  // the others, beside the files
  // A grid-shell's fabrication files (their beams.csv included) need only the mesh and the
  // results: written on the second core while this one writes the frame's files and the report.
  std::future<nlohmann::json> fabrication;
  const std::optional<fabrication::BeamResults> envelope =
      sized ? std::optional(member_envelope(*sized)) : std::nullopt;
  if (gridshell_mesh) {
    fabrication = std::async(std::launch::async, [&] {
      return fabrication_report(a.run.out_dir, mesh, f.supports, &r, frame,
                                fabrication::parse_sheet(a.sheet), envelope ? &*envelope : nullptr);
    });
  }
  write_frame_outputs(a.run.out_dir, f.model, f.supports, r,
                      gridshell_mesh ? BeamsCsv::LeaveToFabrication : BeamsCsv::Write);
  nlohmann::json report;
  nlohmann::json st = structure_block(r);
  st.erase("timings_s");  // report.json has them at the top level
  st["nodes"] = f.model.num_nodes();
  st["members"] = f.model.members.size();
  st["supports"] = f.supports.size();
  st["analysis"] = to_string(level);
  st["steel"] = a.checks.steel;
  if (gridshell_mesh) st["section"] = section_block(frame);
  const Vec3 total = fem::total_load(f.model);
  st["total_load_N"] = {total.x(), total.y(), total.z()};
  st["loads"] = gridshell_mesh           ? analysis::to_string(frame.loads)
                : f.combinations.empty() ? "model"
                                         : "load_cases";
  if (!gridshell_mesh)
    st["combinations"] = model_combinations(f, analysis_options(a, level, f.request), r);
  else
    st["combinations"] =
        combinations_block(mesh, f.supports, frame, analysis_options(a, level, f.request), r,
                           sized ? &sized->final : nullptr);
  st["governing"] = governing_block(st["combinations"]);
  if (gridshell_mesh) report["mass"] = steel_block(mesh, frame, a.sizing.carbon_factor);
  if (sized) {
    StructureOptions so;
    apply_sizing_options(a.sizing, so);
    report["sizing"] = sizing_block(*sized, mesh, frame, so.sizing_options, a.sizing.carbon_factor);
    report["sizing"]["sections_list"] = a.sizing.sections;
    if (!sized->sized) spdlog::warn("[sizing] not sized: {}", sized->failure);
  }
  write_analyze_frame_json(a, f, frame, analysis_options(a, level, f.request), level);
  report["structure"] = st;
  if (gridshell_mesh) {
    GridShellOutput out;
    out.mesh = mesh;
    out.supports = f.supports;
    add_structure(out, r);
    write_gridshell_vtp(a.run.out_dir, out);
    // The grid as given, with the same keys as design's (its overlaps get a row on the page).
    const MeshMetrics metrics = mesh_metrics(mesh);
    out.planarity = metrics.planarity;
    out.regularity = metrics.regularity;
    report["mesh"] = mesh_block(out);
  }
  report["figures"] = figures.written();
  report["timings_s"] = r.timings;
  report["timings_s"]["figures"] = figures.seconds();
  if (gridshell_mesh) report["fabrication"] = fabrication.get();
  write_report(a.run.out_dir, report);
  write_report_page(a.run.out_dir,
                    !gridshell_mesh ? report::frame_report_input(f.model, f.supports, r)
                                    : report::gridshell_report_input(mesh, f.supports, &r),
                    report, sub);
  write_config(a.run.out_dir, sub);
  return 0;
}

}  // namespace

void register_analyze(CLI::App& app, Action& action) {
  auto a = std::make_shared<AnalyzeArgs>();
  CLI::App* sub = app.add_subcommand(
      "analyze",
      "Structural analysis of a grid-shell as a rigid-jointed 3D frame: deflection, linearised "
      "and non-linear buckling factor");
  sub->add_option("input", a->input, "GRIDSHELL.obj|.ply|.off or MODEL.json")->required();
  sub->add_option("--analyze", a->analyze,
                  "linear | buckling (+ linearised buckling) | nonlinear (+ arc-length path); "
                  "default nonlinear, or what MODEL.json's analysis asks")
      ->default_str("auto");
  sub->add_option("--area-load", a->area_load,
                  "extra surface load in kN/m² spread to the joints by tributary face area")
      ->default_str("0");
  sub->add_option("--self-weight", a->self_weight,
                  "surface (spread by face area, the paper's load) | at-bars (at the bar ends)")
      ->default_str("surface");
  sub->add_option("--elements", a->elements, "beam elements per grid-shell bar")->default_str("2");
  sub->add_option("--diameter", a->diameter, "solid circular bar diameter [m]")
      ->default_str("0.037");
  sub->add_option("--modes", a->modes, "linearised buckling modes to compute")->default_str("5");
  sub->add_flag(
      "--imperfection", a->imperfection,
      "perturb the geometry by the first buckling mode (span/300) for the non-linear path");
  sub->add_option("--imperfection-amplitude", a->imperfection_amplitude,
                  "imperfection amplitude in m (implies --imperfection)")
      ->default_str("0");
  sub->add_option("--nonlinear-static", a->nonlinear_static,
                  "also solve the non-linear equilibrium at this load factor (nodes_nonlinear.csv)")
      ->default_str("0");
  sub->add_option("--max-steps", a->max_steps,
                  "non-linear path: arc-length step limit (default: MODEL.json's "
                  "analysis.max_steps, else 1000 for MODEL.json, 300 for grid-shell meshes)")
      ->default_str("0");
  sub->add_option("--stop-displacement", a->stop_displacement,
                  "non-linear path: stop when the largest displacement reaches this (model "
                  "units; default: MODEL.json's analysis.stop_displacement, else 3 × the model's "
                  "size for MODEL.json, span/5 for grid-shell meshes)")
      ->default_str("0");
  sub->add_option("--stop-lambda", a->stop_lambda,
                  "non-linear path: stop when the load factor reaches this (default: MODEL.json's "
                  "analysis.stop_lambda, else 20 × lambda_LBA)")
      ->default_str("0");
  sub->add_option("--displacement-limit", a->displacement_limit,
                  "report lambda_displacement_limit: the load factor at which the non-linear "
                  "path's largest displacement reaches this many metres (0 = span / 100)")
      ->default_str("0");
  add_load_check_options(sub, a->checks);
  add_member_options(sub, a->members);
  add_sizing_options(sub, a->sizing);
  sub->add_flag("--single-path", a->single_path,
                "non-linear analysis: follow only the path asked for (perfect, or imperfect with "
                "--imperfection), not also the other");
  sub->add_option("--sheet", a->sheet,
                  "fabrication (grid-shell meshes): sheet size WxH in metres on which the panels "
                  "are nested")
      ->default_str(fabrication::kDefaultSheet);
  sub->footer(
      "Writes nodes.csv, beams.csv, path.csv (nodes_nonlinear.csv with --nonlinear-static),\n"
      "frame.vtp, figures/*.png (top, perspective, buckling_mode, load_path: docs/figures.md),\n"
      "report.json, config.json and report.html (open it first: the 3D view with forces and\n"
      "buckling modes, offline); for a grid-shell mesh also gridshell.vtp, joints.csv,\n"
      "panels.csv and panels.svg.");
  add_surface_options(sub, a->surface_options);
  add_run_options(sub, a->run);
  add_figure_option(sub, a->run);
  sub->callback([a, sub, &action] { action = [a, sub] { return run_analyze(*a, sub); }; });
}

}  // namespace gridshell::app
