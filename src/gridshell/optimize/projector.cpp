#include "gridshell/optimize/projector.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include "gridshell/core/error.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

namespace {
using K = CGAL::Simple_cartesian<double>;
using Point = K::Point_3;
using Triangle = K::Triangle_3;
using Segment = K::Segment_3;
using TriPrimitive = CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>;
using TriTree = CGAL::AABB_tree<CGAL::AABB_traits<K, TriPrimitive>>;
using SegPrimitive = CGAL::AABB_segment_primitive<K, std::vector<Segment>::const_iterator>;
using SegTree = CGAL::AABB_tree<CGAL::AABB_traits<K, SegPrimitive>>;

Point to_cgal(const Vec3& p) {
  return Point(p.x(), p.y(), p.z());
}
Vec3 from_cgal(const Point& p) {
  return Vec3(p.x(), p.y(), p.z());
}
}  // namespace

struct SurfaceProjector::Impl {
  std::vector<Triangle> triangles;
  std::vector<Segment> segments;
  TriTree tri_tree;
  SegTree seg_tree;
  std::vector<std::vector<int>> loops;
  double diagonal = 0;
};

SurfaceProjector::SurfaceProjector(const TriMesh& m) : impl_(std::make_unique<Impl>()) {
  Impl& I = *impl_;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Triangle t(to_cgal(m.vertex(m.F(f, 0))), to_cgal(m.vertex(m.F(f, 1))),
                     to_cgal(m.vertex(m.F(f, 2))));
    if (!t.is_degenerate()) I.triangles.push_back(t);
  }
  if (I.triangles.empty()) throw Error("surface", "no non-degenerate triangles to project onto");
  const Topology topo = build_topology(m);
  I.loops = topo.boundary_loops;
  for (const auto& loop : I.loops)
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Segment s(to_cgal(m.vertex(loop[i])), to_cgal(m.vertex(loop[(i + 1) % loop.size()])));
      if (!s.is_degenerate()) I.segments.push_back(s);
    }
  I.diagonal = bbox_diagonal(m.V);
  // Build eagerly so that concurrent const queries never trigger a lazy build.
  I.tri_tree.rebuild(I.triangles.begin(), I.triangles.end());
  I.tri_tree.accelerate_distance_queries();
  I.tri_tree.build();
  (void)I.tri_tree.closest_point(to_cgal(m.vertex(0)));
  if (!I.segments.empty()) {
    I.seg_tree.rebuild(I.segments.begin(), I.segments.end());
    I.seg_tree.accelerate_distance_queries();
    I.seg_tree.build();
    (void)I.seg_tree.closest_point(to_cgal(m.vertex(0)));
  }
}

SurfaceProjector::~SurfaceProjector() = default;
SurfaceProjector::SurfaceProjector(SurfaceProjector&&) noexcept = default;
SurfaceProjector& SurfaceProjector::operator=(SurfaceProjector&&) noexcept = default;

Vec3 SurfaceProjector::closest_point(const Vec3& p) const {
  return from_cgal(impl_->tri_tree.closest_point(to_cgal(p)));
}

Vec3 SurfaceProjector::closest_point(const Vec3& p, const Vec3& hint) const {
  return from_cgal(impl_->tri_tree.closest_point(to_cgal(p), to_cgal(hint)));
}

Vec3 SurfaceProjector::closest_boundary_point(const Vec3& p, const Vec3& hint) const {
  if (impl_->segments.empty()) return closest_point(p, hint);
  return from_cgal(impl_->seg_tree.closest_point(to_cgal(p), to_cgal(hint)));
}

Vec3 SurfaceProjector::closest_boundary_point(const Vec3& p) const {
  if (impl_->segments.empty()) return closest_point(p);
  return from_cgal(impl_->seg_tree.closest_point(to_cgal(p)));
}

bool SurfaceProjector::has_boundary() const {
  return !impl_->segments.empty();
}
const std::vector<std::vector<int>>& SurfaceProjector::boundary_loops() const {
  return impl_->loops;
}
double SurfaceProjector::diagonal() const {
  return impl_->diagonal;
}

}  // namespace gridshell
