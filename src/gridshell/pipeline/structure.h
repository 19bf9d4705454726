#pragma once
/// \file structure.h
/// The steel structure of a grid-shell, as design and baseline build it: the frame of
/// analysis/gridshell_frame.h analysed with the members' given section, or with every member
/// sized to the code (sizing/sizing.h, `--size`); and report.json's `sizing` block with the
/// figures of a sized design (steel mass per plan area, embodied carbon, distinct sections).

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/fabrication/fabrication_files.h"
#include "gridshell/mesh/mesh.h"
#include "gridshell/sizing/sizing.h"

namespace gridshell {

/// Embodied carbon of steel sections, cradle to gate (A1–A3) [kgCO2e/kg]: the ICE database
/// v3.0 (Circular Ecology / University of Bath, 2019) value for steel sections, world average
/// (docs/sizing.md). `--carbon-factor` sets a supplier's EPD value instead.
inline constexpr double kSteelCarbonFactor = 1.55;

struct StructureOptions {
  analysis::AnalysisLevel level = analysis::AnalysisLevel::nonlinear;
  sizing::MemberSizing sizing = sizing::MemberSizing::given;
  sizing::SizingOptions sizing_options;  ///< with MemberSizing::sized
};

struct GridshellStructure {
  /// The frame as analysed: the given options, with a sized design's `member_sections`.
  analysis::GridshellFrameOptions frame;
  analysis::FrameResult result;  ///< the primary combination (report.json `structure`)
  /// Sized: the sizing and its final analysis of every combination (report.json
  /// `structure.combinations` is written from them, not analysed again).
  std::optional<sizing::SizingResult> sizing;
};

/// Analyses (or sizes, then analyses) the grid-shell. Throws what the analyses throw.
GridshellStructure analyze_structure(const PolyMesh& mesh, const std::vector<int>& supports,
                                     const analysis::GridshellFrameOptions& frame,
                                     const analysis::FrameAnalysisOptions& options,
                                     const StructureOptions& structure);

/// Per member the envelope of a sized design's final analysis over its ULS combinations: the
/// axial force of the primary combination, the largest cross-section and buckling utilisations,
/// and the governing check as "clause under COMBINATION" (beams.csv's `governing`).
fabrication::BeamResults member_envelope(const sizing::SizingResult& sizing);

/// Per member (topology edge order) its section's designation; empty when every member has
/// the frame's one section.
std::vector<std::string> member_designations(const analysis::GridshellFrameOptions& frame);

/// Plan area [m²] of a grid-shell: Σ over panels of the vertical component of their vector area.
double plan_area(const PolyMesh& mesh);

/// report.json's `sizing` block: sized, convergence, failure, iterations, history, the list and
/// groups asked for, λ_min and the λ_LBA target reached, steel mass (kg, kg/m² of plan), embodied
/// carbon and its factor, the distinct sections (designation, members, length, mass).
nlohmann::json sizing_block(const sizing::SizingResult& sizing, const PolyMesh& mesh,
                            const analysis::GridshellFrameOptions& frame,
                            const sizing::SizingOptions& options, double carbon_factor);

/// Steel mass and embodied carbon of any design (sized or not): mass_kg, mass_kg_per_m2 (plan),
/// plan_area_m2, carbon_kgCO2e, carbon_factor_kgCO2e_per_kg, distinct_sections.
nlohmann::json steel_block(const PolyMesh& mesh, const analysis::GridshellFrameOptions& frame,
                           double carbon_factor);

}  // namespace gridshell
