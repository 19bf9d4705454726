#pragma once
/// \file plate.h
/// The printed joints of a kit laid out on a 3-D printer's bed, ready to slice: every joint
/// once, turned so that its flat base lies on the bed (z = 0), packed on as few plates as a
/// shelf packing gives.
///
/// Method, per joint: the rotation taking its base's outward normal to −z (the shortest
/// rotation between the two; a part without a base is printed as it stands in the roof, −z
/// down), the lift putting its lowest point on z = 0, and its footprint, the convex hull of its
/// vertices seen from above. The footprints go to fabrication/nesting.h: each is turned about
/// the vertical to its smallest-area bounding rectangle and the rectangles, grown by `gap`, are
/// packed `margin` inside the bed by first-fit decreasing-height shelf packing. Rectangles
/// never overlap, so neither do the parts they hold. A part whose footprint fits the bed in
/// neither orientation is an error naming `--print-bed`.
///
/// Files: OUT/plates/plate_<k>.stl (k = 0, 1, …; one binary STL per plate, the parts as
/// separate closed shells, joint id order, each a rigid motion of its joints/J<id>.stl) and
/// OUT/plates.csv `joint,plate,x_mm,y_mm,rotation_deg`: where the joint's centre lands on its
/// plate (from the bed's front-left corner) and its turn about the vertical after being laid
/// base down. Cost: O(v log v) per part of v corners plus the packing's O(parts · shelves).

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "gridshell/kit/stl.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell::kit {

struct HubPlan;

/// The printer's bed [mm]. The default, 200 × 200 mm, fits the beds of the common desktop
/// printers (Prusa MK3/MK4 250 × 210, Creality Ender-3 220 × 220, Bambu Lab P1/X1/A1 256 × 256).
struct PrintBed {
  double width = 200, height = 200;
  double gap = 3;     ///< clear distance between two parts' footprint rectangles
  double margin = 5;  ///< clear distance from the bed's edges
};

/// Throws Error("--print-bed") for a bed smaller than 20 mm or larger than 2000 mm a side.
void check_print_bed(const PrintBed& bed);

/// The plane a part is printed on: outward unit normal and its distance from the joint's
/// centre (every point x of the part has x · normal ≤ distance). `flat` = the part has a flat
/// face there (otherwise the plane only touches its lowest point).
struct PartBase {
  Vec3 normal = -Vec3::UnitZ();
  double distance = 0;
  bool flat = false;
};

/// A joint's base: its plan's flat base (HubPlan::base_normal, HubPlan::base); none (`flat`
/// false, printed as it stands) for a hub without one.
PartBase part_base(const HubPlan& hub);

/// A part turned base down: plate coordinates before packing = tilt · p + (0, 0, lift).
struct LaidPart {
  int joint = 0;
  Eigen::Matrix3d tilt = Eigen::Matrix3d::Identity();
  double lift = 0;
  std::vector<Eigen::Vector2d> footprint;  ///< convex hull of the tilted vertices' (x, y)
};

/// Lays `mesh` (a joint's solid in its own frame [mm]) base down on z = 0; its footprint is
/// CGAL's convex hull of the tilted corners seen from above.
LaidPart lay_part(int joint, const PartMesh& mesh, const PartBase& base);

/// Where a part lands: plate coordinates = rotation · p + offset, for p in the joint's frame.
struct PlacedPart {
  int joint = 0;
  int plate = 0;
  double turn = 0;  ///< about the vertical after the tilt [rad], counter-clockwise
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Vec3 offset = Vec3::Zero();  ///< (x, y) = the joint's centre on the bed [mm]
};
struct Plates {
  std::vector<PlacedPart> parts;  ///< in the order of the laid parts given
  int plates = 0;
};

/// Packs the laid parts on plates of `bed`. Throws Error("--print-bed") naming the first part
/// too large for it.
Plates pack_plates(const std::vector<LaidPart>& parts, const PrintBed& bed);

/// plates.csv: `joint,plate,x_mm,y_mm,rotation_deg`, plate by plate, joint ids rising.
std::string plates_csv(const Plates& plates);

/// Writes OUT/plates/plate_<k>.stl (atomically) for every plate: each part is `meshes[i]`
/// (the mesh of plates.parts[i], the corners its J<id>.stl holds) moved rigidly.
void write_plate_stls(const Plates& plates, const std::vector<PartMesh>& meshes,
                      const std::filesystem::path& plates_dir);

}  // namespace gridshell::kit
