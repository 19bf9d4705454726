#include "gridshell/optimize/projector.h"

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <array>

#include "gridshell/core/error.h"
#include "gridshell/mesh/geometry.h"
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
  // For the walk: corners of each kept triangle, its neighbour across edge k (corner k to k + 1;
  // −1 on the boundary), and the kept triangles around each vertex of M.
  std::vector<std::array<int, 3>> corners;
  std::vector<std::array<int, 3>> across;
  std::vector<std::vector<int>> around;
  Points V;
  std::vector<Segment> segments;
  TriTree tri_tree;
  SegTree seg_tree;
  std::vector<std::vector<int>> loops;
  double diagonal = 0;
};

SurfaceProjector::SurfaceProjector(const TriMesh& m) : impl_(std::make_unique<Impl>()) {
  Impl& I = *impl_;
  std::vector<int> kept(m.num_faces(), -1);  // index among the non-degenerate triangles
  for (int f = 0; f < m.num_faces(); ++f) {
    const Triangle t(to_cgal(m.vertex(m.F(f, 0))), to_cgal(m.vertex(m.F(f, 1))),
                     to_cgal(m.vertex(m.F(f, 2))));
    if (t.is_degenerate()) continue;
    kept[f] = static_cast<int>(I.triangles.size());
    I.triangles.push_back(t);
    I.corners.push_back({m.F(f, 0), m.F(f, 1), m.F(f, 2)});
  }
  if (I.triangles.empty()) throw Error("surface", "no non-degenerate triangles to project onto");
  const Topology topo = build_topology(m);
  I.V = m.V;
  I.around.resize(m.num_vertices());
  for (int v = 0; v < m.num_vertices(); ++v)
    for (int f : topo.vertex_faces[v])
      if (kept[f] >= 0) I.around[v].push_back(kept[f]);
  I.across.assign(I.corners.size(), {-1, -1, -1});
  for (int f = 0; f < m.num_faces(); ++f) {
    if (kept[f] < 0) continue;
    for (int k = 0; k < 3; ++k) {  // edge k runs from corner k to corner k + 1
      const auto& faces = topo.edge_faces[topo.face_edges[f][k]];
      if (faces.size() != 2) continue;  // boundary or non-manifold
      const int g = faces[0] == f ? faces[1] : faces[0];
      I.across[kept[f]][k] = kept[g];  // −1 next to a degenerate triangle
    }
  }
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

Vec3 SurfaceProjector::closest_point_walk(const Vec3& p, int& triangle) const {
  const Impl& I = *impl_;
  const int nt = static_cast<int>(I.corners.size());
  if (triangle < 0 || triangle >= nt) {
    const auto hit = I.tri_tree.closest_point_and_primitive(to_cgal(p));
    triangle = static_cast<int>(hit.second - I.triangles.begin());
    return from_cgal(hit.first);
  }
  auto on = [&](int t) {
    const auto& c = I.corners[t];
    return closest_point_on_triangle(p, I.V.row(c[0]).transpose(), I.V.row(c[1]).transpose(),
                                     I.V.row(c[2]).transpose());
  };
  TrianglePoint best = on(triangle);
  double best_d = (best.point - p).squaredNorm();
  for (int step = 0; step < 64; ++step) {
    int next = -1;
    TrianglePoint next_tp;
    double next_d = best_d;
    auto consider = [&](int t) {
      if (t < 0 || t == triangle) return;
      const TrianglePoint tp = on(t);
      const double d = (tp.point - p).squaredNorm();
      if (d < next_d) {
        next = t;
        next_tp = tp;
        next_d = d;
      }
    };
    if (best.region == 0) {
      // Inside its triangle: a local minimum of the distance, but across a concave crease of
      // the piecewise-flat M the neighbour can hold a closer one.
      for (int t : I.across[triangle]) consider(t);
      if (next < 0 || next_d >= best_d * (1 - 1e-12)) return best.point;
    } else if (best.region <= 3) {
      consider(I.across[triangle][best.region - 1]);
    } else {
      for (int t : I.around[I.corners[triangle][best.region - 4]]) consider(t);
    }
    // No neighbour closer by more than rounding: the closest point sits on an edge or vertex of
    // M — a crease, the boundary, or next to a skipped (degenerate or non-manifold) triangle,
    // where the walk's neighbourhood may be incomplete. The tree decides there, with the walk's
    // point as its starting bound.
    if (next < 0 || next_d >= best_d * (1 - 1e-12)) {
      const auto hit = I.tri_tree.closest_point_and_primitive(
          to_cgal(p), {to_cgal(best.point), I.triangles.begin() + triangle});
      triangle = static_cast<int>(hit.second - I.triangles.begin());
      return from_cgal(hit.first);
    }
    triangle = next;
    best = next_tp;
    best_d = next_d;
  }
  const auto hit = I.tri_tree.closest_point_and_primitive(to_cgal(p));
  triangle = static_cast<int>(hit.second - I.triangles.begin());
  return from_cgal(hit.first);
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
