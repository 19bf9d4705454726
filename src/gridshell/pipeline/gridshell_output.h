#pragma once
/// \file gridshell_output.h
/// The files every grid-shell producing command writes (design, baseline): gridshell.obj,
/// gridshell_raw.obj, gridshell.ply (support flags), gridshell.vtp (ParaView: beams and panels
/// with their figures, joints with support flags and displacements), cells.csv, and the `mesh`
/// block of report.json.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct GridShellOutput {
  PolyMesh mesh;                    ///< final grid-shell
  PolyMesh raw;                     ///< before regularization (same as mesh when none)
  std::vector<int> supports;        ///< joints that are supported (sorted)
  std::vector<double> d_target;     ///< per face, ≥ 1 (1 when the field is uniform)
  std::vector<double> a_target;     ///< per face, ≥ 1
  io::Attributes extra_cell_data;   ///< further per-face arrays for the .vtp
  io::Attributes extra_point_data;  ///< further per-vertex arrays for the .vtp
  std::vector<double> planarity;    ///< per face (empty: not computed)
  std::vector<double> regularity;   ///< per face (empty: not computed)
  /// From a frame analysis whose members are the mesh's topology edges and whose first nodes
  /// are the mesh's vertices (empty: not analysed): per beam, linear axial force [N] (tension
  /// positive); per joint, linear displacement [m].
  std::vector<double> beam_axial_force;
  Points joint_displacement;
};

/// Copies a frame analysis's per-beam and per-joint results into `out` (see above).
void add_structure(GridShellOutput& out, const analysis::FrameResult& structure);

/// Statistics of a polygon mesh used in reports and tests.
struct PolyStats {
  int vertices = 0, faces = 0, edges = 0;
  double total_length = 0, edge_length_cv = 0, min_edge = 0, max_edge = 0;
  std::map<int, int> face_sides;
  double hex_share_interior = 0;       ///< hexagons among faces with no boundary vertex
  double valence3_share_interior = 0;  ///< valence-3 vertices among non-boundary vertices
  int boundary_loops = 0, euler = 0;
  /// Beams that cross and joints inside a panel not their own (mesh/overlaps.h): 0 for a grid
  /// that can be built.
  int overlaps = 0;
};
PolyStats poly_stats(const PolyMesh& mesh);

/// The report.json `mesh` block (CONTRACT keys plus statistics).
nlohmann::json mesh_block(const GridShellOutput& out);

/// Writes the files listed above into `dir` (which must exist).
void write_gridshell_files(const std::filesystem::path& dir, const GridShellOutput& out);

/// Writes only gridshell.vtp: the beams (lines: `beam_id`, `length`, `axial_force` when analysed)
/// and the panels (polygons: `panel_id`, sides, area, targets, planarity, regularity) in one
/// piece, cell array `is_beam` telling them apart; per joint `joint_id`, `support` and
/// `displacement` when analysed. Ids are those of joints.csv, beams.csv and panels.csv.
void write_gridshell_vtp(const std::filesystem::path& dir, const GridShellOutput& out);

}  // namespace gridshell
