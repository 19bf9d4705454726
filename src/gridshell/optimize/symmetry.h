#pragma once
/// \file symmetry.h
/// Mirror symmetry of the input surface and of the grid-shell (GUIDE stage 11): detect whether M
/// is symmetric about the x / y planes through its bounding-box centre, and build an exactly
/// symmetric polygon mesh from the tessellation of one sector by reflecting it and welding it
/// along the planes.

#include <string>
#include <vector>

#include "gridshell/mesh/geometry.h"  // Plane
#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct SymmetryReport {
  Vec3 center = Vec3::Zero();  ///< bounding-box centre of M
  double diagonal = 0;         ///< bounding-box diagonal of M (m)
  Plane x_plane, y_plane;      ///< x = centre.x (normal +x), y = centre.y (normal +y)
  /// Max distance from a reflected vertex of M to M, divided by the diagonal.
  double x_deviation = 0, y_deviation = 0;
  bool x_symmetric = false, y_symmetric = false;  ///< deviation ≤ tolerance
};

/// Symmetry of M about the planes x = cx and y = cy through the bounding-box centre. Every
/// vertex of M is reflected and its distance to M measured (AABB tree): one-sided Hausdorff
/// distance of the reflected vertices, which suffices because a reflection is an involution.
/// `tolerance` is relative to the bounding-box diagonal. Cost O(n log n).
SymmetryReport detect_symmetry(const TriMesh& surface, double tolerance = 1e-6);

/// Mirror symmetry asked of a design: none, about the x plane, the y plane, or both (the
/// bounding-box mid-planes). The option words of `--symmetry` ("" also means none).
enum class Symmetry { none, x, y, xy };
Symmetry parse_symmetry(const std::string& word);  ///< throws Error("--symmetry")
const char* to_string(Symmetry s);

/// The planes of `which` from a report. Throws Error("--symmetry", …) when M is not symmetric
/// about a requested plane.
std::vector<Plane> symmetry_planes(const SymmetryReport& report, Symmetry which);

/// The planes named by `which` ("x", "y", "xy" or "none"/"" for none) from a report.
/// Throws Error("--symmetry", …) for another name, or when M is not symmetric about a requested
/// plane within the report's tolerance (the message gives the measured deviation).
std::vector<Plane> symmetry_planes(const SymmetryReport& report, const std::string& which);

struct ReflectedMesh {
  PolyMesh mesh;
  std::vector<int> source_vertex;  ///< per vertex: the sector vertex it is an image of
  std::vector<int> source_face;    ///< per face: the sector face it (or its merged half) came from
  /// Per plane (in the order given): per vertex, the vertex that is its mirror image (itself for
  /// vertices on the plane). Stays valid through `regularize` (topology unchanged).
  std::vector<std::vector<int>> mirror;
};

/// Reflects a sector tessellation across each plane in turn and welds the copies: sector
/// vertices within `weld_tolerance` × (sector bbox diagonal) of a plane are snapped onto it and
/// shared by both copies; a face touching the plane along a chain of edges is merged with its
/// mirror image into one polygon (the cell of a seed on the plane); interior vertices left with
/// two edges on the plane are dissolved into the straight beam crossing it. Faces keep a
/// consistent orientation (mirrored faces are reversed), unreferenced vertices are dropped.
/// Every vertex's mirror image is a vertex (exactly for axis-aligned planes).
/// Throws Error("symmetry", …) when the sector lies on both sides of a plane, a sector edge on
/// the plane is interior to the sector, or a face touches the plane in two separate places.
/// Planes must be mutually perpendicular (the x / y planes of `detect_symmetry`).
ReflectedMesh reflect_and_weld(const PolyMesh& sector, const std::vector<Plane>& planes,
                               double weld_tolerance = 1e-6);

/// Restores exact symmetry after an optimisation of a welded mesh (e.g. `regularize`, which is
/// symmetric only up to rounding): for each plane in turn, every mirror pair (v, m) is set to
/// (a, reflect(a)) with a = (p_v + reflect(p_m)) / 2, and vertices on the plane are projected
/// onto it. `mirror` as returned by `reflect_and_weld`. O(n). Throws Error on size mismatch.
void enforce_symmetry(PolyMesh& mesh, const std::vector<Plane>& planes,
                      const std::vector<std::vector<int>>& mirror);

}  // namespace gridshell
