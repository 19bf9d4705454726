#include "gridshell/surfaces/grid.h"

namespace gridshell {

TriMesh parametric_grid(int nu, int nv, const std::function<Vec3(double, double)>& map) {
  TriMesh m;
  m.V.resize((nu + 1) * (nv + 1), 3);
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i)
      m.V.row(j * (nu + 1) + i) = map(double(i) / nu, double(j) / nv).transpose();
  m.F.resize(2 * nu * nv, 3);
  int f = 0;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int a = j * (nu + 1) + i, b = a + 1, c = a + nu + 1, d = c + 1;
      if ((i + j) % 2 == 0) {
        m.F.row(f++) << a, b, d;
        m.F.row(f++) << a, d, c;
      } else {
        m.F.row(f++) << a, b, c;
        m.F.row(f++) << b, d, c;
      }
    }
  return m;
}

TriMesh flat_grid(int nx, int ny, double w, double h) {
  return parametric_grid(nx, ny, [w, h](double s, double t) { return Vec3(w * s, h * t, 0); });
}

}  // namespace gridshell
