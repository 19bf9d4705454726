#pragma once
/// \file label.h
/// The flat base of a kit joint and the id engraved in it (kit.h, "Base and id").
///
/// Digits are seven-segment glyphs drawn as disjoint convex hexagons (each stroke `s` wide,
/// its ends mitred at 45°): a digit's cell is 4 s wide and 7 s high, digits s apart, every
/// segment 3 s from tip to tip along its centre-line with each tip drawn back by kStrokeGap s,
/// so neighbouring strokes stay kStrokeGap·√2·s apart (disjoint prisms: one cut subtracts them
/// with the socket holes). A segment's area is (3 − 2 kStrokeGap) s² − s²/2. The glyph outlines
/// are data; the solids are made by kit_mesh.cpp with CGAL.
///
/// The base direction: straight down (−z) for a supported joint (a foot), else minus the
/// joint's surface normal (joint_normal); the first of these, −n, +n that no beam comes within
/// 45° of. Cost: O(valence²) per joint.

#include <vector>

#include <Eigen/Core>

#include "gridshell/kit/kit.h"

namespace gridshell::kit {

/// Tips of a stroke drawn back from the cell's corner, in strokes.
inline constexpr double kStrokeGap = 0.1;
/// Depth of the relief slab before a bridge's mid-plane, in walls (kit.h "Bridges").
inline constexpr double kReliefWalls = 0.25;

using Polygon2 = std::vector<Eigen::Vector2d>;

/// The segments (bit k = segment "abcdefg"[k]) lit for each digit 0–9.
int digit_segments(int digit);
/// The strokes of `id` (≥ 0) as disjoint convex counter-clockwise polygons, x the reading
/// direction, y up, the text's box centred at the origin [mm].
std::vector<Polygon2> label_strokes(int id, double stroke);
/// Half the width and half the height of the id's text box [mm].
Eigen::Vector2d label_half_size(int id, double stroke);

/// The unit outward normal of the surface at a joint estimated from its beams' unit directions:
/// the normal of the plane nearest to them (for two nearly collinear beams, the direction ⟂ to
/// them nearest to +z), oriented with n·z ≥ 0.
Vec3 joint_normal(const std::vector<Vec3>& axes);

/// Sets hub's base (base_normal, base, base_radius, foot, label frame, plate_cut) from its
/// sockets, which must be planned (seat, depth, bridge, mid).
void plan_base(HubPlan& hub, bool supported, const KitOptions& options);

}  // namespace gridshell::kit
