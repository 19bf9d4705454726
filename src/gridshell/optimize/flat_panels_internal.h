#pragma once
/// \file flat_panels_internal.h
/// The parts of flat_panels (flat_panels.h) shared by its files: the layout of joints and planes
/// (flat_layout.cpp), the optimisation of the planes (flat_solve.cpp), polygon tests
/// (flat_panels.cpp). Internal: nothing outside optimize/flat_*.cpp includes it.

#include <array>
#include <utility>
#include <vector>

#include "gridshell/mesh/mesh.h"
#include "gridshell/optimize/flat_panels.h"

namespace gridshell::flat_detail {

/// A panel polygon's 2-D corners in the frame of `normal`.
std::vector<Eigen::Vector2d> in_plane(const std::vector<Vec3>& p, const Vec3& normal);
/// True when the polygon (2-D) is simple: non-zero area, no two non-adjacent sides crossing.
bool simple_2d(const std::vector<Eigen::Vector2d>& q);
/// Smallest interior angle (degrees) and whether some corner is reflex, of a 2-D polygon.
std::pair<double, bool> corner_angles(const std::vector<Eigen::Vector2d>& q);

/// A joint of the flat grid-shell: the design joint it comes from and its three planes (≥ 0: a
/// panel; < 0: fixed plane −1 − k).
struct Joint {
  int source = 0;
  int plane[3] = {0, 0, 0};
  bool support = false;
  bool pinned = false;  ///< an interior support: held at its design position
  /// A part of a split boundary joint: its target is the design joint moved by `along` spacings
  /// along the boundary tangent `tangent` (flat_panels.cpp), so the parts start apart, in order.
  double along = 0;
  Vec3 tangent = Vec3::Zero();
};

/// The flat grid-shell's topology: joints, their planes, the faces over the new joints.
struct Layout {
  std::vector<Joint> joints;
  std::vector<Vec3> fixed_normal;
  std::vector<double> fixed_offset;
  std::vector<std::vector<int>> faces;
  int split = 0;
};

/// The layout: which planes meet at each joint; joints of more than three planes split into fans.
/// `vertex_normal`: the surface normal at each design joint. Throws FlatPanelsFailed for a
/// non-manifold joint.
Layout build_layout(const PolyMesh& design, const std::vector<Vec3>& vertex_normal,
                    const std::vector<char>& is_support);

/// The planes being optimised and the fixed ones.
struct Planes {
  std::vector<Vec3> n;
  std::vector<double> d;
};

/// Per joint the closest point on M and M's normal there (the surface term's anchor).
struct Anchor {
  Vec3 point = Vec3::Zero(), normal = Vec3::UnitZ();
  int triangle = -1;
};

/// A beam of the flat grid-shell between joints a and b: the energy keeps its signed length
/// u·(x_b − x_a) (u its design direction) at least `min_length`.
struct Beam {
  int a = 0, b = 0;
  Vec3 u = Vec3::UnitX();
  double min_length = 0;
};

/// A side of a joint's cells' triangle: normal·x ≥ offset inside (normal 0: no side).
struct Side {
  Vec3 normal = Vec3::Zero();
  double offset = 0;
};
constexpr int kJointResiduals = 8;

struct Problem {
  const Layout* L = nullptr;
  std::vector<Vec3> x0;         ///< design position per joint
  std::vector<Anchor> anchor;   ///< per joint
  std::vector<std::vector<int>> face_neighbours;
  std::vector<Beam> beams;      ///< every panel side once
  /// Per joint of three panels: the sides of the triangle of its panels' centres (of the targets),
  /// each moved out to the target joint where that lies outside (the P-Hex papers' rule that a
  /// joint stays inside its cells' triangle, here never stricter than the design).
  std::vector<std::array<Side, 3>> inside;
  double h = 1;                 ///< mean beam length
  double shortest_allowed = 0;  ///< the post-check's shortest beam (m)
  /// Per joint: a factor on its design weight (empty: 1 everywhere). A region whose panels
  /// failed the post-check in an earlier attempt is held closer to the design (flat_panels.cpp).
  std::vector<double> stiffness;
  FlatPanelOptions o;
};

/// Joint j's weight towards its design position: support_weight for an interior support, else
/// design_weight times its stiffness.
inline double design_weight_of(const Problem& P, int j) {
  if (P.L->joints[j].pinned) return P.o.support_weight;
  return P.o.design_weight * (P.stiffness.empty() ? 1.0 : P.stiffness[j]);
}


/// The plane `ref` refers to (a panel's or a fixed one).
void plane_of(const Problem& P, const Planes& pl, int ref, Vec3& n, double& d);
/// All joints of `pl`; false when a joint's planes are nearly parallel.
bool joints_of(const Problem& P, const Planes& pl, std::vector<Vec3>& x, std::vector<double>& det,
               double min_det);
/// The closest points on M of the joints `x` and M's normals there (walks from the last ones).
void update_anchors(const TriMesh& surface, const SurfaceProjector& projector,
                    const std::vector<Vec3>& x, std::vector<Anchor>& anchor);
/// The design's joints lifted by a shallow paraboloid along M's normal (flat_solve.cpp).
std::vector<Vec3> lifted_targets(const Problem& P, double lift, double diagonal);
/// The starting planes: nearly planar panels by a ShapeUp-like alternation towards `target`.
Planes start_planes(Problem& P, const TriMesh& surface, const SurfaceProjector& projector,
                    const std::vector<Vec3>& target);
/// Levenberg–Marquardt on the planes; returns the iterations run.
int optimise(Problem& P, Planes& pl, const TriMesh& surface, const SurfaceProjector& projector,
             FlatPanelStats& stats);

/// Every side of the layout's panels once, as a beam kept at least `keep` × its length between
/// the joints' targets `x0` (beams of no target length, split joints' beams, are left out).
/// The triangle sides of every joint of three panels (Problem::inside) from the targets `x0`.
std::vector<std::array<Side, 3>> inside_sides(const Layout& L, const std::vector<Vec3>& x0);
std::vector<Beam> beams_of(const Layout& L, const std::vector<Vec3>& x0, double keep);
/// Number of beams whose signed length is below the post-check's shortest beam.
int short_beams(const Problem& P, const std::vector<Vec3>& x);
/// Turns over (T1 flip) up to `max_flips` beams shorter than the post-check allows, shortest
/// first, one per joint: beam (a, b) of joints A∩B∩C and A∩B∩D becomes joints A∩C∩D and B∩C∩D
/// (panels A, B lose a corner, C, D gain one and become neighbours); the joints' targets move to
/// the new beam's line. Only interior beams between unsplit, unsupported valence-3 joints whose
/// panels keep at least three sides. `x`: the joints of `pl`. Returns the flips made; updates
/// L, P.x0 and P.face_neighbours (P.beams must then be rebuilt).
int flip_collapsed_beams(Layout& L, Problem& P, const Planes& pl, const std::vector<Vec3>& x,
                         int max_flips);

/// The flat grid-shell after split_failing_panels: joints, faces (a split panel's first triangle
/// keeps its id, the others follow all panels) and each face's plane.
struct SplitPanels {
  std::vector<Vec3> x;
  std::vector<std::vector<int>> faces;
  std::vector<Vec3> normal;
  std::vector<double> offset;
  std::vector<int> owner;  ///< per face: the panel of the layout it glazes
  int split = 0;           ///< panels glazed as triangles
};

/// The last resort when the planes `pl` fail the post-check: the failing panels (one that
/// self-intersects, a short side — both panels along it —, a joint farther from the surface than
/// `far_limit` or whose planes are parallel — all its panels) give up their planes and become
/// flat triangles (triangulate_polygon). A joint then sits nearest its target on the planes it
/// keeps (its three: their intersection, as before; none: its target, on the surface), so every
/// kept panel stays flat. Repeated while something fails (a split panel that cannot be
/// triangulated splits its neighbours too); false when more than `max_panels` panels would split.
bool split_failing_panels(const Problem& P, const Planes& pl, const SurfaceProjector& projector,
                          double far_limit, int max_panels, SplitPanels& out);

}  // namespace gridshell::flat_detail
