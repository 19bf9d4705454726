#pragma once
/// \file nearest_triangles.h
/// Closest points on a triangle mesh and the triangle nearest each query: a CGAL AABB tree over
/// the mesh's non-degenerate triangles with its distance-query kd-tree, built in one fixed order
/// (primitives as given, the kd-tree over them, then the tree). The kd-tree's hint decides
/// between equally close triangles, so two trees built this way over the same mesh answer every
/// query the same, bit for bit; a tree built in another order (SurfaceProjector's) may not. The
/// coarsening (mesh/coarsen.h) and the field transfer (field/transfer.h) share this one, which
/// lets the coarsening's tree also give the copy's map to the input. Cost: O(n log n) to build,
/// O(log n) expected per query; queries are const and thread-safe.

#include <memory>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

class NearestTriangles {
 public:
  explicit NearestTriangles(const TriMesh& mesh);
  ~NearestTriangles();
  NearestTriangles(const NearestTriangles&) = delete;
  NearestTriangles& operator=(const NearestTriangles&) = delete;

  /// No non-degenerate triangle (then no query may be made).
  bool empty() const;
  /// The point of the mesh closest to p.
  Vec3 closest_point(const Vec3& p) const;
  /// Per triangle of `to`, the mesh's triangle nearest its centroid (queries in parallel, each
  /// writing its own entry: the same map on any number of threads).
  std::vector<int> nearest_faces(const TriMesh& to) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gridshell
