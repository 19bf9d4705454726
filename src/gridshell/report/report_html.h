#pragma once
/// \file report_html.h
/// report.html: one self-contained page per design / baseline / analyze folder that opens from
/// disk with no server and no network. It holds
///
/// - the page template and the viewer script (three.js bundled at build time, assets.h),
/// - the grid-shell and its results as JSON in `<script type="application/json"
///   id="gridshell-data">`: joints, beams, panels, supports, per-beam axial force, per-joint
///   displacement, per-panel density and planarity, per-beam utilisation and section (when
///   known), the buckling modes, report.json and config.json,
/// - every `figures/*.png` of the folder as a base64 data: URI.
///
/// One numbering everywhere: joint j = mesh vertex j (joints.csv, nodes.csv), beam b = Topology
/// edge b (beams.csv, the frame's member order), panel p = face p (panels.csv, cells.csv).
/// Numbers are written with a few significant digits (coordinates 6, results 5, mode shapes 4),
/// so a 10 K-beam grid-shell gives about 1.5 MB of data next to 0.6 MB of viewer (docs/report.md).
/// Cost: linear in the mesh; the file is written atomically.

#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/fem/frame_model.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell::report {

/// What the page shows. Per-item arrays are either empty (unknown: the page offers no colour
/// mode for them) or exactly as long as what they describe; write_report_html checks that.
struct ReportInput {
  std::string title = "gridshell report";
  Points joints;                             ///< joint positions [m]
  std::vector<std::array<int, 2>> beams;     ///< joint pairs, in beams.csv order
  std::vector<std::vector<int>> panels;      ///< joint cycles, in panels.csv order (may be empty)
  std::vector<int> supports;                 ///< supported joints
  std::vector<double> axial_force;           ///< per beam [N], tension positive
  Points displacement;                       ///< per joint [m], linear under the reference load
  std::vector<double> density;               ///< per panel: d_target (≥ 1)
  std::vector<double> planarity;             ///< per panel (optimize/metrics.h)
  std::vector<double> out_of_plane_mm;       ///< per panel: largest corner distance to its plane
  std::vector<double> utilisation;           ///< per beam: cross-section utilisation (§6.2)
  std::vector<double> buckling_utilisation;  ///< per beam: member buckling utilisation (§6.3)
  /// Per beam its section's designation (beams.csv `section`), e.g. "CHS 88.9x3.2"; empty when
  /// every beam has the one section of the run (the page then offers no section colouring).
  std::vector<std::string> beam_sections;
  std::vector<double> buckling_lambdas;  ///< per mode
  std::vector<Points> buckling_modes;    ///< per mode, per joint translation (largest 1)
  nlohmann::json report = nlohmann::json::object();  ///< report.json (key figures, timings)
  nlohmann::json config = nlohmann::json::object();  ///< config.json (the options)
};

/// The input for a polygon grid-shell: beams are the Topology edges of `mesh`, panels its
/// faces, planarity computed here; axial forces, displacements and buckling modes from
/// `structure` when given (its model node j = joint j, its members = the Topology edges).
ReportInput gridshell_report_input(const PolyMesh& mesh, const std::vector<int>& supports,
                                   const analysis::FrameResult* structure);

/// The input for a frame model (MODEL.json): joints are its nodes, beams its members, panels its
/// optional faces, beam sections its members' section names when it has more than one.
ReportInput frame_report_input(const fem::FrameModel& model, const std::vector<int>& supports,
                               const analysis::FrameResult& structure);

/// A PNG figure as it goes into the page.
struct Figure {
  std::string name;  ///< file name, e.g. "axial_force.png"
  std::string png;   ///< the file's bytes
};

/// Every `dir/figures/*.png`, sorted by name (none when the folder is missing).
std::vector<Figure> read_figures(const std::filesystem::path& dir);

/// The page's data block (JSON text; `<` escaped so that it cannot end the script element).
/// Throws Error("report.html", …) when an array has the wrong length, an index is out of range
/// or a number is not finite.
std::string report_data_json(const ReportInput& input, const std::vector<Figure>& figures);

/// The whole page: the template with the title, data and viewer filled in.
std::string report_html(const ReportInput& input, const std::vector<Figure>& figures);

struct ReportWritten {
  std::filesystem::path path;
  std::size_t bytes = 0;
  int figures = 0;
  double seconds = 0;  ///< time to build and write the page
};

/// Writes `dir/report.html` atomically with the figures present in `dir/figures` now.
ReportWritten write_report_html(const std::filesystem::path& dir, const ReportInput& input);

}  // namespace gridshell::report
