#pragma once
/// \file fabrication.h
/// A grid-shell as parts to build: joints (nodes), beams (bars cut to length) and panels (glass
/// or sheet cut from a flat plate). One numbering everywhere: joint id = mesh vertex index,
/// beam id = edge index of mesh/topology.h (the frame's member order), panel id = face index.
///
/// - Joints: position, valence, support flag, the incident beams in the order they turn around
///   the joint's normal (area-weighted normal of the incident panels; the best-fit plane of the
///   neighbours when there are none), and the angles between consecutive beams measured in the
///   joint's tangent plane (the beams projected onto it). The angles go once around: they add
///   up to 360° (at a boundary joint one of them spans the open side).
/// - Beams: end joints, cut length = centre-line length, the id of its length class (lengths
///   rounded to `length_resolution`), the panels on either side.
/// - Panels: corner joints in face order, area (norm of the vector area), planarity = mean
///   distance of the corners to their best-fit (PCA) plane / half the perimeter, and the outline
///   flattened into that plane (flatten_panel).
///
/// Cost: O(face corners + edges) plus a tiny Gauss–Newton solve per non-planar panel.

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gridshell/mesh/mesh.h"
#include "gridshell/mesh/topology.h"

namespace gridshell::fabrication {

using Vec2 = Eigen::Vector2d;

struct Joint {
  int id = 0;
  Vec3 position = Vec3::Zero();
  int valence = 0;
  bool support = false;
  std::vector<int> beams;          ///< incident beams, counter-clockwise about the normal
  std::vector<double> angles_deg;  ///< angle from beams[k] to beams[k+1] (cyclic), tangent plane
};

struct Beam {
  int id = 0;
  int i = 0, j = 0;           ///< end joints (i < j for mesh edges)
  double length = 0;          ///< centre-line (cut) length [m]
  int length_class = 0;       ///< index of its length among the distinct rounded lengths
  std::vector<int> panels;    ///< faces on either side (1 at the boundary)
};

/// A panel's outline in its own plane.
struct FlatPanel {
  std::vector<Vec2> outline;      ///< one point per corner, counter-clockwise, [m]
  double planarity = 0;           ///< mean distance to the best-fit plane / half perimeter
  double edge_length_error = 0;   ///< max |flat edge − 3D edge| / 3D edge
  double out_of_plane = 0;        ///< largest corner distance to the best-fit plane [m]
};

struct Panel {
  int id = 0;
  std::vector<int> joints;  ///< corners in face order
  double area = 0;          ///< norm of the vector area [m²]
  FlatPanel flat;
};

struct FabricationOptions {
  /// Beams whose lengths round to the same multiple of this are one length class [m].
  double length_resolution = 1e-3;
  /// Gauss–Newton iterations that restore the edge lengths of a non-planar panel's outline.
  int flatten_iterations = 30;
};

struct Fabrication {
  std::vector<Joint> joints;
  std::vector<Beam> beams;
  std::vector<Panel> panels;
  int distinct_lengths = 0;  ///< number of length classes
  double total_length = 0;   ///< Σ beam lengths [m]
};

/// Flattens one polygon (3D corners in order): projects it onto its best-fit (PCA) plane, then,
/// when the polygon is not planar, moves the projected corners by minimum-norm Gauss–Newton
/// steps until the outline's edges have the 3D edge lengths (an n-gon has 2n − 3 in-plane
/// degrees of freedom for n edge lengths, so this succeeds unless the lengths are degenerate;
/// the outline stays as close to the projection as the steps allow). A planar polygon's outline
/// is its exact isometric image. The outline is counter-clockwise seen from the side its vector
/// area points to, with its centroid at the origin and its first edge along +x.
FlatPanel flatten_panel(const std::vector<Vec3>& corners, int iterations = 30);

/// Planarity of a polygon: mean distance of its corners to their best-fit plane / half its
/// perimeter (0 for a planar polygon, dimensionless).
double panel_planarity(const std::vector<Vec3>& corners);

/// Joints, beams (topology edge order) and panels of `mesh`. `supports`: supported joints.
Fabrication fabrication_parts(const PolyMesh& mesh, const Topology& topology,
                              const std::vector<int>& supports,
                              const FabricationOptions& options = {});

}  // namespace gridshell::fabrication
