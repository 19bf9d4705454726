#include "gridshell/mesh/geometry.h"

namespace gridshell {

double polygon_area(const PolyMesh& mesh, int face) {
  const auto& f = mesh.faces[face];
  Vec3 a = Vec3::Zero();
  for (std::size_t k = 0; k < f.size(); ++k)
    a += mesh.vertex(f[k]).cross(mesh.vertex(f[(k + 1) % f.size()]));
  return 0.5 * a.norm();
}

double surface_area(const TriMesh& mesh) {
  double area = 0;
  for (int f = 0; f < mesh.num_faces(); ++f)
    area += triangle_area(mesh.vertex(mesh.F(f, 0)), mesh.vertex(mesh.F(f, 1)),
                          mesh.vertex(mesh.F(f, 2)));
  return area;
}

double bbox_diagonal(const Points& V) {
  if (V.rows() == 0) return 0;
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

}  // namespace gridshell
