// Flat facet shell triangle: Felippa's OPT membrane + Batoz's DKT plate. See shell_element.h.

#include "gridshell/fem/shell_element.h"

#include <algorithm>
#include <cmath>

namespace gridshell::fem {

namespace {

using Mat93 = Eigen::Matrix<double, 9, 3>;

struct TriGeom {
  double x12, x21, x13, x31, x23, x32;
  double y12, y21, y13, y31, y23, y32;
  double area;
};

TriGeom tri_geom(const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
  TriGeom g{};
  g.x12 = x(0) - x(1), g.x21 = -g.x12, g.x13 = x(0) - x(2), g.x31 = -g.x13;
  g.x23 = x(1) - x(2), g.x32 = -g.x23;
  g.y12 = y(0) - y(1), g.y21 = -g.y12, g.y13 = y(0) - y(2), g.y31 = -g.y13;
  g.y23 = y(1) - y(2), g.y32 = -g.y23;
  g.area = 0.5 * (g.y21 * g.x13 - g.x21 * g.y13);
  return g;
}

// The lumping matrix L of the basic stiffness (Felippa 2003, eq. for the template), without the
// thickness factor h/2; alpha_b = 3/2 weights the drilling contribution.
Mat93 opt_lumping(const TriGeom& g) {
  const double ab = 1.5;  // α_b (Felippa's name)
  Mat93 L;
  L << g.y23, 0, g.x32,  //
      0, g.x32, g.y23,   //
      ab * g.y23 * (g.y13 - g.y21) / 6, ab * g.x32 * (g.x31 - g.x12) / 6,
      ab * (g.x31 * g.y13 - g.x12 * g.y21) / 3,  //
      g.y31, 0, g.x13,                           //
      0, g.x13, g.y31,                           //
      ab * g.y31 * (g.y21 - g.y32) / 6, ab * g.x13 * (g.x12 - g.x23) / 6,
      ab * (g.x12 * g.y21 - g.x23 * g.y32) / 3,  //
      g.y12, 0, g.x21,                           //
      0, g.x21, g.y12,                           //
      ab * g.y12 * (g.y32 - g.y13) / 6, ab * g.x21 * (g.x23 - g.x31) / 6,
      ab * (g.x23 * g.y32 - g.x31 * g.y13) / 3;
  return L;
}

}  // namespace

Eigen::Matrix3d plane_stress_matrix(double E, double nu) {
  Eigen::Matrix3d C;
  const double c = E / (1 - nu * nu);
  C << c, c * nu, 0, c * nu, c, 0, 0, 0, c * (1 - nu) / 2;
  return C;
}

FacetFrame facet_frame(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  FacetFrame f;
  const Vec3 a = p1 - p0, b = p2 - p0;
  const Vec3 n = a.cross(b);
  const double nn = n.norm();
  f.area = 0.5 * nn;
  f.R.setZero();
  f.xy.setZero();
  if (!(nn > 0) || !(a.norm() > 0)) {
    f.area = 0;
    return f;
  }
  const Vec3 ex = a.normalized();
  const Vec3 ez = n / nn;
  const Vec3 ey = ez.cross(ex);
  f.R.row(0) = ex.transpose();
  f.R.row(1) = ey.transpose();
  f.R.row(2) = ez.transpose();
  f.xy(1, 0) = a.norm();
  f.xy(2, 0) = b.dot(ex);
  f.xy(2, 1) = b.dot(ey);
  return f;
}

Mat9 membrane_opt_stiffness(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                            const ShellSection& s) {
  const TriGeom g = tri_geom(x, y);
  const double A = g.area, h = s.thickness, V = A * h;
  const Eigen::Matrix3d E = plane_stress_matrix(s.E, s.nu);

  // Basic stiffness.
  const Mat93 L = opt_lumping(g) * (h / 2);
  Mat9 K = L * E * L.transpose() / V;

  // Higher-order stiffness.
  const double b0 = std::max(0.5 * (1 - 4 * s.nu * s.nu), 0.01);
  const double b1 = 1, b2 = 2, b3 = 1, b4 = 0, b5 = 1, b6 = -1, b7 = -1, b8 = -1, b9 = -2;
  const double l21 = g.x21 * g.x21 + g.y21 * g.y21;
  const double l32 = g.x32 * g.x32 + g.y32 * g.y32;
  const double l13 = g.x13 * g.x13 + g.y13 * g.y13;

  Eigen::Matrix<double, 3, 9> Ttu;  // deviatoric corner rotations from the dofs
  Ttu << g.x32, g.y32, 4 * A, g.x13, g.y13, 0, g.x21, g.y21, 0,  //
      g.x32, g.y32, 0, g.x13, g.y13, 4 * A, g.x21, g.y21, 0,     //
      g.x32, g.y32, 0, g.x13, g.y13, 0, g.x21, g.y21, 4 * A;
  Ttu /= 4 * A;

  Eigen::Matrix3d Te;  // natural strains (along the sides) → Cartesian strains
  Te << g.y23 * g.y13 * l21, g.y31 * g.y21 * l32, g.y12 * g.y32 * l13,  //
      g.x23 * g.x13 * l21, g.x31 * g.x21 * l32, g.x12 * g.x32 * l13,    //
      (g.y23 * g.x31 + g.x32 * g.y13) * l21, (g.y31 * g.x12 + g.x13 * g.y21) * l32,
      (g.y12 * g.x23 + g.x21 * g.y32) * l13;
  Te /= 4 * A * A;

  const double c = 2 * A / 3;
  Eigen::Matrix3d Q1, Q2, Q3;
  Q1 << b1 / l21, b2 / l21, b3 / l21, b4 / l32, b5 / l32, b6 / l32, b7 / l13, b8 / l13, b9 / l13;
  Q2 << b9 / l21, b7 / l21, b8 / l21, b3 / l32, b1 / l32, b2 / l32, b6 / l13, b4 / l13, b5 / l13;
  Q3 << b5 / l21, b6 / l21, b4 / l21, b8 / l32, b9 / l32, b7 / l32, b2 / l13, b3 / l13, b1 / l13;
  Q1 *= c, Q2 *= c, Q3 *= c;
  const Eigen::Matrix3d Q4 = (Q1 + Q2) / 2, Q5 = (Q2 + Q3) / 2, Q6 = (Q3 + Q1) / 2;
  const Eigen::Matrix3d En = Te.transpose() * E * Te;
  const Eigen::Matrix3d Kt =
      (0.75 * b0 * V) *
      (Q4.transpose() * En * Q4 + Q5.transpose() * En * Q5 + Q6.transpose() * En * Q6);
  K += Ttu.transpose() * Kt * Ttu;
  return 0.5 * (K + K.transpose());
}

Eigen::Vector3d membrane_opt_mean_strain(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                                         const Eigen::Matrix<double, 9, 1>& u) {
  const TriGeom g = tri_geom(x, y);
  // (1/V) (h/2 L)ᵀ u = Lᵀ u / (2A)
  return opt_lumping(g).transpose() * u / (2 * g.area);
}

Mat9 dkt_stiffness(const Eigen::Vector3d& x, const Eigen::Vector3d& y, const ShellSection& s) {
  const TriGeom g = tri_geom(x, y);
  const double A = g.area;
  const double Db = s.E * s.thickness * s.thickness * s.thickness / (12 * (1 - s.nu * s.nu));
  Eigen::Matrix3d D;
  D << 1, s.nu, 0, s.nu, 1, 0, 0, 0, (1 - s.nu) / 2;
  D *= Db;

  // Side coefficients for sides 4 (2-3), 5 (3-1), 6 (1-2): index 0, 1, 2.
  const double xs[3] = {g.x23, g.x31, g.x12}, ys[3] = {g.y23, g.y31, g.y12};
  double P[3], q[3], t[3], r[3];
  for (int k = 0; k < 3; ++k) {
    const double l2 = xs[k] * xs[k] + ys[k] * ys[k];
    P[k] = -6 * xs[k] / l2;
    q[k] = 3 * xs[k] * ys[k] / l2;
    t[k] = -6 * ys[k] / l2;
    r[k] = 3 * ys[k] * ys[k] / l2;
  }
  const double P4 = P[0], P5 = P[1], P6 = P[2], q4 = q[0], q5 = q[1], q6 = q[2];
  const double t4 = t[0], t5 = t[1], t6 = t[2], r4 = r[0], r5 = r[1], r6 = r[2];

  Mat9 K = Mat9::Zero();
  const double pts[3][2] = {{0.5, 0.0}, {0.5, 0.5}, {0.0, 0.5}};
  for (const auto& pt : pts) {
    const double xi = pt[0], eta = pt[1];
    const double a = 1 - 2 * xi, b = 1 - 2 * eta;
    Eigen::Matrix<double, 9, 1> Hx_xi, Hy_xi, Hx_eta, Hy_eta;
    Hx_xi << P6 * a + (P5 - P6) * eta, q6 * a - (q5 + q6) * eta,
        -4 + 6 * (xi + eta) + r6 * a - eta * (r5 + r6), -P6 * a + eta * (P4 + P6),
        q6 * a - eta * (q6 - q4), -2 + 6 * xi + r6 * a + eta * (r4 - r6), -eta * (P5 + P4),
        eta * (q4 - q5), -eta * (r5 - r4);
    Hy_xi << t6 * a + eta * (t5 - t6), 1 + r6 * a - eta * (r5 + r6), -q6 * a + eta * (q5 + q6),
        -t6 * a + eta * (t4 + t6), -1 + r6 * a + eta * (r4 - r6), -q6 * a - eta * (q4 - q6),
        -eta * (t4 + t5), eta * (r4 - r5), -eta * (q4 - q5);
    Hx_eta << -P5 * b - xi * (P6 - P5), q5 * b - xi * (q5 + q6),
        -4 + 6 * (xi + eta) + r5 * b - xi * (r5 + r6), xi * (P4 + P6), xi * (q4 - q6),
        -xi * (r6 - r4), P5 * b - xi * (P4 + P5), q5 * b + xi * (q4 - q5),
        -2 + 6 * eta + r5 * b + xi * (r4 - r5);
    Hy_eta << -t5 * b - xi * (t6 - t5), 1 + r5 * b - xi * (r5 + r6), -q5 * b + xi * (q5 + q6),
        xi * (t4 + t6), xi * (r4 - r6), -xi * (q4 - q6), t5 * b - xi * (t4 + t5),
        -1 + r5 * b + xi * (r4 - r5), -q5 * b - xi * (q4 - q5);
    Eigen::Matrix<double, 3, 9> B;
    B.row(0) = (g.y31 * Hx_xi + g.y12 * Hx_eta).transpose();
    B.row(1) = (-g.x31 * Hy_xi - g.x12 * Hy_eta).transpose();
    B.row(2) = (-g.x31 * Hx_xi - g.x12 * Hx_eta + g.y31 * Hy_xi + g.y12 * Hy_eta).transpose();
    B /= 2 * A;
    K += (A / 3) * B.transpose() * D * B;
  }
  return 0.5 * (K + K.transpose());
}

Mat18 shell_element_stiffness(const Vec3& p0, const Vec3& p1, const Vec3& p2,
                              const ShellSection& s) {
  const FacetFrame f = facet_frame(p0, p1, p2);
  Mat18 Kg = Mat18::Zero();
  if (!(f.area > 0)) return Kg;
  const Eigen::Vector3d x = f.xy.col(0), y = f.xy.col(1);
  const Mat9 Km = membrane_opt_stiffness(x, y, s);
  const Mat9 Kb = dkt_stiffness(x, y, s);
  Mat18 Kl = Mat18::Zero();
  constexpr int kMembraneDofs[3] = {0, 1, 5};  // ux, uy, rz
  constexpr int kBendingDofs[3] = {2, 3, 4};  // uz, rx, ry
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < 3; ++i)
      for (int b = 0; b < 3; ++b)
        for (int j = 0; j < 3; ++j) {
          Kl(6 * a + kMembraneDofs[i], 6 * b + kMembraneDofs[j]) += Km(3 * a + i, 3 * b + j);
          Kl(6 * a + kBendingDofs[i], 6 * b + kBendingDofs[j]) += Kb(3 * a + i, 3 * b + j);
        }
  // Kg = Tᵀ Kl T with T = blockdiag(R, R, R, R, R, R), block by block.
  for (int I = 0; I < 6; ++I)
    for (int J = 0; J < 6; ++J)
      Kg.block<3, 3>(3 * I, 3 * J).noalias() = f.R.transpose() * Kl.block<3, 3>(3 * I, 3 * J) * f.R;
  return Kg;
}

Eigen::Vector3d shell_membrane_stress(const FacetFrame& frame, const ShellSection& s,
                                      const Eigen::Matrix<double, 18, 1>& u_global) {
  Eigen::Matrix<double, 9, 1> um;
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d t = frame.R * u_global.segment<3>(6 * a);
    const Eigen::Vector3d r = frame.R * u_global.segment<3>(6 * a + 3);
    um(3 * a) = t(0);
    um(3 * a + 1) = t(1);
    um(3 * a + 2) = r(2);
  }
  const Eigen::Vector3d eps = membrane_opt_mean_strain(frame.xy.col(0), frame.xy.col(1), um);
  return plane_stress_matrix(s.E, s.nu) * eps;
}

}  // namespace gridshell::fem
