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

#include <string>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

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

/// Builds a named surface with explicit options.
Surface make_builtin(const std::string& name, const BuiltinOptions& options);

/// The funicular shell and its force-density equilibrium residual (relative), for tests.
struct FunicularResult {
  Surface surface;
  double residual = 0;
};
FunicularResult make_funicular(const BuiltinOptions& options);

}  // namespace gridshell
