#include "gridshell/mesh/mesh.h"

namespace gridshell {

TriMesh triangulate(const PolyMesh& poly) {
  TriMesh out;
  out.V = poly.V;
  int count = 0;
  for (const auto& f : poly.faces) count += std::max<int>(0, static_cast<int>(f.size()) - 2);
  out.F.resize(count, 3);
  int row = 0;
  for (const auto& f : poly.faces)
    for (std::size_t k = 1; k + 1 < f.size(); ++k) out.F.row(row++) << f[0], f[k], f[k + 1];
  return out;
}

PolyMesh to_poly(const TriMesh& tri) {
  PolyMesh out;
  out.V = tri.V;
  out.faces.reserve(tri.F.rows());
  for (int f = 0; f < tri.F.rows(); ++f)
    out.faces.push_back({tri.F(f, 0), tri.F(f, 1), tri.F(f, 2)});
  return out;
}

}  // namespace gridshell
