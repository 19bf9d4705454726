#pragma once
/// \file projector.h
/// Closest-point queries on the input surface M and on its boundary polylines, for keeping the
/// vertices of a grid-shell on M while it is optimised. Built once (CGAL AABB trees over the
/// triangles and over the boundary edges, O(n log n)), then each query is O(log n) expected.
/// Queries are const and thread-safe after construction (the trees are built eagerly).

#include <memory>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

class SurfaceProjector {
 public:
  /// Throws Error("surface", …) for a mesh without (non-degenerate) triangles.
  explicit SurfaceProjector(const TriMesh& surface);
  ~SurfaceProjector();
  SurfaceProjector(SurfaceProjector&&) noexcept;
  SurfaceProjector& operator=(SurfaceProjector&&) noexcept;
  SurfaceProjector(const SurfaceProjector&) = delete;
  SurfaceProjector& operator=(const SurfaceProjector&) = delete;

  /// The point of M closest to p.
  Vec3 closest_point(const Vec3& p) const;
  /// Same, faster when `hint` is a point of M near the answer (e.g. the previous position of a
  /// vertex that moved a little). `hint` must lie on M.
  Vec3 closest_point(const Vec3& p, const Vec3& hint) const;
  /// Same by walking over M's triangles from `triangle` (in/out: the triangle the answer lies
  /// on; < 0 = unknown, then the AABB tree answers and sets it). Each step moves to the
  /// neighbouring triangle (across the edge, or around the vertex, where the current closest
  /// point lies) while that gets closer; a local minimum of the distance ends the walk. For a
  /// point that moved a little since its last projection this visits a handful of triangles
  /// instead of descending the tree (the regularizer's reprojection: 7 ms → 0.6–2 ms per
  /// iteration at 10 K polygons). Where the walk ends on an edge or vertex of M (a crease, the
  /// boundary), and after 64 steps, the tree answers. The result always lies on M; it is a local
  /// closest point, which differs from the global one only behind a concave crease of the
  /// piecewise-flat M (tests: at most 1 query in 280 for moves of 1e-3 of the diagonal).
  Vec3 closest_point_walk(const Vec3& p, int& triangle) const;
  /// The point of M's boundary polylines closest to p (p itself projected onto M when M has no
  /// boundary).
  Vec3 closest_boundary_point(const Vec3& p) const;
  /// Same with a hint that lies on the boundary.
  Vec3 closest_boundary_point(const Vec3& p, const Vec3& hint) const;
  /// Distance from p to M (m).
  double distance(const Vec3& p) const { return (closest_point(p) - p).norm(); }
  /// Distance from p to M's boundary (m).
  double boundary_distance(const Vec3& p) const { return (closest_boundary_point(p) - p).norm(); }

  bool has_boundary() const;
  /// Boundary loops of M as vertex cycles (from build_topology).
  const std::vector<std::vector<int>>& boundary_loops() const;
  /// Bounding-box diagonal of M (m).
  double diagonal() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gridshell
