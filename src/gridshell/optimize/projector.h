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
