#pragma once
/// \file kit.h
/// A model kit of a grid-shell for a desk: one printable hub per joint with a socket per beam
/// along the beam's true 3-D direction, and the cut list of the rods between them (the mock-up
/// technique of Tonelli, Pietroni, Cignoni, Scopigno, STAG 2016). Input: a design / baseline /
/// analyze output folder (its joints.csv and beams.csv, docs/fabrication.md). Output, in
/// millimetres at the model's scale:
///
/// - joints/J<id>.stl  binary STL, one closed solid per joint, in the joint's own frame (the
///   joint's centre at the origin, the grid-shell's axes): a sphere hub united with one sleeve
///   per beam (CGAL corefinement) and, for a supported joint, a foot with a flat base, the
///   socket holes subtracted.
/// - rods.csv  `rod,joint_i,joint_j,length_mm` (rod = beam id of beams.csv), longest first:
///   rod length = beam length at scale − the two seats (the distance from each joint's centre to
///   its socket's floor).
/// - panels.svg, panels.dxf  (when the folder has panels.csv) every panel's flat outline at
///   scale, labelled with its id, nested on the laser's bed (`bed_width` × `bed_height`), each
///   outline offset outward by half the `kerf` so that the part cut out has the panel's size
///   (fabrication/panel_sheets.h). The outline is the panel's centre-line polygon: the panel
///   rests on the rods.
/// - assembly.html  the joints in the order to put them together (kit/assembly.h).
///
/// Geometry per joint: socket hole radius r = rod/2 + clearance, sleeve radius r + wall. The
/// seat s (socket floor's distance from the centre) is the smallest that keeps every pair of
/// holes a wall apart: for two beams at angle θ, s ≥ (wall/2 + r cos θ/2) / sin θ/2 (and
/// s ≥ r). The socket depth is `depth_factor` × rod, shortened on a beam too short at scale to
/// hold two full sockets and a `gap` between the sleeves (counted in KitResult).
///
/// Cost: per joint valence unions and valence differences of meshes of a few hundred
/// triangles, with exact constructions (about 0.07 s per joint of valence 3 on one core).

#include <filesystem>
#include <string>
#include <vector>

#include "gridshell/fabrication/panel_sheets.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell::kit {

struct KitOptions {
  double scale = 50;        ///< the model is 1 : scale
  double rod_diameter = 3;  ///< [mm]
  double clearance = 0.1;   ///< radial play between rod and socket wall [mm]
  double depth_factor = 3;  ///< socket depth = depth_factor × rod_diameter
  double wall = 1.2;        ///< sleeve wall, and the least material between two holes [mm]
  double gap = 1;           ///< least free rod between the sleeves of two joints [mm]
  int segments = 32;        ///< sides of the polygons approximating cylinders (vertices on r)
  double bed_width = 600, bed_height = 400;  ///< the laser cutter's bed [mm]
  double kerf = 0.15;  ///< width the laser burns away [mm] (0.1–0.2 mm in 3 mm acrylic)
};

/// Throws Error naming the option (`--scale`, `--rod`, …) when an option is out of range.
void check_kit_options(const KitOptions& options);

/// What the kit reads of a design folder (SI units, ids as in the files).
struct KitJoint {
  int id = 0;
  Vec3 position = Vec3::Zero();  ///< [m]
  bool support = false;
  std::vector<int> beams;  ///< incident beam ids
};
struct KitBeam {
  int id = 0, joint_i = 0, joint_j = 0;
  double length = 0;  ///< centre-line length [m]
};
struct KitFrame {
  std::vector<KitJoint> joints;  ///< indexed by joint id
  std::vector<KitBeam> beams;    ///< indexed by beam id
};

/// Reads DIR/joints.csv and DIR/beams.csv. Throws Error (one line) when the folder or a file
/// is missing, a header lacks a needed column, or a row is malformed or refers to a missing id.
KitFrame read_kit_frame(const std::filesystem::path& dir);

/// One socket of a hub, in the hub's frame (centre at the origin) [mm].
struct Socket {
  int beam = 0;
  Vec3 axis = Vec3::UnitX();  ///< unit, from the joint towards the beam's other joint
  double seat = 0;            ///< socket floor's distance from the centre
  double depth = 0;           ///< floor to mouth
  double radius = 0;          ///< hole radius (rod/2 + clearance)
};
struct HubPlan {
  int joint = 0;
  double hub_radius = 0;     ///< the central sphere [mm]
  double sleeve_radius = 0;  ///< outer radius of the sleeves [mm]
  std::vector<Socket> sockets;
  /// A supported joint's foot: a stem straight down (−z) ending in a flat disc of radius
  /// `foot_radius` whose underside lies `foot` below the centre, below every other part of
  /// the hub, so the joint stands on the base board as it stands in the roof [mm]; 0 = none
  /// (not supported, or a beam points within 45° of straight down, where the stem would be).
  double foot = 0, foot_radius = 0;
};

/// The hubs of every joint (joint id order) and their sockets' seats and depths.
std::vector<HubPlan> plan_hubs(const KitFrame& frame, const KitOptions& options);

struct Rod {
  int beam = 0, joint_i = 0, joint_j = 0;
  double length_mm = 0;
};
/// Every beam's rod: its length at scale minus the two seats, longest first (ties by beam id).
/// Throws Error when a rod would have no length (the scale is too small for the hubs).
std::vector<Rod> cut_list(const KitFrame& frame, const std::vector<HubPlan>& hubs,
                          const KitOptions& options);
std::string rods_csv(const std::vector<Rod>& rods);

/// The printable hub as binary STL bytes (kit_mesh.cpp: CGAL corefinement). Throws Error when a
/// boolean fails.
std::string hub_stl(const HubPlan& hub, const KitOptions& options);

/// The `outline` column of DIR/panels.csv (each panel's flat outline [m], panel id order).
/// Throws Error (one line) for a malformed file.
std::vector<std::vector<Eigen::Vector2d>> read_panel_outlines(const std::filesystem::path& path);

/// The outlines at the kit's scale nested on its laser bed, offset for its kerf.
fabrication::PanelSheets kit_panel_sheets(
    const std::vector<std::vector<Eigen::Vector2d>>& outlines, const KitOptions& options);

struct KitResult {
  int joints = 0, rods = 0;
  int panels = 0, panel_sheets = 0;  ///< laser-cut panels and the beds they take
  int short_sockets = 0;  ///< sockets shortened on beams too short at scale
  double rod_total_mm = 0;
};
/// Writes OUT/joints/J<id>.stl, OUT/rods.csv and (with panels.csv) OUT/panels.svg and
/// OUT/panels.dxf, atomically, for the design folder `dir`.
KitResult write_kit(const std::filesystem::path& dir, const std::filesystem::path& out,
                    const KitOptions& options = {});

}  // namespace gridshell::kit
