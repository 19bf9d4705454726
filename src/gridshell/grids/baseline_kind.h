#pragma once
/// \file baseline_kind.h
/// The comparison grid-shells of `gridshell baseline --kind`.

#include <string>

namespace gridshell {

enum class BaselineKind {
  quad,         ///< isotropic square grid in plan (quad_grid.h)
  quad_aniso,   ///< quads following the stress field's directions and sizes (quad_aniso.h)
  tri,          ///< dual triangulation of the isotropic Voronoi tessellation (dual.h)
  voronoi_iso,  ///< the isotropic Voronoi design (D = A = 1)
  original,     ///< the surface file's own quads, stored as triangle pairs (recover_quads.h)
};

/// "quad", "quad-aniso", "tri", "voronoi-iso", "original"; throws Error("--kind", …) naming them
/// otherwise.
BaselineKind parse_baseline_kind(const std::string& word);
const char* to_string(BaselineKind kind);

}  // namespace gridshell
