#include "gridshell/mesh/nearest_triangles.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace gridshell {

namespace {
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point point(const Vec3& p) {
  return Point(p.x(), p.y(), p.z());
}
}  // namespace

struct NearestTriangles::Impl {
  std::vector<Triangle> triangles;
  std::vector<int> face;  ///< per kept triangle: its face of the mesh
  Tree tree;
};

NearestTriangles::NearestTriangles(const TriMesh& mesh) : impl_(std::make_unique<Impl>()) {
  Impl& I = *impl_;
  I.triangles.reserve(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Triangle t(point(mesh.vertex(mesh.F(f, 0))), point(mesh.vertex(mesh.F(f, 1))),
                     point(mesh.vertex(mesh.F(f, 2))));
    if (t.is_degenerate()) continue;
    I.triangles.push_back(t);
    I.face.push_back(f);
  }
  if (I.triangles.empty()) return;
  // The order the file comment names: insert, kd-tree over the primitives as given, then the
  // tree (which sorts the primitives). Both are built now: no query builds anything lazily.
  I.tree.insert(I.triangles.cbegin(), I.triangles.cend());
  I.tree.accelerate_distance_queries();
  I.tree.build();
}

NearestTriangles::~NearestTriangles() = default;

bool NearestTriangles::empty() const {
  return impl_->triangles.empty();
}

Vec3 NearestTriangles::closest_point(const Vec3& p) const {
  const Point q = impl_->tree.closest_point(point(p));
  return Vec3(q.x(), q.y(), q.z());
}

std::vector<int> NearestTriangles::nearest_faces(const TriMesh& to) const {
  const Impl& I = *impl_;
  std::vector<int> out(to.num_faces());
  tbb::parallel_for(tbb::blocked_range<int>(0, to.num_faces(), 1024),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int f = range.begin(); f < range.end(); ++f) {
                        const Vec3 c = (to.vertex(to.F(f, 0)) + to.vertex(to.F(f, 1)) +
                                        to.vertex(to.F(f, 2))) /
                                       3;
                        const auto hit = I.tree.closest_point_and_primitive(point(c));
                        out[f] = I.face[hit.second - I.triangles.cbegin()];
                      }
                    });
  return out;
}

}  // namespace gridshell
