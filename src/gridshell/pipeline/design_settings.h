#pragma once
/// \file design_settings.h
/// The settings of a design as a user gives them (words and numbers, with their defaults stated
/// here once), and the one builder that turns them into the pipeline's `DesignOptions`:
/// `gridshell design`, `baseline`, `sweep` and the studio all call build_design_options, so an
/// option word means the same everywhere and is parsed and checked (Error naming the option,
/// exit 2) before any work.
///
/// The walk of one option, `-D 2`: the command line (app/cmd_design.cpp) stores it in
/// `DesignSettings::options.field_options.D` → build_design_options copies it, once, into
/// `DesignOptions::field_options.D` and checks it (check_design_options) → the field stage
/// (pipeline/design.cpp, make_field) rescales the density to [1, D].
///
/// Also here: the load model, member and sizing settings that `analyze` shares with the design
/// commands (--steel, --loads, --section, --size, …; docs/checks.md, docs/sizing.md).

#include <cstdint>
#include <string>
#include <vector>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/structure.h"

namespace gridshell {

/// The load model and member-check settings of the commands that analyse a grid-shell (design,
/// analyze, baseline, sweep): --steel, --loads, --glass, --snow, --deflection-limit, --load-case.
struct LoadCheckOptions {
  std::string steel = "S355";     ///< S235 | S275 | S355
  std::string loads;              ///< paper | eurocode; empty = paper, or eurocode with --size
  double glass = 0.4;             ///< eurocode G2 [kN/m² of surface]
  double snow = 1.0;              ///< eurocode Q: s_k [kN/m² of plan]
  double deflection_limit = 300;  ///< δ passes when at most span / this
  std::vector<std::string> load_cases;  ///< --load-case NAME=FILE.csv (repeatable)
};
/// Parses and checks them (Error naming the option) and sets `frame`'s load model (no --loads:
/// eurocode when `sized`, else paper), glass, snow and file load cases (read here: a bad file is
/// an Error before any work), and `analysis`'s fy and deflection limit.
void apply_load_check_options(const LoadCheckOptions& options,
                              analysis::GridshellFrameOptions& frame,
                              analysis::FrameAnalysisOptions& analysis, bool sized = false);
/// Gives the file load cases on the input surface's vertices that surface (checks the ids).
void attach_load_case_surface(analysis::GridshellFrameOptions& frame, const TriMesh& surface);

/// The members (docs/checks.md): --section "CHS 88.9x4.0" | "RHS 120x60x4" | "SHS 100x5" |
/// "bar 37" [cold] (sections/sections.h; empty = the solid bar of --diameter) and
/// --buckling-length-factor F (L_cr = F × member length, default 1).
struct MemberOptions {
  std::string section;
  double buckling_length_factor = 1;
};
/// Checks them (Error naming the option, exit 2, before any work) and sets frame.section and
/// analysis.checks.buckling_length_factor.
void apply_member_options(const MemberOptions& options, analysis::GridshellFrameOptions& frame,
                          analysis::FrameAnalysisOptions& analysis);

/// Member sizing (docs/sizing.md): --size, --sections chs|rhs|bar|'chs cold'|FILE,
/// --section-groups N, --lambda-min, --carbon-factor.
struct SizingArgs {
  bool size = false;
  std::string sections = "chs";
  int groups = 0;
  double lambda_min = 1.0;
  double carbon_factor = kSteelCarbonFactor;  ///< kgCO2e/kg
};
/// Checks them (Error naming the option, exit 2) and sets `structure`'s sizing mode and options
/// (the section list read here).
void apply_sizing_options(const SizingArgs& options, StructureOptions& structure);

/// The words of Finish (design.h): raw | regularize | planarize.
Finish parse_finish(const std::string& word);
const char* to_string(Finish finish);
/// The finish the command line's two flags ask for: `--no-regularize` → raw, `--planarize` →
/// planarize, neither → regularize. Both together contradict each other (planarize replaces the
/// regularization; no-regularize keeps the raw tessellation): Error("--planarize"), exit 2.
Finish finish_from_flags(bool no_regularize, bool planarize);

/// A design's settings. The words are parsed by build_design_options; the numbers that go to
/// the pipeline as they are (D and A in `options.field_options`, the size request in
/// `options.tessellation`, the regularization's knobs, the bars, the displacement limit) are
/// stored in `options` directly, once.
struct DesignSettings {
  /// stress | uniform | FILE (BLK or CSV), or frame-mode | frame-energy (pipeline/objective.h:
  /// DesignOptions::field is then left at stress; the caller runs design_from_frame_response)
  std::string field = "stress";
  std::string measure = "magnitude";  ///< --stress-measure: magnitude | tension | compression
  std::string stretch = "along";      ///< --stretch: along | across
  std::string density = "rising";     ///< --density-trend (--density): rising | falling
  std::string analyze = "nonlinear";  ///< none | linear | buckling | nonlinear
  std::string symmetry = "none";      ///< none | x | y | xy
  std::string resolution = "cells";   ///< --analysis-resolution: cells | input
  std::string panels = "free";        ///< --panels: flat | free
  bool no_regularize = false;         ///< --no-regularize: Finish::raw
  bool planarize = false;             ///< --planarize: Finish::planarize
  bool single_path = false;           ///< non-linear: no second (imperfect) path
  std::uint64_t seed = 1;             ///< the tessellation's seed
  LoadCheckOptions checks;
  MemberOptions members;
  SizingArgs sizing;
  /// The numbers, and the defaults of everything the words do not set.
  DesignOptions options;
};

/// The pipeline's options for `settings`, checked (check_design_options). Throws Error naming the
/// option for a bad word or value, e.g. `--no-regularize --planarize` (finish_from_flags).
DesignOptions build_design_options(const DesignSettings& settings);

}  // namespace gridshell
