#pragma once
/// \file shell_element.h
/// The flat facet shell triangle: 3 nodes, 6 dof per node (ux, uy, uz, rx, ry, rz; rotations
/// right-handed about the global axes).
///
/// - Membrane: Felippa's optimal ANDES triangle "OPT" with corner drilling freedoms
///   (C. A. Felippa, "A study of optimal membrane triangles with drilling freedoms",
///   CMAME 192, 2003): basic stiffness with alpha_b = 3/2 plus the higher-order stiffness with
///   beta_0 = max((1 − 4ν²)/2, 0.01) and beta_1..9 = (1, 2, 1, 0, 1, −1, −1, −1, −2). It has a
///   true drilling stiffness, so a node where only coplanar facets meet is not singular.
/// - Bending: the discrete Kirchhoff triangle DKT in the explicit form of Batoz, Bathe and Ho
///   (IJNME 15, 1980), integrated exactly by the 3 mid-side point rule.
///
/// The element matrix is built in the facet's local frame (x along edge 0→1, z the facet normal
/// (p1 − p0) × (p2 − p0)) and rotated to the global frame. Cost: a few microseconds per element.

#include <Eigen/Core>

#include "gridshell/mesh/mesh.h"

namespace gridshell::fem {

using Mat9 = Eigen::Matrix<double, 9, 9>;
using Mat18 = Eigen::Matrix<double, 18, 18>;

/// Isotropic linear elastic plane-stress constants of a shell element.
struct ShellSection {
  double E = 0;          ///< Young's modulus (Pa)
  double nu = 0;         ///< Poisson's ratio
  double thickness = 0;  ///< m
};

/// The facet's local frame: rows are the unit local axes x, y, z (z = normal) in global
/// coordinates; `xy` are the 2-D local coordinates of the three nodes (node 0 at the origin).
struct FacetFrame {
  Eigen::Matrix3d R;
  Eigen::Matrix<double, 3, 2> xy;
  double area = 0;
};

/// Local frame of the triangle (p0, p1, p2). Area 0 when degenerate (R then undefined).
FacetFrame facet_frame(const Vec3& p0, const Vec3& p1, const Vec3& p2);

/// OPT membrane stiffness in local coordinates; dof order (ux, uy, rz) per node.
/// x, y: local node coordinates (counter-clockwise, area > 0).
Mat9 membrane_opt_stiffness(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                            const ShellSection& s);

/// Mean (= centroid) membrane strain (exx, eyy, gxy) of the OPT element for local membrane dofs
/// (ux, uy, rz per node); this is the strain of the basic stiffness (the higher-order part has
/// zero mean).
Eigen::Vector3d membrane_opt_mean_strain(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                                         const Eigen::Matrix<double, 9, 1>& u);

/// DKT bending stiffness in local coordinates; dof order (uz, rx, ry) per node.
Mat9 dkt_stiffness(const Eigen::Vector3d& x, const Eigen::Vector3d& y, const ShellSection& s);

/// Plane-stress constitutive matrix (stress per strain, Voigt with engineering shear).
Eigen::Matrix3d plane_stress_matrix(double E, double nu);

/// The full 18×18 element stiffness in global coordinates (dof order node-major:
/// ux uy uz rx ry rz of node 0, then node 1, node 2). Throws nothing; returns zero for a
/// degenerate facet (callers check the area first).
Mat18 shell_element_stiffness(const Vec3& p0, const Vec3& p1, const Vec3& p2,
                              const ShellSection& s);

/// Membrane stress (sxx, syy, sxy in Pa, mid-surface) of the facet in its local frame, from the
/// global 18-vector of nodal displacements.
Eigen::Vector3d shell_membrane_stress(const FacetFrame& frame, const ShellSection& s,
                                      const Eigen::Matrix<double, 18, 1>& u_global);

}  // namespace gridshell::fem
