#pragma once
/// \file builtin.h
/// Surfaces the program generates itself, selected as `builtin:NAME[:key=value,...]`, e.g.
/// `builtin:dome:span=30,rise=6,res=20`. Every one is a valid manifold triangle mesh, z up, in
/// metres, with its supports set; the meshes of the square and rectangular ones are symmetric
/// about the x and y planes through the centre.
///
/// | name        | shape                                                   | supports           |
/// |-------------|---------------------------------------------------------|--------------------|
/// | paraboloid  | z = rise (1 − (x²+y²)/(2h²)) over a square of side span | whole boundary     |
/// | dome        | spherical cap of plan diameter span and height rise      | whole boundary     |
/// | barrel      | circular barrel vault, chord span, length `length`      | the two ground edges |
/// | court       | rectangle span × width with a central circular hole     | both boundaries    |
/// |             | (radius `hole`), z = rise · 4t(1−t) between them         |                    |
/// | funicular   | force-density form-found shell on a square plan, four   | a few nodes at each
/// corner | |             | corner supports, stiffer edge cables, crown height rise  | |
///
/// Keys: span, rise, res (divisions along the span), and width / length / hole / edge_q /
/// corner where they apply. Defaults give meshes of a few thousand triangles.
///
/// Bounds (anything else is an Error naming the key, from the command line and the studio):
/// span, width and length in [0.1, 1000] m; rise in [0.01, 1000] m (and at most half the span
/// for dome and barrel); hole in [0.01, 500] m and inside the rectangle; edge_q in [0.01, 100];
/// res and corner whole numbers written as digits, res in [2, 2000], corner in [0, 2000]. The
/// mesh's vertex count is computed before anything is allocated and may not exceed
/// kMaxBuiltinVertices (res ≤ 1000 for paraboloid and funicular, ≤ 1155 for dome; a barrel's
/// rows grow with length / span).

#include <string>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

/// The most vertices a built-in surface may have: a 1001 × 1001 grid, res=1000 of a paraboloid
/// or funicular (about 2 M triangles; about 100 MB of mesh and topology).
inline constexpr long kMaxBuiltinVertices = 1001L * 1001L;
inline constexpr double kBuiltinMinSize = 0.1;   ///< m: span, width, length
inline constexpr double kBuiltinMaxSize = 1000;  ///< m: span, width, length, rise
inline constexpr double kBuiltinMinRise = 1e-6;  ///< m: rise (a nearly flat plate is a valid test surface)
inline constexpr double kBuiltinMinHole = 0.01;  ///< m: hole
inline constexpr int kBuiltinMaxRes = 2000;      ///< res, corner

struct BuiltinOptions {
  double span = 0;    ///< m; 0 = the surface's default
  double rise = 0;    ///< m
  int res = 0;        ///< divisions along the span
  double width = 0;   ///< court: plan width (m)
  double length = 0;  ///< barrel: length (m)
  double hole = 0;    ///< court: hole radius (m)
  double edge_q = 0;  ///< funicular: force density of the edge cables relative to the net
  int corner = -1;    ///< funicular: supported nodes along each edge from each corner
};

/// Names accepted after `builtin:`.
std::vector<std::string> builtin_names();

/// Parses `NAME[:key=value,...]` (without the `builtin:` prefix) and builds the surface.
/// Throws Error for an unknown name, key or an invalid value.
Surface make_builtin(const std::string& spec);

/// The canonical text of a spec `NAME[:key=value,...]`: keys sorted, the last of a repeated key,
/// numbers in their shortest exact form (`dome:span=20.0,res=12` → `dome:res=12,span=20`), so
/// equal specs give equal text (a cache key). Throws as make_builtin does for an unknown name, key
/// or a value out of bounds; does not build the surface (limits that depend on several keys, such
/// as the vertex count, are checked by make_builtin).
std::string canonical_builtin(const std::string& spec);

/// Builds a named surface with explicit options (0, and corner −1, take the default; set values
/// obey the bounds above).
Surface make_builtin(const std::string& name, const BuiltinOptions& options);

/// The funicular shell and its force-density equilibrium residual (relative), for tests.
struct FunicularResult {
  Surface surface;
  double residual = 0;
};
FunicularResult make_funicular(const BuiltinOptions& options);

}  // namespace gridshell
