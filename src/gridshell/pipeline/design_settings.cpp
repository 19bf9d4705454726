#include "gridshell/pipeline/design_settings.h"

#include <cmath>

#include <spdlog/spdlog.h>

#include "gridshell/checks/member_checks.h"
#include "gridshell/core/enum_words.h"
#include "gridshell/core/error.h"
#include "gridshell/pipeline/objective.h"
#include "gridshell/sections/sections.h"

namespace gridshell {

namespace {

constexpr EnumWords<Finish, 3> kFinishWords{
    {{"raw", Finish::raw}, {"regularize", Finish::regularize}, {"planarize", Finish::planarize}}};
constexpr EnumWords<AnalysisResolution, 2> kAnalysisResolutionWords{
    {{"cells", AnalysisResolution::cells}, {"input", AnalysisResolution::input}}};

}  // namespace

AnalysisResolution parse_analysis_resolution(const std::string& word) {
  return parse_word(word, "--analysis-resolution", kAnalysisResolutionWords);
}
const char* to_string(AnalysisResolution resolution) {
  return word_of(resolution, kAnalysisResolutionWords);
}

FieldInput parse_field_input(const std::string& word, std::string* file) {
  if (word == "stress") return FieldInput::stress;
  if (word == "uniform") return FieldInput::uniform;
  if (file) *file = word;
  return FieldInput::file;
}

Finish parse_finish(const std::string& word) {
  return parse_word(word, "--finish", kFinishWords);
}

const char* to_string(Finish finish) {
  return word_of(finish, kFinishWords);
}

Finish finish_from_flags(bool no_regularize, bool planarize) {
  if (no_regularize && planarize)
    throw Error("--planarize",
                "not with --no-regularize (--planarize replaces the regularization, "
                "--no-regularize keeps the raw tessellation): give one of them");
  return planarize ? Finish::planarize : no_regularize ? Finish::raw : Finish::regularize;
}

void apply_load_check_options(const LoadCheckOptions& o, analysis::GridshellFrameOptions& frame,
                              analysis::FrameAnalysisOptions& analysis, bool sized) {
  analysis.checks.fy = checks::yield_strength(checks::parse_steel_grade(o.steel));
  frame.loads = analysis::parse_load_model(!o.loads.empty() ? o.loads
                                           : sized          ? std::string("eurocode")
                                                            : std::string("paper"));
  if (!(o.glass >= 0) || !std::isfinite(o.glass))
    throw Error("--glass", "must be a load >= 0 (kN/m²)");
  if (!(o.snow >= 0) || !std::isfinite(o.snow))
    throw Error("--snow", "must be a load >= 0 (kN/m²)");
  if (!(o.deflection_limit > 0) || !std::isfinite(o.deflection_limit))
    throw Error("--deflection-limit", "must be a span divisor > 0 (e.g. 300 for span/300)");
  frame.glass_kN_m2 = o.glass;
  frame.snow_kN_m2 = o.snow;
  analysis.deflection_limit_divisor = o.deflection_limit;
  frame.load_cases.clear();
  if (!o.load_cases.empty() && frame.loads != analysis::LoadModel::eurocode)
    throw Error("--load-case", "load cases are combined per EN 1990: give --loads eurocode");
  for (const std::string& spec : o.load_cases) {
    analysis::FileLoadCase c = analysis::read_load_case_file(spec);
    for (const analysis::FileLoadCase& other : frame.load_cases)
      if (other.name == c.name) throw Error("--load-case", "two load cases named " + c.name);
    frame.load_cases.push_back(std::move(c));
  }
}

void attach_load_case_surface(analysis::GridshellFrameOptions& frame, const TriMesh& surface) {
  for (analysis::FileLoadCase& c : frame.load_cases)
    if (c.given == analysis::FileLoadCase::Given::surface_vertex)
      analysis::attach_surface(c, surface);
}

void apply_member_options(const MemberOptions& o, analysis::GridshellFrameOptions& frame,
                          analysis::FrameAnalysisOptions& analysis) {
  if (!(o.buckling_length_factor > 0) || !(o.buckling_length_factor <= 10))
    throw Error("--buckling-length-factor", "must be a factor in (0, 10]");
  analysis.checks.buckling_length_factor = o.buckling_length_factor;
  if (o.section.empty()) return;
  sections::parse_section(o.section, "--section");
  frame.section = o.section;
}

void apply_sizing_options(const SizingArgs& o, StructureOptions& structure) {
  if (!(o.carbon_factor >= 0) || !std::isfinite(o.carbon_factor))
    throw Error("--carbon-factor", "must be a number >= 0 (kgCO2e/kg)");
  if (o.groups < 0 || o.groups > 10000)
    throw Error("--section-groups", "must be 0 (each member its own) … 10000");
  if (!(o.lambda_min > 0) || !(o.lambda_min <= 100))
    throw Error("--lambda-min", "must be a load factor in (0, 100]");
  structure.sizing = o.size ? sizing::MemberSizing::sized : sizing::MemberSizing::given;
  if (!o.size) return;
  structure.sizing_options.catalogue = sizing::parse_section_list(o.sections);
  structure.sizing_options.groups = o.groups;
  structure.sizing_options.lambda_min = o.lambda_min;
}

DesignOptions build_design_options(const DesignSettings& s) {
  DesignOptions o = s.options;
  o.tessellation.seed = s.seed;
  o.finish = finish_from_flags(s.no_regularize, s.planarize);
  // A frame-response field (frame-mode, frame-energy) is run by design_from_frame_response.
  if (!parse_frame_source(s.field)) o.field = parse_field_input(s.field, &o.field_file);
  o.analyze = analysis::parse_analysis_level(s.analyze);
  apply_load_check_options(s.checks, o.frame, o.frame_analysis, s.sizing.size);
  apply_member_options(s.members, o.frame, o.frame_analysis);
  StructureOptions structure;
  apply_sizing_options(s.sizing, structure);
  o.sizing = structure.sizing;
  o.sizing_options = structure.sizing_options;
  o.frame_analysis.stability = !s.single_path;
  o.symmetry = parse_symmetry(s.symmetry);
  o.analysis_resolution = parse_analysis_resolution(s.resolution);
  o.panels = parse_panel_mode(s.panels);
  o.field_options.measure = parse_stress_measure(s.measure);
  o.field_options.stretch = parse_stretch_axis(s.stretch);
  o.field_options.density = parse_density_trend(s.density);
  check_design_options(o);
  return o;
}

// The checks run_design makes before any work (declared in design.h).
void check_design_options(const DesignOptions& o) {
  if (!(o.field_options.D >= 1) || !std::isfinite(o.field_options.D))
    throw Error("-D", "must be a number ≥ 1");
  if (!(o.field_options.A >= 1) || !std::isfinite(o.field_options.A))
    throw Error("-A", "must be a number ≥ 1");
  if (o.field_options.D > 8 || o.field_options.A > 8)
    spdlog::warn("design: D or A above ~4 may fold the deformed surface (D = {}, A = {})",
                 o.field_options.D, o.field_options.A);
  if (!(o.frame_analysis.displacement_limit >= 0) ||
      !std::isfinite(o.frame_analysis.displacement_limit))
    throw Error("--displacement-limit", "must be a length >= 0 (m; 0 = span / 100)");
  if (!(o.frame_analysis.deflection_limit_divisor > 0))
    throw Error("--deflection-limit", "must be a span divisor > 0 (e.g. 300 for span/300)");
  if (o.frame.loads == analysis::LoadModel::eurocode) {
    if (o.frame.area_load_kN_m2 != 0)
      throw Error("--area-load",
                  "with --loads eurocode give the surface loads as --glass and --snow");
    if (!(o.frame.glass_kN_m2 >= 0) || !std::isfinite(o.frame.glass_kN_m2))
      throw Error("--glass", "must be a load >= 0 (kN/m²)");
    if (!(o.frame.snow_kN_m2 >= 0) || !std::isfinite(o.frame.snow_kN_m2))
      throw Error("--snow", "must be a load >= 0 (kN/m²)");
  }
  if (o.analyze != analysis::AnalysisLevel::none) analysis::member_section(o.frame);  // --section
  if (o.field == FieldInput::file && o.field_file.empty())
    throw Error("--field", "no field file given");
  if (!(o.analysis_edges_per_radius > 0) || !std::isfinite(o.analysis_edges_per_radius))
    throw Error("analysis resolution", "edges per cell radius must be a number > 0");
  check_tessellation_options(o.tessellation);
}

}  // namespace gridshell
