// Member checks (EN 1993-1-1 §6.2.1(7) cross-section, §6.3.1 flexural buckling) on cantilevers
// and columns whose section forces are known in closed form, and χ against hand values.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/checks/member_checks.h"
#include "gridshell/core/error.h"
#include "gridshell/fem/frame_arclength.h"
#include "gridshell/fem/frame_solver.h"
#include "gridshell/surfaces/load.h"

using namespace gridshell;
using namespace gridshell::fem;

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kD = 0.037, kL = 2.0, kE = 210e9, kFy = 355e6;

/// A cantilever along `dir` from node 0 (clamped) to node 1 (free) with nodal load `F`, `M` at
/// the tip, 4 elements, the paper's Ø37 bar.
FrameModel cantilever(const Vec3& dir, const Vec3& F, const Vec3& M) {
  FrameModel m;
  m.nodes.resize(2, 3);
  m.nodes.row(0) = Vec3(0.3, -0.2, 1.0).transpose();
  m.nodes.row(1) = (Vec3(0.3, -0.2, 1.0) + kL * dir.normalized()).transpose();
  m.sections = {circle_section(kD, "bar")};
  m.materials = {{"steel", kE, 0.3, 7850}};
  FrameMember mb;
  mb.i = 0;
  mb.j = 1;
  mb.elements = 4;
  m.members = {mb};
  m.supports = {{0, {true, true, true, true, true, true}}};
  m.loads = {{1, F, M}};
  return m;
}

std::vector<MemberForces> linear_member_forces(const FrameModel& m) {
  const FrameMesh mesh = discretize(m);
  const FrameAssembler assembler(mesh);
  const LinearResult lin = linear_static(mesh, assembler);
  return member_forces(mesh, element_section_forces(mesh, assembler, lin.u));
}

checks::MemberCheckOptions with_fy(double fy) {
  checks::MemberCheckOptions o;
  o.fy = fy;
  return o;
}

const double kA = kPi * kD * kD / 4, kW = kPi * kD * kD * kD / 32;
}  // namespace

TEST(MemberChecks, SteelGradesParseAndGiveTheirYieldStrength) {
  EXPECT_EQ(checks::parse_steel_grade("S235"), checks::SteelGrade::s235);
  EXPECT_DOUBLE_EQ(checks::yield_strength(checks::parse_steel_grade("S275")), 275e6);
  EXPECT_DOUBLE_EQ(checks::yield_strength(checks::SteelGrade::s355), 355e6);
  EXPECT_STREQ(checks::to_string(checks::SteelGrade::s235), "S235");
  EXPECT_THROW(checks::parse_steel_grade("S460"), Error);
}

TEST(MemberChecks, BarUnderPureTensionUsesNOverAfy) {
  const double P = 150e3;  // N along the (skew) bar axis, tension
  const Vec3 dir = Vec3(1, 2, 0.5).normalized();
  const FrameModel m = cantilever(dir, P * dir, Vec3::Zero());
  const auto f = linear_member_forces(m);
  EXPECT_NEAR(f[0].N_max, P, 1e-6 * P);
  EXPECT_NEAR(f[0].N_min, P, 1e-6 * P);
  EXPECT_LT(f[0].M, 1e-6 * P * kD);
  const checks::MemberChecks c = checks::check_members(m, f, with_fy(kFy));
  const double expected = P / (kA * kFy);  // 0.3929
  EXPECT_NEAR(c.members[0].section, expected, 0.005 * expected);
  EXPECT_EQ(c.section_worst, 0);
  EXPECT_EQ(c.members[0].buckling, 0.0);  // tension: no buckling check
  EXPECT_EQ(c.buckling_worst, -1);
}

TEST(MemberChecks, CantileverUnderEndMomentUsesMOverWfy) {
  // Uniform bending: M = M0 everywhere, about an axis normal to the bar.
  const Vec3 dir = Vec3(0, 1, 0);
  const double M0 = 1.2e3;  // N·m
  const FrameModel m = cantilever(dir, Vec3::Zero(), Vec3(M0, 0, 0));
  const auto f = linear_member_forces(m);
  EXPECT_NEAR(f[0].M, M0, 1e-6 * M0);
  EXPECT_NEAR(f[0].N_max, 0, 1e-6);
  const checks::MemberChecks c = checks::check_members(m, f, with_fy(kFy));
  const double expected = M0 / (kW * kFy);  // 0.6783
  EXPECT_NEAR(c.members[0].section, expected, 0.005 * expected);
}

TEST(MemberChecks, CantileverUnderAxialAndTwoTransverseLoadsCombines) {
  // Tip load: axial P plus transverse Fy, Fz; the root moment is L √(Fy² + Fz²) (linear theory).
  const Vec3 dir(1, 0, 0);
  const double P = -40e3, Fy = 300, Fz = -400;
  const FrameModel m = cantilever(dir, Vec3(P, Fy, Fz), Vec3::Zero());
  const auto f = linear_member_forces(m);
  const double M = kL * std::hypot(Fy, Fz);
  EXPECT_NEAR(f[0].M, M, 1e-6 * M);
  EXPECT_NEAR(f[0].N_min, P, 1e-6 * std::abs(P));
  const checks::MemberChecks c = checks::check_members(m, f, with_fy(235e6));
  const double expected = std::abs(P) / (kA * 235e6) + M / (kW * 235e6);
  EXPECT_NEAR(c.members[0].section, expected, 0.005 * expected);
  // Compressed: flexural buckling by hand, L_cr = L = 2 m, curve c.
  const double I = kPi * std::pow(kD, 4) / 64;
  const double Ncr = kPi * kPi * kE * I / (kL * kL);
  const double lam = std::sqrt(kA * 235e6 / Ncr);
  const double phi = 0.5 * (1 + 0.49 * (lam - 0.2) + lam * lam);
  const double chi = 1 / (phi + std::sqrt(phi * phi - lam * lam));
  EXPECT_NEAR(c.members[0].slenderness, lam, 1e-9 * lam);
  EXPECT_NEAR(c.members[0].buckling, -P / (chi * kA * 235e6), 1e-9);
  EXPECT_EQ(c.buckling_worst, 0);
}

TEST(MemberChecks, ReductionFactorMatchesCurveCHandValues) {
  // Curve c (α = 0.49): published table value χ(1.0) = 0.5399; a worked example with
  // λ̄ = 1.203 gives Φ = 1.4694, χ = 0.4323; the plateau λ̄ ≤ 0.2 gives 1.
  EXPECT_NEAR(checks::buckling_reduction(1.0), 0.5399, 5e-5);
  EXPECT_NEAR(checks::buckling_reduction(1.203), 0.4323, 5e-5);
  EXPECT_DOUBLE_EQ(checks::buckling_reduction(0.2), 1.0);
  EXPECT_DOUBLE_EQ(checks::buckling_reduction(0.1), 1.0);
  // Monotone decreasing beyond the plateau.
  EXPECT_GT(checks::buckling_reduction(0.5), checks::buckling_reduction(0.6));
}

TEST(MemberChecks, CorotationalForcesAtASmallLoadEqualTheLinearOnes) {
  // The path's section forces (corotational element) agree with K_e u_e where the response is
  // linear: a cantilever under a small tip load, one Newton solve of the non-linear equilibrium.
  const Vec3 dir = Vec3(1, 1, 0).normalized();
  const FrameModel m = cantilever(dir, Vec3(-1, 0.2, -0.3), Vec3(0.05, 0, 0));
  const FrameMesh mesh = discretize(m);
  const FrameAssembler assembler(mesh);
  const auto lin = linear_member_forces(m);
  const NonlinearStaticResult ns = nonlinear_static(mesh, assembler, 1.0);
  const auto nl = member_forces(mesh, element_section_forces(mesh, ns.state));
  EXPECT_NEAR(nl[0].M, lin[0].M, 1e-3 * lin[0].M);
  EXPECT_NEAR(nl[0].N_min, lin[0].N_min, 1e-3 * std::abs(lin[0].N_min));
}

TEST(MemberChecks, RejectsMismatchedForces) {
  const FrameModel m = cantilever(Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3::Zero());
  EXPECT_THROW(checks::check_members(m, {}), Error);
  EXPECT_THROW(checks::check_members(m, {MemberForces{}}, with_fy(0)), Error);
}

TEST(MemberChecks, LambdaAtFirstYieldFollowsThePathSectionForces) {
  // A 1 m cantilever (Ø37, S355) under a transverse tip load F: the root moment F L reaches
  // W fy at λ = W fy / (F L) in linear theory; the tip deflects only ~3 % of L by then, so the
  // non-linear path's λ_y must agree within 1 %. δ at λ = 1 is F L³ / (3 E I).
  FrameModel m = cantilever(Vec3(1, 0, 0), Vec3::Zero(), Vec3::Zero());
  m.nodes.row(1) = m.nodes.row(0) + Eigen::RowVector3d(1.0, 0, 0);
  const double F = 300;
  m.loads = {{1, Vec3(0, 0, -F), Vec3::Zero()}};
  analysis::FrameAnalysisOptions o;
  o.buckling = false;
  o.checks.fy = kFy;
  o.deflection_limit_divisor = 300;
  const analysis::FrameResult r = analysis::analyze_frame(m, o);
  const double lambda_y = kW * kFy / (F * 1.0);  // 5.89
  ASSERT_TRUE(r.lambda_yield_linear.has_value());
  EXPECT_NEAR(*r.lambda_yield_linear, lambda_y, 1e-6 * lambda_y);
  ASSERT_TRUE(r.lambda_yield.has_value());
  EXPECT_NEAR(*r.lambda_yield, lambda_y, 0.01 * lambda_y);
  EXPECT_EQ(r.lambda_yield_path, "perfect");
  EXPECT_EQ(r.checks.section_worst, 0);
  const double I = kPi * std::pow(kD, 4) / 64, delta = F / (3 * kE * I);
  EXPECT_NEAR(r.delta_max_m, delta, 1e-3 * delta);
  EXPECT_DOUBLE_EQ(r.delta_limit_m, 1.0 / 300);  // span = plan extent = 1 m
  EXPECT_EQ(r.delta_pass, delta <= 1.0 / 300);
}

TEST(MemberChecks, ImperfectArchIsWeakerThanThePerfectOne) {
  // A shallow pinned two-bar arch (a von Mises truss of beams) under an apex load: with the
  // stability block both paths run, the imperfect one (first mode, span/300) carries less.
  FrameModel m;
  m.nodes.resize(3, 3);
  m.nodes << 0, 0, 0, 2, 0, 0.4, 4, 0, 0;
  m.sections = {circle_section(kD, "bar")};
  m.materials = {{"steel", kE, 0.3, 7850}};
  for (int k = 0; k < 2; ++k) {
    FrameMember mb;
    mb.i = k;
    mb.j = k + 1;
    mb.elements = 8;
    m.members.push_back(mb);
  }
  m.supports = {{0, {true, true, true, true, false, true}},
                {2, {true, true, true, true, false, true}}};
  m.loads = {{1, Vec3(0, 0, -1e3), Vec3::Zero()}};
  analysis::FrameAnalysisOptions o;
  o.stability = true;
  const analysis::FrameResult r = analysis::analyze_frame(m, o);
  ASSERT_TRUE(r.lambda_perfect && r.lambda_imperfect && r.lambda_linear_buckling);
  EXPECT_DOUBLE_EQ(*r.lambda_perfect, *r.lambda_nonlinear);  // imperfection off: main = perfect
  EXPECT_LT(*r.lambda_imperfect, *r.lambda_perfect);
  EXPECT_GT(*r.lambda_imperfect, 0.3 * *r.lambda_perfect);
  EXPECT_DOUBLE_EQ(r.imperfection_amplitude_m, 4.0 / 300);
}

TEST(MemberChecks, GridshellSectionForcesBalanceEveryJoint) {
  // Independent of how the forces were obtained: rebuild each element's 12 end forces from the
  // stored N, T, My, Mz alone (shears from the element's moment equilibrium), rotate them to
  // global axes and sum per node. At every free dof the sum must equal the applied load (forces
  // and moments): the section forces are complete, correctly signed and in the right frame.
  // The built-in dome grid-shell (triangulated surface as the frame), the paper's load, Eurocode
  // ULS so that the load is not only vertical self-weight shares.
  const PolySurface dome = load_poly_surface("builtin:dome");
  analysis::GridshellFrameOptions go;
  go.loads = analysis::LoadModel::eurocode;
  go.elements = 3;
  const FrameModel m = analysis::gridshell_frame(dome.mesh, dome.supports, go);
  const FrameMesh mesh = discretize(m);
  const FrameAssembler assembler(mesh);
  const LinearResult lin = linear_static(mesh, assembler);
  const auto forces = element_section_forces(mesh, assembler, lin.u);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(mesh.load_full.size());
  for (std::size_t k = 0; k < mesh.elements.size(); ++k) {
    const auto& e = mesh.elements[k];
    const ElementSectionForces& f = forces[k];
    const double L = e.beam.l0;
    const Vec3 fj(f.N, -(f.Mz[0] + f.Mz[1]) / L, (f.My[0] + f.My[1]) / L);
    const Vec3 mi(f.T[0], f.My[0], f.Mz[0]), mj(f.T[1], f.My[1], f.Mz[1]);
    const Mat3& R = e.beam.R0;
    sum.segment<3>(6 * e.i) -= R * fj;
    sum.segment<3>(6 * e.j) += R * fj;
    sum.segment<3>(6 * e.i + 3) += R * mi;
    sum.segment<3>(6 * e.j + 3) += R * mj;
  }
  double worst = 0, scale = 0;
  int free_dofs = 0;
  for (int v = 0; v < static_cast<int>(mesh.X.rows()); ++v)
    for (int c = 0; c < 6; ++c) {
      scale = std::max(scale, std::abs(mesh.load_full(6 * v + c)));
      if (mesh.dof[v][c] < 0) continue;
      ++free_dofs;
      worst = std::max(worst, std::abs(sum(6 * v + c) - mesh.load_full(6 * v + c)));
    }
  ASSERT_GT(free_dofs, 100);
  ASSERT_GT(scale, 0);
  RecordProperty("equilibrium_residual_relative", std::to_string(worst / scale));
  std::printf(
      "joint equilibrium from section forces: %d free dofs, worst residual %.3g of the "
      "largest load\n",
      free_dofs, worst / scale);
  EXPECT_LT(worst, 1e-6 * scale);
  // And the member envelope is the largest end value of the member's elements.
  const auto members = member_forces(mesh, forces);
  double largest = 0;
  for (const auto& f : forces) largest = std::max(largest, std::hypot(f.My[0], f.Mz[0]));
  double largest_member = 0;
  for (const auto& f : members) largest_member = std::max(largest_member, f.M);
  EXPECT_GE(largest_member, largest);
}

TEST(MemberChecks, SectionOuterFibreGivesTheModulus) {
  // A solid square b × b (c = b/2, W = b³/6) under an end moment: the section's c is used.
  FrameModel m = cantilever(Vec3(0, 1, 0), Vec3::Zero(), Vec3(800, 0, 0));
  const double b = 0.032;
  auto& s = m.sections[0];
  s.A = b * b;
  s.Iy = s.Iz = b * b * b * b / 12;
  s.J = 0.1406 * b * b * b * b;
  s.c = b / 2;
  const checks::MemberChecks c = checks::check_members(m, linear_member_forces(m), with_fy(kFy));
  const double expected = 800 / (b * b * b / 6 * kFy);
  EXPECT_NEAR(c.members[0].section, expected, 0.005 * expected);
}
