#pragma once
/// \file flat_panels_internal.h
/// The parts of flat_panels (flat_panels.h) shared by its files: the layout of joints and planes
/// (flat_layout.cpp), the optimisation of the planes (flat_solve.cpp), polygon tests
/// (flat_panels.cpp). Internal: nothing outside optimize/flat_*.cpp includes it.

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

struct Problem {
  const Layout* L = nullptr;
  std::vector<Vec3> x0;         ///< design position per joint
  std::vector<Anchor> anchor;   ///< per joint
  std::vector<std::vector<int>> face_neighbours;
  double h = 1;                 ///< mean beam length
  FlatPanelOptions o;
};


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

}  // namespace gridshell::flat_detail
