#pragma once
/// \file load.h
/// Turning what a user names on the command line into a `Surface`: a mesh file or
/// `builtin:NAME[:key=value,...]`, re-oriented (`up`), scaled, with its supports.

#include <string>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct SurfaceOptions {
  /// "auto" (red if the file has pure red (255,0,0) vertices, else the built-in's own supports or
  /// the whole boundary), "red", "boundary", or a path to a JSON list of vertex ids.
  std::string supports = "auto";
  std::string up = "z";  ///< the file's up axis: z, y or -y
  double scale = 1.0;    ///< multiplies coordinates
};

/// Loads and prepares a surface (triangulating polygons). Throws Error for bad input.
Surface load_surface(const std::string& spec, const SurfaceOptions& options = {});

/// Loads a polygon mesh (a grid-shell) with its supports, by the same rules.
struct PolySurface {
  PolyMesh mesh;
  std::vector<int> supports;
};
PolySurface load_poly_surface(const std::string& path, const SurfaceOptions& options = {});

/// The default surface of `gridshell design`.
inline constexpr const char* kDefaultSurface = "builtin:funicular";

}  // namespace gridshell
