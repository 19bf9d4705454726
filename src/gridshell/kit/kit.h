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
///   per beam (CGAL corefinement) and a flat base carrying the engraved id, bridges cut, the
///   socket holes and the engraving subtracted.
/// - rods.csv  `rod,joint_i,joint_j,length_mm` (rod = beam id of beams.csv), longest first:
///   rod length = beam length at scale − the two seats (the distance from each joint's centre to
///   its socket's floor).
/// - panels.svg, panels.dxf  (when the folder has panels.csv) every panel's flat outline at
///   scale, labelled with its id, nested on the laser's bed (`bed_width` × `bed_height`), each
///   outline offset outward by half the `kerf` so that the part cut out has the panel's size
///   (fabrication/panel_sheets.h). The outline is the panel's centre-line polygon: the panel
///   rests on the rods.
/// - bridges.csv  `beam,joint_i,joint_j,glue_radius_mm`: the beams printed as glued bridges.
/// - assembly.html  the joints in the order to put them together (kit/assembly.h).
///
/// Geometry per joint: socket hole radius r = rod/2 + clearance, sleeve radius r + wall. The
/// seat s (socket floor's distance from the centre) is the smallest that keeps every pair of
/// holes a wall apart: for two beams at angle θ, s ≥ (wall/2 + r cos θ/2) / sin θ/2 (and
/// s ≥ r). The socket depth is `depth_factor` × rod, shortened on a beam too short at scale to
/// hold two full sockets and a `gap` between the sleeves (counted in KitResult).
///
/// Bridges: a beam too short at scale for a rod with two sockets of at least `min_socket` is
/// printed instead: each of its joints gets a solid stub of the sleeve's radius along the beam,
/// and the whole part is cut by the beam's mid-plane, so the two halves meet face to face in
/// the same flat glue disc (radius sleeve − wall/4) and are glued. A relief slab wall/4 deep
/// before the mid-plane clears everything else of the part outside that disc, so the two faces
/// coincide exactly whatever else of either part reaches the plane. A beam whose socket would
/// reach another bridge's cut at its joint (its rod would run into the glued neighbour) is a
/// bridge too. Bridged beams are no rods.
///
/// Base and id: every joint has a flat base: a stem from the hub along `base_normal` (straight
/// down for a supported joint, its foot; else the joint's inward surface normal) into a plate
/// whose outer face lies below every other part of the hub in that direction, so the joint
/// prints standing on it; the joint's id is engraved in that face (kit/label.h), mirrored to
/// read from outside.
///
/// Cost: per joint three corefinements of meshes of a few hundred triangles (sphere ∪ sleeves,
/// ∪ base, minus the holes and the id; one more per bridge but the last), with exact
/// constructions on corners snapped to a 2^-20 mm grid (docs/performance.md, "The model kit of
/// a 1200-cell roof").

#include <filesystem>
#include <string>
#include <vector>

#include "gridshell/fabrication/panel_sheets.h"
#include "gridshell/kit/plate.h"
#include "gridshell/kit/stl.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell::kit {

struct KitOptions {
  double scale = 50;        ///< the model is 1 : scale
  double rod_diameter = 3;  ///< [mm]
  double clearance = 0.1;   ///< radial play between rod and socket wall [mm]
  double depth_factor = 3;  ///< socket depth = depth_factor × rod_diameter
  double wall = 1.2;        ///< sleeve wall, and the least material between two holes [mm]
  double gap = 1;           ///< least free rod between the sleeves of two joints [mm]
  /// Least socket depth [mm] (0: one rod diameter): a beam whose rod would have a shallower
  /// socket is a printed bridge (see above).
  double min_socket = 0;
  double label_stroke = 0.6;  ///< width of the engraved digits' strokes [mm] (≥ 0.6)
  double label_depth = 0.4;   ///< depth of the engraving [mm]
  /// The socket holes' polygons have their corners on the hole's radius r; their flat sides lie
  /// at most `tolerance` inside it (r − r·cos(π/n)) [mm].
  double tolerance = 0.02;
  int segments = 0;  ///< sides of the cylinders' polygons; 0 = the fewest within `tolerance`
  double bed_width = 600, bed_height = 400;  ///< the laser cutter's bed [mm]
  double kerf = 0.15;  ///< width the laser burns away [mm] (0.1–0.2 mm in 3 mm acrylic)
  PrintBed print_bed;  ///< the 3-D printer's bed for the plates (kit/plate.h) [mm]
};

/// Throws Error naming the option (`--scale`, `--rod`, …) when an option is out of range.
void check_kit_options(const KitOptions& options);

/// The sides of every cylinder's polygon (sleeves, holes; a foot's disc has twice as many):
/// `segments`, or the fewest n ≥ 12 with r·(1 − cos(π/n)) ≤ `tolerance` for the hole radius r
/// (20 for a 3 mm rod with 0.1 mm clearance and the default 0.02 mm).
int polygon_sides(const KitOptions& options);

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
  double depth = 0;           ///< floor to mouth (0 on a bridge)
  double radius = 0;          ///< hole radius (rod/2 + clearance)
  /// A printed bridge (no hole, no rod): a solid stub along `axis`, the part cut flat by the
  /// beam's mid-plane at `mid` from the centre; the glue disc's polygon (radius `disc`, at most
  /// sleeve − wall/4, less where another cut or a hole of either joint comes near) starts at
  /// `disc_u` (unit, ⟂ axis): the same at both ends of the beam, so both discs coincide. disc 0:
  /// under a quarter sleeve of room (another bridge at an acute angle cuts the beam's middle
  /// away): the parts stop a relief short of the mid-plane and meet only through neighbours.
  bool bridge = false;
  double mid = 0, disc = 0;
  Vec3 disc_u = Vec3::UnitY();
};
struct HubPlan {
  int joint = 0;
  double hub_radius = 0;     ///< the central sphere [mm]
  double sleeve_radius = 0;  ///< outer radius of the sleeves [mm]
  std::vector<Socket> sockets;
  /// Where the sleeves start along their axes [mm]: beyond it no two sleeves meet, and the
  /// sphere (`hub_radius`) covers their start caps, so one union joins them all to the sphere.
  /// 0 = the sleeves of this joint meet (beams too close for a sphere short of the sockets'
  /// mouths): they start half a sleeve radius off-centre and are joined one by one.
  double sleeve_start = 0;
  /// The flat base: unit outward normal of the base face (the part prints with base_normal
  /// pointing to −z) and the base plane's distance from the centre [mm]: every point x of the
  /// part has x·base_normal ≤ base. The base is a disc of `base_radius` about
  /// base·base_normal (a wall thick, on a stem of the sleeves' radius), less any bridge cut.
  Vec3 base_normal = -Vec3::UnitZ();
  double base = 0, base_radius = 0;
  /// True when base_normal is straight down (a supported joint's foot: it stands on the base
  /// board as it stands in the roof).
  bool foot = false;
  /// The engraved id's frame in the base plane: reading direction and up (label_x × label_y =
  /// base_normal, so it reads from outside); the text is centred on the disc's centre.
  Vec3 label_x = Vec3::UnitX(), label_y = Vec3::UnitY();
  /// False when the id could not be placed clear of a bridge cut; the plate is then left uncut
  /// and overlaps its glued neighbour's (trim it after assembly; counted in KitResult).
  bool plate_cut = true;
};

/// The hub's sphere is a UV polygon of kSphereBands latitude bands × kSphereSides longitudes,
/// its corners on the sphere; its faces lie at least kSphereInscribed of its radius from the
/// centre (the 8 × 16 polygon's: 0.96264).
inline constexpr int kSphereBands = 8, kSphereSides = 16;
inline constexpr double kSphereInscribed = 0.9626;

/// The hubs of every joint (joint id order): their sockets' seats and depths, the sleeves'
/// start and the sphere. The sphere has 1.25 sleeve radii, or more where the sleeves start
/// farther out: for two beams at angle θ, sleeves of radius R are disjoint beyond
/// R·cot(θ/2) along their axes; they start at R·(cot(θ/2) + 0.1) (at least R/2) and the sphere's
/// polygon covers their start caps with 2% to spare.
std::vector<HubPlan> plan_hubs(const KitFrame& frame, const KitOptions& options);

struct Rod {
  int beam = 0, joint_i = 0, joint_j = 0;
  double length_mm = 0;
};
/// Every beam's rod but the bridges: its length at scale minus the two seats, longest first
/// (ties by beam id). Throws Error when a bridge would be too short to cut (the scale is far too
/// small for the hubs).
std::vector<Rod> cut_list(const KitFrame& frame, const std::vector<HubPlan>& hubs,
                          const KitOptions& options);
std::string rods_csv(const std::vector<Rod>& rods);

/// Per beam id: 1 when it is a printed bridge (Socket::bridge), else 0.
std::vector<char> bridged_beams(const KitFrame& frame, const std::vector<HubPlan>& hubs);
/// `beam,joint_i,joint_j,glue_radius_mm` for every bridged beam (beam id order): the joints to
/// glue together and their glue disc's radius (0: the parts do not meet on this beam).
std::string bridges_csv(const KitFrame& frame, const std::vector<HubPlan>& hubs);

/// The printable hub's closed surface (kit_mesh.cpp: CGAL corefinement), corners rounded to
/// float32 as its STL holds them. Throws Error when a boolean fails.
PartMesh hub_part(const HubPlan& hub, const KitOptions& options);
/// The same as binary STL bytes (kit/stl.h).
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
  int bridges = 0;        ///< beams printed as glued bridges (no rod)
  int unglued = 0;        ///< bridges whose parts do not meet (Socket::disc 0)
  int uncut_plates = 0;   ///< bases left uncut by a bridge to keep the id (HubPlan::plate_cut)
  int plates = 0;         ///< print plates the joints take
  double rod_total_mm = 0;
};
/// Writes OUT/joints/J<id>.stl, OUT/plates/plate_<k>.stl, OUT/plates.csv (kit/plate.h),
/// OUT/rods.csv, OUT/bridges.csv, OUT/assembly.html and (with panels.csv) OUT/panels.svg and
/// OUT/panels.dxf, atomically, for the design folder `dir`.
KitResult write_kit(const std::filesystem::path& dir, const std::filesystem::path& out,
                    const KitOptions& options = {});

}  // namespace gridshell::kit
