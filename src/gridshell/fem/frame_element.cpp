#include "gridshell/fem/frame_element.h"

#include <cmath>

#include <Eigen/Geometry>

namespace gridshell::fem {

Mat3 skew(const Vec3& a) {
  Mat3 S;
  S << 0, -a(2), a(1), a(2), 0, -a(0), -a(1), a(0), 0;
  return S;
}

Mat3 rotation_exp(const Vec3& w) {
  const double t = w.norm();
  const Mat3 S = skew(w);
  double a, b;
  if (t < 1e-6) {
    a = 1 - t * t / 6;
    b = 0.5 - t * t / 24;
  } else {
    a = std::sin(t) / t;
    b = (1 - std::cos(t)) / (t * t);
  }
  return Mat3::Identity() + a * S + b * S * S;
}

Vec3 rotation_log(const Mat3& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1;
  const Vec3 v = q.vec();
  const double s = v.norm();
  if (s < 1e-8) return 2.0 * v / q.w();
  const double angle = 2 * std::atan2(s, q.w());
  return v * (angle / s);
}

Mat3 inverse_left_jacobian(const Vec3& theta) {
  const double t = theta.norm();
  const Mat3 S = skew(theta);
  double c;
  if (t < 1e-4) {
    c = 1.0 / 12 + t * t / 720;
  } else {
    c = (1 - (t / 2) / std::tan(t / 2)) / (t * t);
  }
  return Mat3::Identity() - 0.5 * S + c * S * S;
}

Mat3 element_frame(const Vec3& xi, const Vec3& xj, const Vec3& up) {
  const Vec3 e1 = (xj - xi).normalized();
  Vec3 u = up;
  if (u.squaredNorm() == 0 || u.cross(e1).norm() < 1e-6 * u.norm()) {
    u = Vec3::UnitZ();
    if (u.cross(e1).norm() < 1e-3) u = Vec3::UnitX();
  }
  const Vec3 e3 = (u - u.dot(e1) * e1).normalized();
  const Vec3 e2 = e3.cross(e1);
  Mat3 R;
  R.col(0) = e1;
  R.col(1) = e2;
  R.col(2) = e3;
  return R;
}

namespace {

Mat12 to_global(const Mat12& k, const Mat3& R) {
  Mat12 K;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      K.block<3, 3>(3 * a, 3 * b) = R * k.block<3, 3>(3 * a, 3 * b) * R.transpose();
  return K;
}

// Adds a 4×4 bending pattern at (translation a, rotation b) indices; sign = −1 for the x–z
// plane (θy = −w').
void add_bending(Mat12& k, int t, int r, double sign, const Eigen::Matrix4d& m) {
  const int idx[4] = {t, r, t + 6, r + 6};
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      double s = 1;
      if ((a == 1 || a == 3) != (b == 1 || b == 3)) s = sign;
      k(idx[a], idx[b]) += s * m(a, b);
    }
}

}  // namespace

Mat12 beam_linear_stiffness(const BeamStiffness& s, double L, const Mat3& R0) {
  Mat12 k = Mat12::Zero();
  const double ea = s.EA / L, gj = s.GJ / L;
  k(0, 0) = k(6, 6) = ea;
  k(0, 6) = k(6, 0) = -ea;
  k(3, 3) = k(9, 9) = gj;
  k(3, 9) = k(9, 3) = -gj;
  Eigen::Matrix4d m;
  m << 12, 6 * L, -12, 6 * L, 6 * L, 4 * L * L, -6 * L, 2 * L * L, -12, -6 * L, 12, -6 * L, 6 * L,
      2 * L * L, -6 * L, 4 * L * L;
  add_bending(k, 1, 5, 1.0, m * (s.EIz / (L * L * L)));
  add_bending(k, 2, 4, -1.0, m * (s.EIy / (L * L * L)));
  return to_global(k, R0);
}

Mat12 beam_geometric_stiffness(double N, double L, const Mat3& R0) {
  Mat12 k = Mat12::Zero();
  Eigen::Matrix4d m;
  m << 6.0 / 5, L / 10, -6.0 / 5, L / 10, L / 10, 2 * L * L / 15, -L / 10, -L * L / 30, -6.0 / 5,
      -L / 10, 6.0 / 5, -L / 10, L / 10, -L * L / 30, -L / 10, 2 * L * L / 15;
  m *= N / L;
  add_bending(k, 1, 5, 1.0, m);
  add_bending(k, 2, 4, -1.0, m);
  return to_global(k, R0);
}

namespace {

struct CorotKinematics {
  Mat3 Rr;
  double ln;
  Vec3 th1, th2;
  Vec3 q, q1, q2;
};

CorotKinematics kinematics(const CorotBeam& b, const CorotState& st) {
  CorotKinematics k;
  const Vec3 dx = st.xj - st.xi;
  k.ln = dx.norm();
  const Vec3 e1 = dx / k.ln;
  const Vec3 p1 = st.Ri * b.R0.col(1), p2 = st.Rj * b.R0.col(1);
  const Vec3 p = 0.5 * (p1 + p2);
  const Vec3 e3 = e1.cross(p).normalized();
  const Vec3 e2 = e3.cross(e1);
  k.Rr.col(0) = e1;
  k.Rr.col(1) = e2;
  k.Rr.col(2) = e3;
  k.th1 = rotation_log(k.Rr.transpose() * st.Ri * b.R0);
  k.th2 = rotation_log(k.Rr.transpose() * st.Rj * b.R0);
  k.q = k.Rr.transpose() * p;
  k.q1 = k.Rr.transpose() * p1;
  k.q2 = k.Rr.transpose() * p2;
  return k;
}

void local_forces(const CorotBeam& b, const Vec7& d, Vec7& f) {
  const double l0 = b.l0;
  const double t1y = d(2), t1z = d(3), t2y = d(5), t2z = d(6);
  const double eps = d(0) / l0 + (2 * t1z * t1z - t1z * t2z + 2 * t2z * t2z) / 30 +
                     (2 * t1y * t1y - t1y * t2y + 2 * t2y * t2y) / 30;
  const double N = b.s.EA * eps;
  f(0) = N;
  f(1) = b.s.GJ / l0 * (d(1) - d(4));
  f(4) = -f(1);
  f(3) = b.s.EIz / l0 * (4 * t1z + 2 * t2z) + N * l0 * (4 * t1z - t2z) / 30;
  f(6) = b.s.EIz / l0 * (2 * t1z + 4 * t2z) + N * l0 * (-t1z + 4 * t2z) / 30;
  f(2) = b.s.EIy / l0 * (4 * t1y + 2 * t2y) + N * l0 * (4 * t1y - t2y) / 30;
  f(5) = b.s.EIy / l0 * (2 * t1y + 4 * t2y) + N * l0 * (-t1y + 4 * t2y) / 30;
}

}  // namespace

void corot_local(const CorotBeam& b, const CorotState& st, Vec7& d, Vec7& f) {
  const CorotKinematics k = kinematics(b, st);
  d(0) = k.ln - b.l0;
  d.segment<3>(1) = k.th1;
  d.segment<3>(4) = k.th2;
  local_forces(b, d, f);
}

Vec12 corot_force(const CorotBeam& b, const CorotState& st, Vec7* local) {
  const CorotKinematics k = kinematics(b, st);
  Vec7 d, f;
  d(0) = k.ln - b.l0;
  d.segment<3>(1) = k.th1;
  d.segment<3>(4) = k.th2;
  local_forces(b, d, f);
  if (local) *local = f;

  // G^T: spin of the element frame (local components) per local dof [u1 w1 u2 w2].
  const double ln = k.ln, q2n = k.q(1);
  const double eta = k.q(0) / q2n, e11 = k.q1(0) / q2n, e12 = k.q1(1) / q2n, e21 = k.q2(0) / q2n,
               e22 = k.q2(1) / q2n;
  Eigen::Matrix<double, 3, 12> Gt = Eigen::Matrix<double, 3, 12>::Zero();
  Gt(0, 2) = eta / ln;
  Gt(0, 3) = e12 / 2;
  Gt(0, 4) = -e11 / 2;
  Gt(0, 8) = -eta / ln;
  Gt(0, 9) = e22 / 2;
  Gt(0, 10) = -e21 / 2;
  Gt(1, 2) = 1 / ln;
  Gt(1, 8) = -1 / ln;
  Gt(2, 1) = -1 / ln;
  Gt(2, 7) = 1 / ln;
  Eigen::Matrix<double, 3, 12> P1 = -Gt, P2 = -Gt;
  P1.block<3, 3>(0, 3) += Mat3::Identity();
  P2.block<3, 3>(0, 9) += Mat3::Identity();
  const Eigen::Matrix<double, 3, 12> B1 = inverse_left_jacobian(k.th1) * P1;
  const Eigen::Matrix<double, 3, 12> B2 = inverse_left_jacobian(k.th2) * P2;
  Vec12 fl = B1.transpose() * f.segment<3>(1) + B2.transpose() * f.segment<3>(4);
  fl(0) -= f(0);
  fl(6) += f(0);
  Vec12 fg;
  for (int a = 0; a < 4; ++a) fg.segment<3>(3 * a) = k.Rr * fl.segment<3>(3 * a);
  return fg;
}

Mat12 corot_tangent(const CorotBeam& b, const CorotState& st, Vec12* force, bool symmetric) {
  // Translation invariance: work with xi = 0 so that perturbations are relative to the length.
  CorotState s0 = st;
  s0.xj = st.xj - st.xi;
  s0.xi.setZero();
  const Vec12 f0 = corot_force(b, s0);
  if (force) *force = f0;
  const double ht = 1e-7 * b.l0, hr = 1e-7;
  Mat12 K;
  for (int c = 0; c < 12; ++c) {
    CorotState s = s0;
    const int node = c / 6, comp = c % 6;
    double h;
    if (comp < 3) {
      h = ht;
      (node == 0 ? s.xi : s.xj)(comp) += h;
    } else {
      h = hr;
      Mat3& R = node == 0 ? s.Ri : s.Rj;
      R = rotation_exp(h * Vec3::Unit(comp - 3)) * R;
    }
    K.col(c) = (corot_force(b, s) - f0) / h;
  }
  if (!symmetric) return K;
  return 0.5 * (K + K.transpose());
}

Vec6 truss_force(double EA, double l0, const Vec3& xi, const Vec3& xj, double* N) {
  const Vec3 dx = xj - xi;
  const double l = dx.norm();
  const Vec3 e = dx / l;
  const double n = EA * (l - l0) / l0;
  if (N) *N = n;
  Vec6 f;
  f.head<3>() = -n * e;
  f.tail<3>() = n * e;
  return f;
}

Mat6 truss_tangent(double EA, double l0, const Vec3& xi, const Vec3& xj) {
  const Vec3 dx = xj - xi;
  const double l = dx.norm();
  const Vec3 e = dx / l;
  const double n = EA * (l - l0) / l0;
  const Mat3 Kb = EA / l0 * e * e.transpose() + n / l * (Mat3::Identity() - e * e.transpose());
  Mat6 K;
  K << Kb, -Kb, -Kb, Kb;
  return K;
}

}  // namespace gridshell::fem
