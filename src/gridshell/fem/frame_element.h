#pragma once
/// \file frame_element.h
/// The 3D frame elements.
///
/// * Linear 12-dof Euler–Bernoulli beam (cubic transverse, linear axial and torsion) and its
///   consistent geometric stiffness (the same cubic shape functions; torsional Wagner term
///   omitted), dofs per node [ux uy uz rx ry rz], used by the linear and LBA analyses.
/// * Corotational beam (Battini & Pacoste 2002 / Crisfield 1990 kinematics): the element frame
///   follows the chord and the mean of the two nodal triads; local deformations are the chord
///   elongation and the two nodal rotation vectors relative to that frame. The local element is
///   the shallow-arch Euler–Bernoulli beam (axial strain includes (1/30)(2θ1² − θ1θ2 + 2θ2²)
///   per bending plane), so that at small deformation its tangent equals linear + consistent
///   geometric stiffness. Internal forces are exact gradients of the local strain energy mapped
///   with the analytical B matrix (spins as global rotational variations); the tangent is their
///   exact (analytical) derivative: Bᵀ k_l B plus the variations of B — of T_s⁻¹(θ̄_i), of the
///   frame's spin matrix Gᵀ and of the frame itself — symmetrised on request.
/// * Corotational truss (engineering strain, analytical tangent).
///
/// Cost: linear ~1 µs, corotational force ~1 µs, corotational tangent ~2 µs per element.

#include <Eigen/Core>

#include "gridshell/mesh/mesh.h"

namespace gridshell::fem {

using Mat3 = Eigen::Matrix3d;
using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Vec7 = Eigen::Matrix<double, 7, 1>;

struct BeamStiffness {
  double EA = 0, EIy = 0, EIz = 0, GJ = 0;
};

/// Skew matrix: skew(a) b = a × b.
Mat3 skew(const Vec3& a);
/// Rotation matrix exp(skew(w)) (Rodrigues).
Mat3 rotation_exp(const Vec3& w);
/// Rotation vector of R with |θ| ≤ π (via the quaternion, robust near 0 and π).
Vec3 rotation_log(const Mat3& R);
/// Inverse of the left Jacobian of exp: δθ = T_s⁻¹(θ) δw for a left spin δw.
Mat3 inverse_left_jacobian(const Vec3& theta);

/// Initial element frame: columns e1 (i→j), e2 = e3 × e1, e3 = `up` made orthogonal to e1
/// (zero `up`: global z, or global x when the element is (nearly) vertical).
Mat3 element_frame(const Vec3& xi, const Vec3& xj, const Vec3& up);

/// Linear stiffness of a 12-dof beam, global coordinates. R0 = element_frame().
Mat12 beam_linear_stiffness(const BeamStiffness& s, double L, const Mat3& R0);
/// Consistent geometric stiffness for axial force N (tension positive), global coordinates.
Mat12 beam_geometric_stiffness(double N, double L, const Mat3& R0);

/// Corotational beam: reference state and state-dependent forces.
struct CorotBeam {
  BeamStiffness s;
  double l0 = 0;  ///< reference length
  Mat3 R0;        ///< reference element frame (columns)
};

/// The current configuration of an element's two nodes: positions and nodal rotation matrices
/// (relative to the reference configuration).
struct CorotState {
  Vec3 xi, xj;
  Mat3 Ri, Rj;
};

/// Local deformations d = [elongation, θ̄1 (3), θ̄2 (3)] and local forces f = ∂U/∂d.
void corot_local(const CorotBeam& b, const CorotState& st, Vec7& d, Vec7& f);
/// Global internal force vector [f_i, m_i, f_j, m_j]; optional local forces out
/// (f[0] = axial force N, tension positive).
Vec12 corot_force(const CorotBeam& b, const CorotState& st, Vec7* local = nullptr);
/// Tangent stiffness and the internal force. `symmetric`: return the symmetric part (the spin
/// tangent is not symmetric away from equilibrium or under applied moments).
/// `local`: optional out, the local forces as corot_force gives them.
Mat12 corot_tangent(const CorotBeam& b, const CorotState& st, Vec12* force = nullptr,
                    bool symmetric = true, Vec7* local = nullptr);
/// The central-difference Jacobian of corot_force (24 force evaluations, relative accuracy
/// ~1e-9): the independent reference the tests check corot_tangent against.
Mat12 corot_tangent_finite_difference(const CorotBeam& b, const CorotState& st,
                                      bool symmetric = true);

/// Corotational truss: force [f_i, f_j] (6) and tangent; N = EA (l − l0) / l0.
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
Vec6 truss_force(double EA, double l0, const Vec3& xi, const Vec3& xj, double* N = nullptr);
Mat6 truss_tangent(double EA, double l0, const Vec3& xi, const Vec3& xj);

}  // namespace gridshell::fem
