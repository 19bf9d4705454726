#pragma once
/// \file design_report.h
/// What `gridshell design` writes, assembled in one place: the grid-shell files' content
/// (GridShellOutput) and report.json's blocks `mesh` (CONTRACT keys, statistics, the raw
/// tessellation's figures, the length target), `design` (every stage's details and the options
/// that shaped the result), `structure` (when analysed) and `timings_s`; and the fabrication
/// files with report.json's `fabrication` block, which baseline and analyze write the same way.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "gridshell/fabrication/fabrication_files.h"
#include "gridshell/fabrication/nesting.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/gridshell_output.h"
#include "gridshell/sizing/sizing.h"

namespace gridshell {

/// The files' content of a design result.
GridShellOutput design_output(const DesignResult& r);

/// report.json without `surface`, `objective` and `timings_s` (the command adds those).
nlohmann::json design_report(const DesignResult& r, const DesignOptions& options);

/// The panel keys of report.json `mesh` (docs/panels.md): `panels` (flat | free, what was built),
/// out_of_plane_max_m / _median_m (largest corner distance to the panel's best-fit plane),
/// surface_distance_max_m / _mean_m (joints to the input surface), nonconvex_panels,
/// self_intersecting_panels, panel_angle_min_deg.
void add_panel_keys(nlohmann::json& mesh, const PanelShape& shape, PanelMode built);

/// report.json's `timings_s`: the stages in `timings` and the extra ones given (a stage in both
/// is summed), and `total`.
nlohmann::json timings_block(const Timings& timings, const Timings& extra, double total);

/// Writes the fabrication files (joints.csv, beams.csv, panels.csv, panels.svg; see
/// fabrication/fabrication_files.h) of `mesh` into `dir` and returns report.json's `fabrication`
/// block (bill of materials). `structure`: a frame analysis of `mesh` whose members are its
/// topology edges (its axial forces go into beams.csv), or null; `frame`: the bars' diameter and
/// density for the mass; `sheet`: the sheet size the panels are nested on; `envelope`: per beam
/// results that replace `structure`'s (a sized design's envelope over its combinations). Design, baseline and
/// analyze all call this.
nlohmann::json fabrication_report(const std::filesystem::path& dir, const PolyMesh& mesh,
                                  const std::vector<int>& supports,
                                  const analysis::FrameResult* structure,
                                  const analysis::GridshellFrameOptions& frame,
                                  const fabrication::SheetOptions& sheet,
                                  const fabrication::BeamResults* envelope = nullptr);

/// An analysed grid-shell, for add_analysed_report. Pointers must outlive the call; `sized` is
/// null unless its members were sized.
struct AnalysedGridshell {
  const PolyMesh* mesh = nullptr;
  const std::vector<int>* supports = nullptr;
  /// As analysed: with a sized design's member sections (analysed_frame, analyze_structure).
  const analysis::GridshellFrameOptions* frame = nullptr;
  const analysis::FrameAnalysisOptions* options = nullptr;
  analysis::AnalysisLevel level = analysis::AnalysisLevel::nonlinear;
  const analysis::FrameResult* structure = nullptr;  ///< the primary combination
  const sizing::SizingResult* sized = nullptr;
  const sizing::SizingOptions* sizing_options = nullptr;  ///< with `sized`
  std::string steel;          ///< the grade's word (`--steel`)
  std::string sections;       ///< the section list's word (`--sections`)
  double carbon_factor = 0;   ///< kgCO2e/kg
};
/// What design and baseline (and the studio's export) write alike for an analysed grid-shell:
/// report.json's `structure.steel`, `structure.loads`, `structure.combinations` and
/// `structure.governing` (combinations_block, governing_block, analysing the combinations other
/// than the primary), `mass` (steel_block) and, when sized, `sizing` (sizing_block with
/// `sections_list`), and DIR/frame.json (frame_output.h). Returns the seconds of the
/// combinations' analyses.
double add_analysed_report(const std::filesystem::path& dir, const AnalysedGridshell& analysed,
                           nlohmann::json& report);

/// report.json's `structure.section`: the members' section (`frame.section`, else the bar of
/// `frame.diameter`) — designation, shape, process, whether a catalogue size, A, mass per metre,
/// Iy, Iz, It (sections/sections.h).
nlohmann::json section_block(const analysis::GridshellFrameOptions& frame);

}  // namespace gridshell
