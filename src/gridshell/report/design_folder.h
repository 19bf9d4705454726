#pragma once
/// \file design_folder.h
/// The design folder: every file `gridshell design -o DIR` writes for a designed grid-shell,
/// written by one function that both front ends call (`gridshell design`, and the studio's
/// export zip), so the two cannot drift apart:
///
///   gridshell.obj, gridshell_raw.obj, gridshell.ply, gridshell.vtp, cells.csv  (gridshell_output.h)
///   joints.csv, beams.csv, panels.csv, panels.svg              (fabrication, design_report.h)
///   field.vtp                                                  the field on the input surface
///   figures/*.png                                              figures/figures.h
///   frame.json, modes.csv                 when analysed        (pipeline/frame_output.h)
///   report.json  design_report + surface, fabrication, figures, and when analysed
///                structure.steel / loads / combinations / governing, mass, sizing; objective;
///                timings_s
///   config.json  the options as given (the caller's: CLI11's resolved options, or the studio's)
///   report.html  last: the page with the 3D view, reading report.json, config.json and figures
///
/// Why here (report/, the presentation layer) and not in pipeline/: the folder holds the figures
/// and report.html, and the pipeline sits below presentation (core numerics ← pipeline ←
/// presentation {figures, report, studio}). Everything the folder computes besides drawing (the
/// report blocks, the combinations, the fabrication files) is the pipeline's own functions;
/// this file only puts them in one order with the drawing.
///
/// Cost: that of the load combinations' analyses (design_report.h combinations_block: the ULS
/// ones other than the primary, linear + LBA) plus ~0.1 s per figure and the report page.

#include <cstdint>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "gridshell/core/timings.h"
#include "gridshell/fabrication/nesting.h"
#include "gridshell/figures/figures.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/design_settings.h"
#include "gridshell/pipeline/objective.h"
#include "gridshell/pipeline/structure.h"
#include "gridshell/report/report_html.h"
#include "gridshell/surfaces/load.h"

namespace gridshell::report {

/// What the folder is written from. The pointers must outlive the call; `search` may be null.
struct DesignFolderInput {
  const Surface* surface = nullptr;         ///< the input surface the design was made on
  const DesignOptions* options = nullptr;   ///< as the design ran
  const DesignResult* result = nullptr;     ///< the design (of `search` when it was searched)
  const ObjectiveResult* search = nullptr;  ///< the objective search that chose it, or null
  std::string surface_name;                 ///< report.json `surface`
  std::string title;                        ///< the figures' subtitle: what was run
  nlohmann::json config = nlohmann::json::object();  ///< config.json
  fabrication::SheetOptions sheet;                   ///< the sheets panels are nested on
  figures::FigureOptions figures;                    ///< `--figures`
  std::string steel = LoadCheckOptions{}.steel;  ///< report.json `structure.steel` (fy's grade)
  std::string sections = SizingArgs{}.sections;  ///< report.json `sizing.sections_list` (sized)
  double carbon_factor = kSteelCarbonFactor;  ///< kgCO2e/kg for report.json `mass`, `sizing`
  /// Stages measured before (e.g. `load`), and the seconds spent before the call (report.json
  /// `timings_s.total` adds the folder's own).
  Timings timings_before;
  double seconds_before = 0;
};

/// Writes the folder into `dir` (created if missing) and returns report.json as written.
/// Throws what the pipeline's functions throw (Error for bad input, e.g. an unwritable folder).
nlohmann::json write_design_folder(const std::filesystem::path& dir, const DesignFolderInput& in);

/// Writes DIR/report.html from `page` with `report` (report.json) and `config` (config.json),
/// titled "gridshell COMMAND POSITIONAL…" (or the report's surface); logs its size and time.
/// Call it last, after the figures.
ReportWritten write_report_page(const std::filesystem::path& dir, ReportInput page,
                                const nlohmann::json& report, const nlohmann::json& config);

}  // namespace gridshell::report
