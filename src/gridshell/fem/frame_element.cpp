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

namespace {

using Mat3x12 = Eigen::Matrix<double, 3, 12>;
using Row12 = Eigen::Matrix<double, 1, 12>;

// One evaluation of the corotational element: the kinematics, the local deformations and
// forces, and the pieces of the B matrix (local coordinates of the element frame Rr).
struct CorotEval {
  CorotKinematics k;
  Vec7 d, f;
  Mat3x12 Gt;      // spin of Rr (local components) per local dof variation
  Mat3x12 P1, P2;  // left spins of the local nodal rotations: P_i = I_i − Gᵀ
  Mat3 A1, A2;     // T_s⁻¹(θ̄_i)
  Vec12 fl;        // internal force, local components
};

CorotEval evaluate(const CorotBeam& b, const CorotState& st) {
  CorotEval e;
  const CorotKinematics& k = e.k = kinematics(b, st);
  e.d(0) = k.ln - b.l0;
  e.d.segment<3>(1) = k.th1;
  e.d.segment<3>(4) = k.th2;
  local_forces(b, e.d, e.f);
  // G^T: spin of the element frame (local components) per local dof [u1 w1 u2 w2].
  const double ln = k.ln, q2n = k.q(1);
  const double eta = k.q(0) / q2n, e11 = k.q1(0) / q2n, e12 = k.q1(1) / q2n, e21 = k.q2(0) / q2n,
               e22 = k.q2(1) / q2n;
  Mat3x12& Gt = e.Gt;
  Gt.setZero();
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
  e.P1 = -Gt;
  e.P2 = -Gt;
  e.P1.block<3, 3>(0, 3) += Mat3::Identity();
  e.P2.block<3, 3>(0, 9) += Mat3::Identity();
  e.A1 = inverse_left_jacobian(k.th1);
  e.A2 = inverse_left_jacobian(k.th2);
  e.fl = e.P1.transpose() * (e.A1.transpose() * e.f.segment<3>(1)) +
         e.P2.transpose() * (e.A2.transpose() * e.f.segment<3>(4));
  e.fl(0) -= e.f(0);
  e.fl(6) += e.f(0);
  return e;
}

// Local coordinates → global: every 3-block of v rotated by R.
Vec12 rotate_blocks(const Mat3& R, const Vec12& v) {
  Vec12 g;
  for (int a = 0; a < 4; ++a) g.segment<3>(3 * a) = R * v.segment<3>(3 * a);
  return g;
}

// Bᵀ k_l B, with k_l = ∂f/∂d of local_forces (symmetric: f is the gradient of the local strain
// energy). k_l is a rank-one axial term, a torsion pair and two 2×2 bending blocks, so the
// product is summed term by term from B's rows: about two thirds of the dense triple product's
// multiplications (1 044 against 1 596), and no 7 × 12 intermediate.
Mat12 material_stiffness(const CorotBeam& b, const Vec7& d, double N,
                         const Eigen::Matrix<double, 7, 12>& B) {
  const double l0 = b.l0;
  const double t1y = d(2), t1z = d(3), t2y = d(5), t2z = d(6);
  Vec7 g;  // ∂ε/∂d
  g << 1 / l0, 0, (4 * t1y - t2y) / 30, (4 * t1z - t2z) / 30, 0, (-t1y + 4 * t2y) / 30,
      (-t1z + 4 * t2z) / 30;
  const Row12 bg = g.transpose().lazyProduct(B);
  Mat12 k = ((b.s.EA * l0) * bg.transpose()).lazyProduct(bg);
  const Row12 bt = B.row(1) - B.row(4);
  k.noalias() += ((b.s.GJ / l0) * bt.transpose()).lazyProduct(bt);
  // Bending in the two planes: (θ1, θ2) at rows (2, 5) and (3, 6).
  const double EI[2] = {b.s.EIy, b.s.EIz};
  for (int p = 0; p < 2; ++p) {
    const double c = EI[p] / l0, n = N * l0 / 30;
    const double kii = 4 * c + 4 * n, kij = 2 * c - n;
    const Row12 bi = B.row(2 + p), bj = B.row(5 + p);
    const Row12 mi = kii * bi + kij * bj, mj = kij * bi + kii * bj;
    k.noalias() += bi.transpose().lazyProduct(mi) + bj.transpose().lazyProduct(mj);
  }
  return k;
}

// ∂(T_s⁻ᵀ(θ) m)/∂θ, with T_s⁻ᵀ(θ) m = m + ½ θ×m + c(t) θ×(θ×m), t = |θ|.
Mat3 inverse_jacobian_transpose_derivative(const Vec3& theta, const Vec3& m) {
  const double t = theta.norm();
  double c, dc;  // c(t) as in inverse_left_jacobian, dc = c′(t) / t
  if (t < 1e-4) {
    c = 1.0 / 12 + t * t / 720;
  } else {
    c = (1 - (t / 2) / std::tan(t / 2)) / (t * t);
  }
  if (t < 5e-2) {
    dc = 1.0 / 360 + t * t / 7560 + t * t * t * t / 201600;
  } else {
    const double s = std::sin(t / 2);
    dc = -2 / (t * t * t * t) + 1 / (2 * t * t * t * std::tan(t / 2)) + 1 / (4 * t * t * s * s);
  }
  const Vec3 ttm = theta.cross(theta.cross(m));
  return -0.5 * skew(m) +
         c * (theta * m.transpose() + theta.dot(m) * Mat3::Identity() - 2 * m * theta.transpose()) +
         dc * ttm * theta.transpose();
}

// ∂(Gᵀ s)/∂d_local for a fixed 3-vector s: the variation of the frame's spin matrix through the
// chord length and the local components of p, p1, p2 (δq_i = −skew(q_i) P_i δd).
Mat12 spin_matrix_derivative(const CorotEval& e, const Vec3& s) {
  const CorotKinematics& k = e.k;
  const double ln = k.ln, Q = k.q(1);
  const double eta = k.q(0) / Q, e11 = k.q1(0) / Q, e12 = k.q1(1) / Q, e21 = k.q2(0) / Q,
               e22 = k.q2(1) / Q;
  const Mat3x12 dq1 = -skew(k.q1) * e.P1, dq2 = -skew(k.q2) * e.P2;
  const Mat3x12 dq = 0.5 * (dq1 + dq2);
  const Row12 dQ = dq.row(1);
  Row12 dln = Row12::Zero();
  dln(0) = -1;
  dln(6) = 1;
  const Row12 deta = (dq.row(0) - eta * dQ) / Q;
  const Row12 de11 = (dq1.row(0) - e11 * dQ) / Q, de12 = (dq1.row(1) - e12 * dQ) / Q;
  const Row12 de21 = (dq2.row(0) - e21 * dQ) / Q, de22 = (dq2.row(1) - e22 * dQ) / Q;
  Mat12 D = Mat12::Zero();
  D.row(2) = s(0) / ln * deta - (eta * s(0) + s(1)) / (ln * ln) * dln;
  D.row(8) = -D.row(2);
  D.row(3) = 0.5 * s(0) * de12;
  D.row(4) = -0.5 * s(0) * de11;
  D.row(9) = 0.5 * s(0) * de22;
  D.row(10) = -0.5 * s(0) * de21;
  D.row(1) = s(2) / (ln * ln) * dln;
  D.row(7) = -D.row(1);
  return D;
}

}  // namespace

Vec12 corot_force(const CorotBeam& b, const CorotState& st, Vec7* local) {
  const CorotEval e = evaluate(b, st);
  if (local) *local = e.f;
  return rotate_blocks(e.k.Rr, e.fl);
}

Mat12 corot_tangent(const CorotBeam& b, const CorotState& st, Vec12* force, bool symmetric,
                    Vec7* local) {
  const CorotEval e = evaluate(b, st);
  if (force) *force = rotate_blocks(e.k.Rr, e.fl);
  if (local) *local = e.f;
  // f_g = E f_l with f_l = rᵀN + Σ P_iᵀ A_iᵀ m_i; in local components (δd_l = Eᵀ δd):
  //   δf_l = Bᵀ k_l B δd_l + Σ P_iᵀ ∂(A_iᵀ m_i)/∂θ_i B_i δd_l − ∂(Gᵀ s)/∂d_l δd_l,
  //   δE f_l = E (−skew(f_l,a))_a Gᵀ δd_l (the frame's spin), s = Σ A_iᵀ m_i.
  const Vec3 m1 = e.f.segment<3>(1), m2 = e.f.segment<3>(4);
  const Mat3x12 B1 = e.A1 * e.P1, B2 = e.A2 * e.P2;
  Eigen::Matrix<double, 7, 12> B;
  B.row(0).setZero();
  B(0, 0) = -1;
  B(0, 6) = 1;
  B.middleRows<3>(1) = B1;
  B.middleRows<3>(4) = B2;
  Mat12 k = material_stiffness(b, e.d, e.f(0), B);
  // P_iᵀ D_i with P_i = I_i − Gᵀ: D_i adds to node i's rotation rows, Gᵀ's part is one product.
  // Products coefficient-based: at these sizes Eigen's blocked GEMM spends more on packing.
  const Mat3x12 D1 = inverse_jacobian_transpose_derivative(e.k.th1, m1).lazyProduct(B1);
  const Mat3x12 D2 = inverse_jacobian_transpose_derivative(e.k.th2, m2).lazyProduct(B2);
  k.middleRows<3>(3) += D1;
  k.middleRows<3>(9) += D2;
  k.noalias() -= e.Gt.transpose().lazyProduct(D1 + D2);
  k -= spin_matrix_derivative(e, e.A1.transpose() * m1 + e.A2.transpose() * m2);
  for (int a = 0; a < 4; ++a)
    k.middleRows<3>(3 * a).noalias() -= skew(e.fl.segment<3>(3 * a)).lazyProduct(e.Gt);
  // To global components: K = E k Eᵀ, by 3-column blocks (k Eᵀ) then 3-row blocks.
  const Mat3& R = e.k.Rr;
  Mat12 T, K;
  for (int c = 0; c < 4; ++c)
    T.middleCols<3>(3 * c).noalias() = k.middleCols<3>(3 * c).lazyProduct(R.transpose());
  for (int a = 0; a < 4; ++a)
    K.middleRows<3>(3 * a).noalias() = R.lazyProduct(T.middleRows<3>(3 * a));
  if (!symmetric) return K;
  return 0.5 * (K + K.transpose());
}

Mat12 corot_tangent_finite_difference(const CorotBeam& b, const CorotState& st, bool symmetric) {
  // Translation invariance: work with xi = 0 so that perturbations are relative to the length.
  CorotState s0 = st;
  s0.xj = st.xj - st.xi;
  s0.xi.setZero();
  const double ht = 1e-5 * b.l0, hr = 1e-5;
  Mat12 K;
  for (int c = 0; c < 12; ++c) {
    const int node = c / 6, comp = c % 6;
    const double h = comp < 3 ? ht : hr;
    Vec12 f[2];
    for (int side = 0; side < 2; ++side) {
      CorotState s = s0;
      const double step = side == 0 ? h : -h;
      if (comp < 3) {
        (node == 0 ? s.xi : s.xj)(comp) += step;
      } else {
        Mat3& R = node == 0 ? s.Ri : s.Rj;
        R = rotation_exp(step * Vec3::Unit(comp - 3)) * R;
      }
      f[side] = corot_force(b, s);
    }
    K.col(c) = (f[0] - f[1]) / (2 * h);
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
