#pragma once
/// \file fabrication_files.h
/// The fabrication files of a grid-shell and report.json's `fabrication` block (bill of
/// materials). Written into every design / baseline / analyze folder that has a polygon mesh:
///
/// - joints.csv  `joint,x,y,z,valence,support,beams,angles_deg` — beams: incident beam ids
///   counter-clockwise about the joint's normal, space-separated; angles_deg: the angle from
///   each of them to the next in the joint's tangent plane (same order, cyclic, Σ = 360).
/// - beams.csv   `beam,node_i,node_j,length,axial_force,utilisation,buckling_utilisation,
///   length_class,panels,section,governing` — the CONTRACT's analyze columns first (length = cut length =
///   centre-line length [m]; axial_force [N], tension positive, empty when not analysed), the
///   member checks (cross-section and flexural buckling utilisation, checks/member_checks.h;
///   empty when not analysed), then the beam's length class (distinct lengths at
///   `length_resolution`, 0 = shortest), the panels on either side (space-separated), the
///   beam's section (its designation, sections/sections.h) and the clause that governs its
///   checks (empty when not analysed).
/// - panels.csv  `panel,sides,joints,area,planarity,edge_length_error,sheet,rotation_deg,
///   offset_x,offset_y,outline,out_of_plane_mm` — joints in face order; outline: the flattened
///   corners as space-separated x y pairs in the panel's own plane [m]; on the sheet a corner p
///   lands at R(rotation_deg) p + offset (sheet −1: larger than a sheet, not nested);
///   out_of_plane_mm: the largest corner distance to the panel's best-fit plane (what the glass
///   and its bedding must take up; ~1e-9 for `--panels flat`).
/// - panels.svg  every panel flattened, labelled with its id, nested on its sheet (millimetres).
///
/// All numbers SI; files written atomically. Cost: linear in the mesh (nesting O(panels ·
/// shelves)).

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gridshell/fabrication/fabrication.h"
#include "gridshell/fabrication/nesting.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell::fabrication {

struct FabricationFileOptions {
  SheetOptions sheet;
  FabricationOptions parts;
  double bar_diameter = 0.037;  ///< solid circular bars [m], for the mass
  double bar_density = 7850;    ///< [kg/m³]
  /// The members' section: its designation for beams.csv and the bill of materials, and its area
  /// [m²] for the mass; empty / 0 = the bar of `bar_diameter`.
  std::string section;
  double section_area = 0;
  /// A sized design's sections per beam (topology edge order): designation and area [m²];
  /// empty = every beam has `section`.
  std::vector<std::string> beam_sections;
  std::vector<double> beam_areas;
};

/// What an analysis says per beam (topology edge order); each empty when not analysed.
struct BeamResults {
  std::vector<double> axial_force;           ///< [N], tension positive
  std::vector<double> utilisation;           ///< cross-section utilisation
  std::vector<double> buckling_utilisation;  ///< flexural buckling utilisation
  std::vector<std::string> governing;        ///< the clause governing the larger of the two
};

/// Everything the files show, computed once.
struct FabricationData {
  Fabrication parts;
  Nesting nesting;
  std::vector<double> axial_force;  ///< per beam [N], empty when not analysed
  std::vector<double> utilisation, buckling_utilisation;  ///< per beam, empty when not analysed
  std::vector<std::string> governing;                     ///< per beam, empty when not analysed
  std::vector<std::string> sections;  ///< per beam its designation
  std::vector<double> areas;           ///< per beam its section area [m²]
};

/// Parts and nesting of `mesh`. `beams`: each per topology edge (the frame's member order), or
/// empty; throws Error when a size is neither.
FabricationData fabrication_data(const PolyMesh& mesh, const std::vector<int>& supports,
                                 const BeamResults& beams,
                                 const FabricationFileOptions& options = {});

/// The file contents (exposed for tests).
std::string joints_csv(const FabricationData& d);
std::string beams_csv(const FabricationData& d);
std::string panels_csv(const FabricationData& d);
std::string panels_svg(const FabricationData& d, const SheetOptions& sheet);

/// report.json's `fabrication` block: counts of joints, beams and panels, total length, mass at
/// the bars' density and diameter, distinct beam lengths, sheets used, oversize panels, …
nlohmann::json bill_of_materials(const FabricationData& d, const FabricationFileOptions& options);

/// Writes joints.csv, beams.csv, panels.csv and panels.svg into `dir` (which must exist) and
/// returns bill_of_materials.
nlohmann::json write_fabrication_files(const std::filesystem::path& dir, const PolyMesh& mesh,
                                       const std::vector<int>& supports, const BeamResults& beams,
                                       const FabricationFileOptions& options = {});

}  // namespace gridshell::fabrication
