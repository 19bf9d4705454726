#pragma once
/// \file gridshell_frame.h
/// A grid-shell (polygon mesh: edges = beams, vertices = joints, faces = panels) as a frame with
/// the paper's defaults: solid circular steel bars Ø37 mm, E = 210 GPa, ν = 0.3, 7850 kg/m³,
/// pinned supports (translations fixed), each beam split into `elements` elements, and the
/// paper's load: the bars' total weight spread over the surface, each joint taking a share
/// proportional to the area of its incident faces (1/n of each n-gon's area per corner), so that
/// λ is a multiple of the structure's own weight. An optional area load (kN/m², same
/// distribution) is added; `self_weight_at_bars` puts each bar's weight at its two ends instead.
/// All loads act along −z. Cost: O(edges + face corners).
///
/// `loads = eurocode` replaces the paper's load by named load cases and an EN 1990 combination
/// (docs/checks.md):
/// * G1 — the bars' self-weight, each bar's weight at its two ends;
/// * G2 — glass and cladding, `glass_kN_m2` per m² of panel surface (default 0.4 kN/m²:
///   10 mm laminated glass ≈ 0.25 kN/m² plus fittings and sealing), corners share each face;
/// * Q  — snow, `snow_kN_m2` = s_k per m² of plan, times the roof shape factor μ1 of the face's
///   slope α (EN 1991-1-3 §5.3.2, Table 5.2: 0.8 for 0° ≤ α ≤ 30°, 0.8 (60° − α) / 30° up to
///   60°, 0 above); a face's plan area and slope come from its area vector (Newell), corners
///   share it. Wind is out of scope.
/// * combinations (EN 1990 6.4.3.2 / 6.5.3, one variable action): ULS = 1.35 (G1 + G2) + 1.5 Q,
///   SLS (characteristic) = G1 + G2 + Q.
/// The frame carries one combination of the load cases of analysis/load_cases.h (the drifted
/// snow arrangements and file cases beside these): `combination_name`, or "ULS"/"SLS" by
/// `combination` (the primary: undrifted snow leading).

#include <string>
#include <utility>
#include <vector>

#include "gridshell/analysis/load_cases.h"
#include "gridshell/fem/frame_model.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell::analysis {

/// The load model: the paper's (self-weight spread over the surface, plus `area_load_kN_m2`) or
/// the Eurocode load cases and combinations. The option words of `--loads`.
enum class LoadModel { paper, eurocode };
LoadModel parse_load_model(const std::string& word);  ///< throws Error("--loads")
const char* to_string(LoadModel model);

/// An EN 1990 combination of the eurocode load cases.
enum class Combination { uls, sls };
const char* to_string(Combination combination);
/// Partial factors (γ_G, γ_Q): ULS (1.35, 1.5), SLS (1, 1).
std::pair<double, double> partial_factors(Combination combination);

/// Snow shape factor μ1 for a roof slope α [degrees] (EN 1991-1-3 Table 5.2).
double snow_shape_factor(double slope_deg);

struct GridshellFrameOptions {
  double diameter = 0.037;  ///< [m] the solid bar's, when `section` is empty
  /// The members' section as a designation (sections/sections.h: "CHS 88.9x4.0",
  /// "RHS 120x60x4 cold", "bar 37"); empty = the solid bar of `diameter`. An RHS stands with its
  /// height along the surface normal: each member's local z is the mean of its two joints'
  /// normals (area-weighted face normals) made orthogonal to the member (docs/frame.md).
  std::string section;
  double E = 210e9;         ///< [Pa]
  double nu = 0.3;
  double density = 7850;  ///< [kg/m³]
  double g = 9.81;        ///< [m/s²]
  int elements = 2;       ///< elements per beam
  bool self_weight = true;
  bool self_weight_at_bars = false;
  double area_load_kN_m2 = 0;
  LoadModel loads = LoadModel::paper;
  double glass_kN_m2 = 0.4;  ///< eurocode G2 [kN/m² of surface]
  double snow_kN_m2 = 1.0;   ///< eurocode Q: s_k [kN/m² of plan]; set it for the site
  Combination combination = Combination::uls;  ///< eurocode: which combination to build
  /// eurocode: a combination of eurocode_combinations by name; empty = by `combination`.
  std::string combination_name;
  /// eurocode: load cases from files (--load-case), beside G1, G2 and the snow arrangements.
  std::vector<FileLoadCase> load_cases;
  /// Per member (topology edge, mesh/topology.h order) its own section — a sized design
  /// (sizing/sizing.h); empty = every member has `section` (or the bar of `diameter`). The
  /// bars' self-weight (G1, or the paper's load) follows each member's section.
  std::vector<sections::Section> member_sections;
};

/// Every eurocode load case of the grid (G1, G2, S, S_x-, S_x+, S_y-, S_y+, the file cases)
/// as nodal forces, and their combinations (load_cases.h). `bar_weight_per_m` per topology edge.
std::vector<LoadCase> eurocode_cases(const PolyMesh& mesh,
                                     const std::vector<double>& bar_weight_per_m,
                                     const GridshellFrameOptions& options);

/// The eurocode load cases as vertical joint forces [N, negative down], one per vertex.
struct LoadCases {
  std::vector<double> G1, G2, Q;
};
LoadCases eurocode_load_cases(const PolyMesh& mesh, const std::vector<double>& bar_weight_per_m,
                              const GridshellFrameOptions& options);

fem::FrameModel gridshell_frame(const PolyMesh& mesh, const std::vector<int>& supports,
                                const GridshellFrameOptions& options = {});

/// The members' section of `options` (its `section`, else the bar of `diameter`). Throws
/// Error("--section") / Error("--diameter") for a bad one. With `member_sections` it is the
/// uniform section those replace (unused by the frame).
fem::FrameSection member_section(const GridshellFrameOptions& options);

/// The bars' weight per metre [N/m] of each member of a frame built by gridshell_frame (its
/// section's area × density × g; 0 without self-weight).
std::vector<double> bar_weights_per_m(const fem::FrameModel& model,
                                      const GridshellFrameOptions& options);

/// Per-vertex unit normals of a polygon mesh: the sum of the incident faces' vector areas,
/// normalised (zero where they cancel).
Points vertex_normals(const PolyMesh& mesh);

/// Per-vertex tributary area: Σ over incident faces of area / (number of corners).
std::vector<double> tributary_areas(const PolyMesh& mesh);

}  // namespace gridshell::analysis
