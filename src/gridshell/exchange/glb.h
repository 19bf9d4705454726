#pragma once
/// \file glb.h
/// A grid-shell as one binary glTF 2.0 file (gridshell.glb), the format 3D viewers, Blender,
/// Rhino, the web and AR tools open directly. Written with tinygltf (Debian libtinygltf-dev).
///
/// - Mesh "beams": every beam a tube of its section's outer shape between its joints' centres —
///   a 12-sided prism of the outer diameter for round bars and CHS, a box b × h for RHS/SHS with
///   h along the beam's `up` (the surface normal, as the frame analysis orients it) — open at
///   the ends (they meet inside the joints); steel grey, metallic.
/// - Mesh "panels": every panel triangulated (minimum-area triangulation of its corner
///   polygon, CGAL), glass: light blue, translucent, double-sided.
/// - Each mesh's `extras` hold {"kind": "beams"|"panels", "count": N}, and every vertex carries
///   the custom attribute `_ID` (float): the id of its beam or panel (beams.csv, panels.csv), so
///   a reader can pick, count and colour the parts.
///
/// glTF is y-up in metres: a design point (x, y, z), z up, is written as (x, z, −y). Cost:
/// linear in beams and panels (about 100 bytes per beam and per panel corner).

#include <filesystem>
#include <string>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell::exchange {

struct GlbBeam {
  Vec3 a = Vec3::Zero(), b = Vec3::Zero();  ///< end joints [m]
  Vec3 up = Vec3::UnitZ();                  ///< the section's local z (need not be unit)
  bool round = true;                        ///< round (bar, CHS) or rectangular (RHS, SHS)
  double height = 0.037;  ///< round: outer diameter; rectangular: h (along `up`) [m]
  double width = 0;       ///< rectangular: b [m]
};

struct GlbModel {
  std::vector<GlbBeam> beams;                  ///< in beam-id order
  std::vector<std::vector<Vec3>> panels;        ///< corners in order, in panel-id order
};

/// The GLB file's bytes (exposed for tests).
std::string glb_bytes(const GlbModel& model);

/// Writes glb_bytes(model) to `path` atomically. Throws Error(path) when it cannot, or when a
/// coordinate is not finite.
void write_glb(const std::filesystem::path& path, const GlbModel& model);

}  // namespace gridshell::exchange
