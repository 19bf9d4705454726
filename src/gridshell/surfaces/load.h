#pragma once
/// \file load.h
/// Turning what a user names on the command line into a `Surface`: a mesh file or
/// `builtin:NAME[:key=value,...]`, re-oriented (`up`), scaled, with its supports.
///
/// Real files are messy. `load_surface` repairs what it safely can (mesh/repair.h: merges
/// duplicate and nearly coincident vertices, drops faces without area and unreferenced vertices —
/// vertex ids after them shift down, so per-vertex output and a CSV field refer to the repaired
/// surface —, orients faces consistently), keeps sliver triangles, and says what it did in one
/// `spdlog::warn` line, which also says when the surface is larger than kLargestRoof (a file in
/// millimetres read as metres) or more than kTallerThanWide times as tall as its plan is wide (a
/// y-up file read without `--up y`). `load_poly_surface` (grid-shells
/// for `analyze`, any mesh for `info`) reads the file as it is.
///
/// Support colour: a vertex is a support when its colour is red — red channel at least 128,
/// green and blue each at most a quarter of it. Pure red (255,0,0) is what our PLY writer uses;
/// near-reds such as (254,0,0), (255,10,10) or a dark (160,20,20) count too (with a warning
/// line), orange (255,128,0), pink (255,192,203) and grey do not.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct SurfaceOptions {
  /// "auto" (the red vertices if the file has any, else the built-in's own supports or the whole
  /// boundary), "red", "boundary", or a path to a JSON list of vertex ids (ids of the file's
  /// vertices; ones the repair drops are ignored with a warning, merged ones follow the merge).
  std::string supports = "auto";
  std::string up = "z";  ///< the file's up axis: z, y or -y
  double scale = 1.0;    ///< multiplies coordinates
};

/// Coordinates are metres; a surface whose bounding box's diagonal exceeds this is most likely
/// in millimetres (the largest grid-shell roofs span a few hundred metres).
inline constexpr double kLargestRoof = 2000;
/// A roof is lower than its plan is wide (hemispherical domes: half as tall; the six shared and
/// 27 other test surfaces: at most 0.5); a surface this many times as tall as the narrower side
/// of its plan is most likely lying on its side (a y-up file read as z-up).
inline constexpr double kTallerThanWide = 1.5;

/// Loads and prepares a surface (repairing it as above, triangulating polygons). Throws Error
/// for bad input, when no face with an area is left, or when it has no supports (a closed
/// surface without red vertices, an empty --supports list).
Surface load_surface(const std::string& spec, const SurfaceOptions& options = {});

/// Loads a polygon mesh (a grid-shell) with its supports, by the same rules, without repairs.
struct PolySurface {
  PolyMesh mesh;
  std::vector<int> supports;
};
PolySurface load_poly_surface(const std::string& path, const SurfaceOptions& options = {});

/// Loads a grid-shell for `analyze`: like load_poly_surface, but a file whose joints are written
/// once per panel (each face with its own copies of its corners, as per-face exporters do) or
/// nearly coincide is one structure, not a heap of loose panels. The mesh is repaired as
/// `load_surface` repairs (mesh/repair.h: joints within kWeldTolerance of the diagonal merged,
/// faces without area and unused joints dropped, faces oriented; one warning line) before the
/// supports are found, so "the boundary" is the repaired grid-shell's. With supports "auto", an
/// OBJ's `# supports` comment line (what our writer puts there) names them, by the file's ids.
/// A clean grid-shell is loaded as it is.
PolySurface load_gridshell(const std::string& path, const SurfaceOptions& options = {});

/// True for the colours that mark supports (the rule above).
bool is_support_colour(const std::array<std::uint8_t, 3>& rgb);

/// The default surface of `gridshell design`.
inline constexpr const char* kDefaultSurface = "builtin:funicular";

}  // namespace gridshell
