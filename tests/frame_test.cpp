// Frame analysis: elements, linear, linearised buckling and non-linear paths against closed
// forms and published benchmarks (sources in docs/frame.md).

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <Eigen/Eigenvalues>
#include <numbers>
#include <numeric>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/core/error.h"
#include "gridshell/core/rng.h"
#include "gridshell/fem/frame_arclength.h"
#include "gridshell/fem/frame_element.h"
#include "gridshell/fem/frame_solver.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/surfaces/load.h"

using namespace gridshell;
using namespace gridshell::fem;

namespace {
constexpr double kPi = std::numbers::pi;

FrameModel straight_member(const Vec3& a, const Vec3& b, int elements, const FrameSection& s,
                           double E, double nu = 0.3) {
  FrameModel m;
  m.nodes.resize(2, 3);
  m.nodes.row(0) = a.transpose();
  m.nodes.row(1) = b.transpose();
  m.sections = {s};
  m.materials = {{"steel", E, nu, 7850}};
  FrameMember mb;
  mb.i = 0;
  mb.j = 1;
  mb.elements = elements;
  m.members = {mb};
  return m;
}

FrameSupport fix(int node, std::array<bool, 6> f) {
  return {node, f};
}
}  // namespace

TEST(FrameElement, CorotationalTangentAtRestEqualsLinearStiffness) {
  CorotBeam b;
  b.s = {2.1e11 * 1e-3, 2.1e11 * 1e-7, 2.1e11 * 2e-7, 8e10 * 3e-7};
  b.l0 = 0.7;
  const Vec3 xi(0.1, 0.2, 0.3), xj = xi + Vec3(0.3, -0.4, 0.5).normalized() * 0.7;
  b.R0 = element_frame(xi, xj, Vec3::Zero());
  CorotState st{xi, xj, Mat3::Identity(), Mat3::Identity()};
  const Mat12 Kt = corot_tangent(b, st);
  const Mat12 Kl = beam_linear_stiffness(b.s, b.l0, b.R0);
  EXPECT_LT((Kt - Kl).norm() / Kl.norm(), 1e-6);
}

TEST(FrameElement, CorotationalTangentUnderAxialForceAddsGeometricStiffness) {
  // A stretched element at rest orientation: tangent = K_lin + K_G(N) to FD accuracy.
  CorotBeam b;
  b.s = {1e6, 2e3, 3e3, 1e3};
  b.l0 = 1.0;
  const Vec3 xi(0, 0, 0), xj(1, 0, 0);
  b.R0 = element_frame(xi, xj, Vec3::Zero());
  const double stretch = 1e-3;
  CorotState st{xi, Vec3(1 + stretch, 0, 0), Mat3::Identity(), Mat3::Identity()};
  Vec7 d, f;
  corot_local(b, st, d, f);
  EXPECT_NEAR(f(0), b.s.EA * stretch, 1e-9 * b.s.EA);
  const Mat12 Kt = corot_tangent(b, st);
  const Mat12 Kref = beam_linear_stiffness(b.s, b.l0 * (1 + stretch), b.R0) +
                     beam_geometric_stiffness(f(0), b.l0 * (1 + stretch), b.R0);
  // Bending terms use l0 in the element, so compare the transverse–geometric pattern loosely.
  EXPECT_LT((Kt - Kref).norm() / Kref.norm(), 5e-3);
}

TEST(FrameElement, RigidRotationGivesNoForces) {
  CorotBeam b;
  b.s = {1e6, 2e3, 3e3, 1e3};
  b.l0 = 2.0;
  const Vec3 xi(0, 0, 0), xj(2, 0, 0);
  b.R0 = element_frame(xi, xj, Vec3::Zero());
  const Mat3 Q = rotation_exp(Vec3(0.3, -1.2, 2.0));
  const Vec3 t(5, -3, 1);
  CorotState st{Q * xi + t, Q * xj + t, Q, Q};
  EXPECT_LT(corot_force(b, st).norm(), 1e-9 * b.s.EA);
}

namespace {
// |A − B| / |B| after scaling rows and columns by 1/√diag(K_lin): translations and rotations,
// axial and bending terms weigh alike (unscaled, the axial EA/L would hide the rest).
double scaled_difference(const Mat12& A, const Mat12& B, const Mat12& Klin) {
  const Eigen::Matrix<double, 12, 1> s = Klin.diagonal().cwiseSqrt().cwiseInverse();
  return (s.asDiagonal() * (A - B) * s.asDiagonal()).norm() /
         (s.asDiagonal() * B * s.asDiagonal()).norm();
}

// A random deformed state of a random element: rotations up to ~1 rad, stretch of a few 1e-3.
std::pair<CorotBeam, CorotState> random_corot_state(Rng& rng, double rotation) {
  const auto rvec = [&](double a) {
    return Vec3(rng.uniform(-a, a), rng.uniform(-a, a), rng.uniform(-a, a));
  };
  const FrameSection sec = circle_section(0.037);
  const double E = 2.1e11, G = E / 2.6;
  CorotBeam b;
  b.s = {E * sec.A, E * sec.Iy, E * 1.5 * sec.Iz, G * sec.J};
  b.l0 = rng.uniform(0.3, 2.0);
  const Vec3 xi = rvec(5), xj = xi + rvec(1).normalized() * b.l0;
  b.R0 = element_frame(xi, xj, rvec(1));
  // A rigid motion, then small relative rotations and a stretch (a beam's working range), plus
  // a large common part: the element frame's own rotation.
  const Mat3 Q = rotation_exp(rvec(rotation));
  CorotState st;
  st.xi = Q * xi + rvec(1);
  st.xj = st.xi + Q * (xj - xi) * (1 + rng.uniform(-3e-3, 3e-3)) + rvec(0.02 * b.l0);
  st.Ri = rotation_exp(rvec(0.1)) * Q;
  st.Rj = rotation_exp(rvec(0.1)) * Q;
  return {b, st};
}
}  // namespace

// The analytical corotational tangent is the exact derivative of the internal forces: against
// the central-difference Jacobian (an independent evaluation of corot_force only) on random
// deformed states, unsymmetrised and symmetrised.
TEST(FrameElement, AnalyticalTangentMatchesFiniteDifferences) {
  Rng rng(20);
  double worst = 0, worst_sym = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const auto [b, st] = random_corot_state(rng, trial < 100 ? 1.0 : 3.0);
    const Mat12 Klin = beam_linear_stiffness(b.s, b.l0, b.R0);
    Vec12 f;
    Vec7 local, local_ref;
    const Mat12 K = corot_tangent(b, st, &f, false, &local);
    const Vec12 f_ref = corot_force(b, st, &local_ref);
    EXPECT_EQ(f, f_ref);
    EXPECT_EQ(local, local_ref);
    ASSERT_GT(f.norm(), 1e-3 * Klin.norm() * 1e-3);  // a loaded state, not the rest state
    worst = std::max(worst,
                     scaled_difference(K, corot_tangent_finite_difference(b, st, false), Klin));
    worst_sym = std::max(worst_sym, scaled_difference(corot_tangent(b, st),
                                                      corot_tangent_finite_difference(b, st), Klin));
  }
  std::printf("analytical vs finite-difference tangent: worst %.3g (symmetrised %.3g)\n", worst,
              worst_sym);
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(worst_sym, 1e-6);
}

// Where no end moment acts (a stretched element, rigidly rotated) the spin tangent is
// symmetric; with end moments its skew part is what the symmetrised tangent drops.
TEST(FrameElement, AnalyticalTangentIsSymmetricWithoutEndMoments) {
  CorotBeam b;
  b.s = {1e6, 2e3, 3e3, 1e3};
  b.l0 = 1.5;
  const Vec3 xi(0.2, -0.1, 0.4), xj = xi + Vec3(0.6, 0.8, 0.0) * 1.5;
  b.R0 = element_frame(xi, xj, Vec3::Zero());
  const Mat3 Q = rotation_exp(Vec3(0.7, -0.4, 1.1));
  const CorotState st{Q * xi, Q * (xi + (xj - xi) * 1.002), Q, Q};
  Vec7 local;
  const Mat12 K = corot_tangent(b, st, nullptr, false, &local);
  EXPECT_NEAR(local(0), b.s.EA * 0.002, 1e-9 * b.s.EA);
  EXPECT_LT(local.tail<6>().norm(), 1e-9 * b.s.EA);
  EXPECT_LT((K - K.transpose()).norm(), 1e-12 * K.norm());
  // With end moments (relative rotations of the nodes) it is not.
  CorotState bent = st;
  bent.Rj = rotation_exp(Vec3(0.0, 0.05, 0.08)) * Q;
  const Mat12 Kb = corot_tangent(b, bent, nullptr, false);
  EXPECT_GT((Kb - Kb.transpose()).norm(), 1e-8 * Kb.norm());
}

// Euler column, pin–pin, solid Ø37 steel, L = 1.5 m: P_cr = π² E I / L² = 84.74 kN.
TEST(FrameBuckling, EulerColumnLinearisedBuckling) {
  const FrameSection s = circle_section(0.037);
  const double E = 2.1e11, L = 1.5;
  const double Pcr = kPi * kPi * E * s.Iy / (L * L);
  EXPECT_NEAR(Pcr, 84.74e3, 0.01e3);
  FrameModel m = straight_member(Vec3(0, 0, 0), Vec3(L, 0, 0), 4, s, E);
  m.supports = {fix(0, {true, true, true, true, false, false}),
                fix(1, {false, true, true, false, false, false})};
  m.loads = {{1, Vec3(-1000, 0, 0), Vec3::Zero()}};
  const FrameMesh mesh = discretize(m);
  const FrameAssembler asmb(mesh);
  const LinearResult lin = linear_static(mesh, asmb);
  EXPECT_NEAR(lin.displacement(1, 0), -1000 * L / (E * s.A), 1e-12);
  const BucklingResult b = linear_buckling(mesh, asmb, lin);
  ASSERT_GE(b.lambdas.size(), 2u);
  std::printf("Euler column LBA (4 elements): P/Pcr = %.6f\n", b.lambdas[0] * 1000 / Pcr);
  EXPECT_NEAR(b.lambdas[0] * 1000 / Pcr, 1.0, 0.005);
  EXPECT_NEAR(b.lambdas[0] * 1000 / Pcr, 1.0, 0.001);  // cubic elements, 4 per member
}

namespace {
// Cantilever along x from the origin, clamped at node 0, `n` elements.
FrameModel cantilever(double L, int n, double EI, const Vec3& dir = Vec3::UnitX(),
                      const Vec3& up = Vec3::Zero()) {
  FrameSection s;
  s.A = 1.0;
  s.Iy = s.Iz = EI / 1e6;
  s.J = 2 * s.Iy;
  s.up = up;
  FrameModel m = straight_member(Vec3::Zero(), L * dir, n, s, 1e6, 0.3);
  m.sections[0].A = 1e4 * s.Iy / (L * L) * 1e2;  // axially stiff (inextensible elastica)
  m.supports = {fix(0, {true, true, true, true, true, true})};
  return m;
}
}  // namespace

// Mattiasson (1981) elastica: cantilever with a transverse tip load, exact values.
TEST(FrameNonlinear, MattiassonElastica) {
  const double L = 1, EI = 1;
  struct Row {
    double load, dx, dy, rot;
  };
  const Row table[] = {{1, 0.05643, 0.30172, 0.46135},
                       {2, 0.16064, 0.49346, 0.78175},
                       {5, 0.38763, 0.71379, 1.21537},
                       {10, 0.55500, 0.81061, 1.43029}};
  for (const Row& row : table) {
    FrameModel m = cantilever(L, 16, EI);
    m.loads = {{1, Vec3(0, row.load * EI / (L * L), 0), Vec3::Zero()}};
    const FrameMesh mesh = discretize(m);
    const FrameAssembler asmb(mesh);
    const NonlinearStaticResult r = nonlinear_static(mesh, asmb, 1.0);
    const Vec3 tip = r.state.x.row(1).transpose();
    const double rot = rotation_log(r.state.R[1]).z();
    std::printf("Mattiasson P=%g: dx %.5f (%.5f) dy %.5f (%.5f) rot %.5f (%.5f)\n", row.load,
                L - tip.x(), row.dx, tip.y(), row.dy, rot, row.rot);
    EXPECT_NEAR((L - tip.x()) / row.dx, 1.0, 0.005) << "P L²/EI = " << row.load;
    EXPECT_NEAR(tip.y() / row.dy, 1.0, 0.005) << "P L²/EI = " << row.load;
    EXPECT_NEAR(rot / row.rot, 1.0, 0.005) << "P L²/EI = " << row.load;
  }
}

// λ_δ on the elastica: Mattiasson's tip displacement at P L²/EI = 1 is |(−0.05643, 0.30172)| L,
// so the path reaches that displacement at λ = 1 for the reference load P = EI/L².
TEST(FrameNonlinear, LambdaAtADisplacementLimitOnTheElastica) {
  const double L = 1, EI = 1;
  FrameModel m = cantilever(L, 16, EI);
  m.loads = {{1, Vec3(0, EI / (L * L), 0), Vec3::Zero()}};
  analysis::FrameAnalysisOptions o;
  o.buckling = false;  // no compression: no buckling
  o.arc.max_displacement = 0.6 * L;
  o.displacement_limit = std::hypot(0.05643, 0.30172) * L;
  const analysis::FrameResult r = analysis::analyze_frame(m, o);
  ASSERT_TRUE(r.lambda_displacement_limit.has_value());
  std::printf("elastica: lambda at |u| = %.5f L: %.5f (exact 1), %zu path points, %s\n",
              o.displacement_limit, *r.lambda_displacement_limit, r.path.size(),
              to_string(r.limit_type));
  EXPECT_NEAR(*r.lambda_displacement_limit, 1.0, 0.01);
  EXPECT_EQ(r.limit_type, LimitType::none);
  EXPECT_DOUBLE_EQ(r.displacement_limit_m, o.displacement_limit);
  // Default limit: span / 100 (span = L here), nearly linear: λ ≈ (L/100) / δ.
  o.displacement_limit = 0;
  const analysis::FrameResult d = analysis::analyze_frame(m, o);
  ASSERT_TRUE(d.lambda_displacement_limit.has_value());
  EXPECT_DOUBLE_EQ(d.displacement_limit_m, L / 100);
  EXPECT_NEAR(*d.lambda_displacement_limit * d.delta_max_m / (L / 100), 1.0, 0.01);
}

// A located crossing is a point of the path: full Newton at its λ (nonlinear_static) puts the
// largest displacement on the level to 1e-6, and paths whose points fall elsewhere (first steps
// 7× apart) locate the same λ to 1e-7, where reading it off between their points does not.
TEST(FrameNonlinear, ACrossingIsLocatedOnThePathWhereverItsPointsFall) {
  const double L = 1, EI = 1, level = 0.45 * L;
  FrameModel m = cantilever(L, 16, EI);
  m.loads = {{1, Vec3(0, EI / (L * L), 0), Vec3::Zero()}};
  const FrameMesh mesh = discretize(m);
  const FrameAssembler asmb(mesh);
  const auto largest = [&mesh](const FrameState& st) {
    return (st.x - mesh.X).rowwise().norm().maxCoeff();
  };
  std::vector<double> located, read_off;
  for (const double first : {0.05, 0.35}) {
    ArcLengthOptions opt;
    opt.initial_lambda = first;
    opt.max_displacement = 0.6 * L;
    opt.crossings = {{[&](const FrameState& st, double) { return largest(st); }, level}};
    const ArcLengthResult r = arc_length(mesh, asmb, opt, reference_state(mesh));
    ASSERT_EQ(r.crossing_steps.size(), 1u);
    ASSERT_TRUE(r.crossing_steps[0].has_value());
    const CrossingStep& step = *r.crossing_steps[0];
    EXPECT_LT(step.value_from, level);
    EXPECT_GE(step.value_to, level);
    int factorizations = 0;
    const std::optional<double> at =
        locate_crossing(mesh, asmb, opt, opt.crossings[0], step, factorizations);
    ASSERT_TRUE(at.has_value());
    EXPECT_GT(*at, step.lambda_from);
    EXPECT_LT(*at, step.lambda_to);
    const NonlinearStaticResult newton = nonlinear_static(mesh, asmb, *at);
    std::printf("elastica: |u| = %.2f L at lambda %.9f (%zu points, %d factorisations), Newton "
                "there: |u| = %.9f\n",
                level, *at, r.path.size(), factorizations, largest(newton.state));
    EXPECT_NEAR(largest(newton.state) / level, 1.0, 1e-6);
    located.push_back(*at);
    const PathPoint* a = nullptr;  // the linear reading between the points around the crossing
    for (const PathPoint& b : r.path) {
      if (a && b.displacement >= level) {
        read_off.push_back(a->lambda + (level - a->displacement) /
                                           (b.displacement - a->displacement) *
                                           (b.lambda - a->lambda));
        break;
      }
      a = &b;
    }
  }
  ASSERT_EQ(read_off.size(), 2u);
  std::printf("elastica: located %.9f / %.9f, read off linearly %.6f / %.6f\n", located[0],
              located[1], read_off[0], read_off[1]);
  EXPECT_NEAR(located[0] / located[1], 1.0, 1e-7);
  EXPECT_GT(std::abs(read_off[0] / read_off[1] - 1), 1e-5);
}

// Asking only for λ_δ stops the path at the displacement limit: the same λ_δ (the same points
// up to there), a shorter path, and no λ (the path never reached a critical point).
TEST(FrameNonlinear, PathStopsWhenOnlyLambdaAtTheDisplacementLimitIsAsked) {
  const double L = 1, EI = 1;
  FrameModel m = cantilever(L, 16, EI);
  m.loads = {{1, Vec3(0, EI / (L * L), 0), Vec3::Zero()}};
  analysis::FrameAnalysisOptions o;
  o.buckling = false;
  o.arc.max_displacement = 0.6 * L;
  o.displacement_limit = std::hypot(0.05643, 0.30172) * L;
  const analysis::FrameResult full = analysis::analyze_frame(m, o);
  o.path_goal = analysis::PathGoal::displacement_limit;
  const analysis::FrameResult cut = analysis::analyze_frame(m, o);
  ASSERT_TRUE(full.lambda_displacement_limit && cut.lambda_displacement_limit);
  std::printf("elastica: lambda_delta %.6f in %zu points (full path %zu points)\n",
              *cut.lambda_displacement_limit, cut.path.size(), full.path.size());
  EXPECT_DOUBLE_EQ(*cut.lambda_displacement_limit, *full.lambda_displacement_limit);
  EXPECT_LT(cut.path.size() + 2, full.path.size());
  EXPECT_GE(cut.path.back().displacement, o.displacement_limit);
  EXPECT_TRUE(full.lambda_nonlinear.has_value());
  EXPECT_FALSE(cut.lambda_nonlinear.has_value());
  EXPECT_EQ(cut.nonlinear_stop_reason, "maximum displacement reached");
}

// A path that creeps towards a limit it cannot pass — the funicular at four times its size with
// 40 cells, where the step is cut back before every point near the end and λ rises by less than
// 2e-5 a step — ends once it has stalled: the λ of the same path followed until its radius
// reaches the floor (the rules off), to 1e-6, for fewer factorisations. Two pinned steps in a row
// (λ up by less than 1e-6 λ after a cut-back) end it sooner still, with the same λ.
TEST(FrameNonlinear, AStalledPathEndsWithTheLambdaOfTheWholeCreep) {
  SurfaceOptions scaled;
  scaled.scale = 4;
  const Surface s = load_surface("builtin:funicular:res=16", scaled);
  DesignOptions o;
  o.tessellation.cells = 40;
  o.field_options.D = o.field_options.A = 2;
  o.analyze = analysis::AnalysisLevel::nonlinear;
  o.frame_analysis.stability = false;
  const DesignResult pinned = run_design(s, o);
  o.frame_analysis.arc.pinned_tolerance = 0;
  const DesignResult stalled = run_design(s, o);
  o.frame_analysis.arc.stall_steps = 0;
  const DesignResult crept = run_design(s, o);
  ASSERT_TRUE(pinned.structure && stalled.structure && crept.structure);
  const analysis::FrameResult &p = *pinned.structure, &a = *stalled.structure,
                              &b = *crept.structure;
  ASSERT_TRUE(p.lambda_nonlinear && a.lambda_nonlinear && b.lambda_nonlinear);
  std::printf(
      "pinned: lambda %.9f, %d factorisations; stalled: %.9f, %d (%s); whole creep: %.9f, %d "
      "(%s)\n",
      *p.lambda_nonlinear, p.nonlinear_factorizations, *a.lambda_nonlinear,
      a.nonlinear_factorizations, a.nonlinear_stop_reason.c_str(), *b.lambda_nonlinear,
      b.nonlinear_factorizations, b.nonlinear_stop_reason.c_str());
  EXPECT_EQ(p.nonlinear_stop_reason, "the path stalled below a limit it could not pass");
  EXPECT_EQ(a.nonlinear_stop_reason, "the path stalled below a limit it could not pass");
  EXPECT_EQ(b.nonlinear_stop_reason, "the arc-length step could not converge");
  EXPECT_NEAR(*a.lambda_nonlinear / *b.lambda_nonlinear, 1.0, 1e-6);
  EXPECT_NEAR(*p.lambda_nonlinear / *b.lambda_nonlinear, 1.0, 1e-6);
  EXPECT_LT(a.nonlinear_factorizations, b.nonlinear_factorizations);
  EXPECT_LT(p.nonlinear_factorizations, a.nonlinear_factorizations);
}

// A cantilever under an end moment M = 2π EI / L rolls up into a full circle.
TEST(FrameNonlinear, EndMomentRollsIntoCircle) {
  const double L = 2, EI = 5;
  for (int inclined = 0; inclined < 2; ++inclined) {
    const Vec3 dir = inclined ? Vec3(1, 2, 3).normalized() : Vec3::UnitX();
    // Bending plane: the moment about an axis perpendicular to the member.
    const Vec3 axis = inclined ? dir.cross(Vec3(0.3, -1, 0.2)).normalized() : Vec3::UnitZ();
    FrameModel m = cantilever(L, 20, EI, dir);
    m.loads = {{1, Vec3::Zero(), 2 * kPi * EI / L * axis}};
    const FrameMesh mesh = discretize(m);
    const FrameAssembler asmb(mesh);
    const NonlinearStaticResult r = nonlinear_static(mesh, asmb, 1.0);
    const Vec3 tip = r.state.x.row(1).transpose();
    std::printf("End moment (%s): |tip - root| / L = %.3g\n", inclined ? "inclined" : "plane",
                tip.norm() / L);
    EXPECT_LT(tip.norm(), 1e-4 * L) << (inclined ? "inclined" : "plane");
    // Half the moment: a half circle, tip at distance 2R = 2L/π from the root.
    const NonlinearStaticResult h = nonlinear_static(mesh, asmb, 0.5);
    EXPECT_NEAR(h.state.x.row(1).norm(), 2 * L / kPi, 1e-3 * L);
    // Equilibrium: the root reaction moment balances the applied one.
    EXPECT_NEAR((r.reactions.segment<3>(3) + 2 * kPi * EI / L * axis).norm(), 0,
                1e-8 * 2 * kPi * EI / L);
  }
}

namespace {
// Levy & Spillers 24-member shallow star dome, inches and pounds; crown load 1 lb (λ = load).
FrameModel star_dome() {
  FrameModel m;
  m.nodes.resize(13, 3);
  m.nodes.row(0) << 0, 0, 3.2346;
  for (int k = 0; k < 6; ++k) {
    const double a = kPi / 3 * (k + 1), b = kPi / 2 + kPi / 3 * k;
    m.nodes.row(1 + k) << 9.8425 * std::cos(a), 9.8425 * std::sin(a), 2.4472;
    m.nodes.row(7 + k) << 19.685 * std::cos(b), 19.685 * std::sin(b), 0;
  }
  FrameSection s;
  s.name = "truss";
  s.A = 0.0155;
  s.Iy = s.Iz = s.J = 1;  // unused by trusses
  m.sections = {s};
  m.materials = {{"dome", 3.0e7, 0.3, 0}};
  auto add = [&](int i, int j) {
    FrameMember mb;
    mb.i = i;
    mb.j = j;
    mb.type = MemberType::truss;
    m.members.push_back(mb);
  };
  for (int k = 0; k < 6; ++k) {
    add(0, 1 + k);
    add(1 + k, 1 + (k + 1) % 6);
    // inner node at 60°(k+1) sits between outer nodes at 60°(k+1) ± 30°
    add(1 + k, 7 + k);            // 90° + 60°k = 60°(k+1) + 30°
    add(1 + k, 7 + (k + 5) % 6);  // 60°(k+1) − 30°
  }
  for (int k = 0; k < 6; ++k)
    m.supports.push_back(fix(7 + k, {true, true, true, true, true, true}));
  m.loads = {{0, Vec3(0, 0, -1), Vec3::Zero()}};
  return m;
}
}  // namespace

TEST(FrameStarDome, LinearBucklingAndLimitPoint) {
  const FrameModel m = star_dome();
  const FrameMesh mesh = discretize(m);
  const FrameAssembler asmb(mesh);
  const LinearResult lin = linear_static(mesh, asmb);
  EXPECT_NEAR(lin.displacement(0, 2) * 220.46 / -0.20641, 1.0, 0.005);
  // Equilibrium of the linear solution: reactions balance the load.
  Vec3 R = Vec3::Zero();
  for (int v = 0; v < mesh.num_model_nodes; ++v) R += lin.reactions.segment<3>(6 * v);
  EXPECT_LT((R + Vec3(0, 0, -1)).norm(), 1e-9);
  const BucklingResult b = linear_buckling(mesh, asmb, lin);
  ASSERT_FALSE(b.lambdas.empty());
  EXPECT_NEAR(b.lambdas[0] / 707, 1.0, 0.03);
  ArcLengthOptions opt;
  opt.initial_lambda = 10;
  const ArcLengthResult nl = arc_length(mesh, asmb, opt, reference_state(mesh));
  EXPECT_EQ(nl.limit_type, LimitType::limit_point);
  EXPECT_NEAR(nl.lambda_critical / 146.7, 1.0, 0.02);
  const double w = nl.critical_state.x(0, 2) - m.nodes(0, 2);
  EXPECT_NEAR(-w, 0.30, 0.05);
  std::printf(
      "star dome: crown %.6f in at 220.46 lb, LBA %.2f lb, limit %.3f lb (%s), w %.4f in, "
      "%d steps, %d iterations, %d factorisations\n",
      lin.displacement(0, 2) * 220.46, b.lambdas[0], nl.lambda_critical, to_string(nl.limit_type),
      w, nl.steps, nl.iterations, nl.factorizations);
}

namespace {
FrameModel euler_column(double L, int n, double imperfection) {
  const FrameSection s = circle_section(0.037);
  FrameModel m = straight_member(Vec3(0, 0, 0), Vec3(L, 0, 0), n, s, 2.1e11);
  m.supports = {fix(0, {true, true, true, true, false, false}),
                fix(1, {false, true, true, false, false, false})};
  m.loads = {{1, Vec3(-1000, 0, 0), Vec3::Zero()}};
  if (imperfection == 0) return m;
  // Replace the member by n straight pieces through a half-sine of amplitude `imperfection`.
  FrameModel c = m;
  c.nodes.resize(n + 1, 3);
  c.members.clear();
  for (int k = 0; k <= n; ++k) c.nodes.row(k) << L * k / n, 0, imperfection * std::sin(kPi * k / n);
  for (int k = 0; k < n; ++k) {
    FrameMember mb;
    mb.i = k;
    mb.j = k + 1;
    c.members.push_back(mb);
  }
  c.supports = {fix(0, {true, true, true, true, false, false}),
                fix(n, {false, true, true, false, false, false})};
  c.loads = {{n, Vec3(-1000, 0, 0), Vec3::Zero()}};
  return c;
}
}  // namespace

TEST(FrameBuckling, EulerColumnNonlinear) {
  const double L = 1.5, Pcr = 84.74e3;
  {  // perfect: the fundamental path meets a (stable symmetric) bifurcation
    const FrameModel m = euler_column(L, 8, 0);
    const FrameMesh mesh = discretize(m);
    const FrameAssembler asmb(mesh);
    ArcLengthOptions opt;
    opt.initial_lambda = 10;
    const ArcLengthResult r = arc_length(mesh, asmb, opt, reference_state(mesh));
    // Round-off lets the arc-length switch onto the (stable, flat) buckled branch right at the
    // bifurcation, or it detects the pivot change: either way λ must sit at P_cr.
    EXPECT_TRUE(r.limit_type == LimitType::bifurcation || r.limit_type == LimitType::none)
        << to_string(r.limit_type);
    std::printf("Euler column perfect, arc-length (8 elements): P/Pcr = %.6f (%s)\n",
                r.lambda_critical * 1000 / Pcr, to_string(r.limit_type));
    EXPECT_NEAR(r.lambda_critical * 1000 / Pcr, 1.0, 0.005);
  }
  {  // imperfect (L/1000 half-sine): the load approaches P_cr as the column bows to L/10
    const FrameModel m = euler_column(L, 8, L / 1000);
    const FrameMesh mesh = discretize(m);
    const FrameAssembler asmb(mesh);
    ArcLengthOptions opt;
    opt.initial_lambda = 10;
    opt.max_displacement = L / 10;
    const ArcLengthResult r = arc_length(mesh, asmb, opt, reference_state(mesh));
    EXPECT_EQ(r.limit_type, LimitType::none);
    std::printf("Euler column L/1000 imperfection, at L/10 sway: P/Pcr = %.6f\n",
                r.lambda_critical * 1000 / Pcr);
    EXPECT_NEAR(r.lambda_critical * 1000 / Pcr, 1.0, 0.02);
  }
}

// The first buckling mode of a pin-pin column is the half-sine: lateral, zero at the ends,
// largest (scaled to 1) at mid-span, sin(πk/n) at node k.
TEST(FrameBuckling, EulerColumnModeShapeIsTheHalfSine) {
  const int n = 8;
  const FrameModel m = euler_column(1.5, n, 1e-9);  // model nodes at every element end
  analysis::FrameAnalysisOptions o;
  o.buckling = true;
  o.buckling_modes = 2;
  const analysis::FrameResult r = analysis::analyze_frame(m, o);
  ASSERT_EQ(r.buckling_modes.size(), r.buckling_lambdas.size());
  ASSERT_GE(r.buckling_modes.size(), 1u);
  const Points& shape = r.buckling_modes.front();
  ASSERT_EQ(shape.rows(), n + 1);
  EXPECT_NEAR(shape.rowwise().norm().maxCoeff(), 1.0, 1e-12);
  for (int k = 0; k <= n; ++k) {
    EXPECT_NEAR(shape.row(k).tail<2>().norm(), std::sin(kPi * k / n), 0.01) << k;
    EXPECT_LT(std::abs(shape(k, 0)), 0.01) << k;  // no axial movement in the mode
  }
}

namespace {
// The von Mises two-bar truss (half-span a = 10, rise h = 1, EA = 1e5, pin-jointed, the apex
// loaded downwards) and its closed-form limit load max P(w) = max −2 N (h − w) / l with
// N = EA (l − l0) / l0, l = √(a² + (h − w)²), over the apex deflection w (at `wmax`).
FrameModel von_mises_truss(double& Pmax, double* wmax = nullptr) {
  const double a = 10, h = 1, EA = 1e5;
  FrameModel m;
  m.nodes.resize(3, 3);
  m.nodes << -a, 0, 0, 0, 0, h, a, 0, 0;
  FrameSection s;
  s.A = 1;
  s.Iy = s.Iz = s.J = 1;
  m.sections = {s};
  m.materials = {{"m", EA, 0.3, 0}};
  for (int k : {0, 2}) {
    FrameMember mb;
    mb.i = k;
    mb.j = 1;
    mb.type = MemberType::truss;
    m.members.push_back(mb);
  }
  m.supports = {fix(0, {true, true, true, false, false, false}),
                fix(2, {true, true, true, false, false, false}),
                fix(1, {false, true, false, false, false, false})};
  m.loads = {{1, Vec3(0, 0, -1), Vec3::Zero()}};
  const double l0 = std::sqrt(a * a + h * h);
  Pmax = 0;
  for (int i = 0; i <= 200000; ++i) {
    const double w = h * i / 100000.0;
    const double l = std::sqrt(a * a + (h - w) * (h - w));
    const double P = -2 * EA * (l - l0) / l0 * (h - w) / l;
    if (P > Pmax) {
      Pmax = P;
      if (wmax) *wmax = w;
    }
  }
  return m;
}
}  // namespace

TEST(FrameNonlinear, APathAdvancedStepByStepIsTheWholePathAndEndsWhereItIsStopped) {
  // ArcLengthPath advanced to its end is arc_length (the same points, bit for bit, and the
  // closed-form limit load); ended early it reports where it stopped, as the largest λ reached,
  // with no critical point, and the points before it are the whole path's.
  double Pmax = 0;
  const FrameModel m = von_mises_truss(Pmax);
  const FrameMesh mesh = discretize(m);
  const FrameAssembler asmb(mesh);
  ArcLengthOptions opt;
  opt.initial_lambda = Pmax / 20;
  const ArcLengthResult whole = arc_length(mesh, asmb, opt, reference_state(mesh));
  ArcLengthPath path(mesh, asmb, opt, reference_state(mesh));
  while (path.advance()) {
  }
  const ArcLengthResult stepped = path.finish("unused");
  EXPECT_EQ(stepped.limit_type, LimitType::limit_point);
  EXPECT_NEAR(stepped.lambda_critical / Pmax, 1.0, 1e-4);
  EXPECT_EQ(stepped.lambda_critical, whole.lambda_critical);
  EXPECT_EQ(stepped.stop_reason, "critical point found");
  ASSERT_EQ(stepped.path.size(), whole.path.size());
  for (std::size_t k = 0; k < whole.path.size(); ++k)
    EXPECT_EQ(stepped.path[k].lambda, whole.path[k].lambda);
  // Ended once λ passes half the limit load.
  ArcLengthPath part(mesh, asmb, opt, reference_state(mesh));
  while (part.lambda() <= 0.5 * Pmax && part.advance()) {
  }
  const double reached = part.lambda();
  const ArcLengthResult early = part.finish("stopped by the caller");
  EXPECT_GT(reached, 0.5 * Pmax);
  EXPECT_LT(reached, Pmax);
  EXPECT_EQ(early.limit_type, LimitType::none);
  EXPECT_EQ(early.lambda_critical, reached);
  EXPECT_EQ(early.stop_reason, "stopped by the caller");
  ASSERT_LT(early.path.size(), whole.path.size());
  for (std::size_t k = 0; k < early.path.size(); ++k)
    EXPECT_EQ(early.path[k].lambda, whole.path[k].lambda);
}

// Von Mises two-bar truss: the path's limit point against the closed form.
TEST(FrameClassic, VonMisesTrussLimitLoad) {
  const double h = 1;  // von_mises_truss's rise
  double Pmax = 0, wmax = 0;
  const FrameModel m = von_mises_truss(Pmax, &wmax);
  const FrameMesh mesh = discretize(m);
  const FrameAssembler asmb(mesh);
  ArcLengthOptions opt;
  opt.initial_lambda = Pmax / 20;
  const ArcLengthResult r = arc_length(mesh, asmb, opt, reference_state(mesh));
  EXPECT_EQ(r.limit_type, LimitType::limit_point);
  std::printf("von Mises truss: limit %.6f, closed form %.6f\n", r.lambda_critical, Pmax);
  // The top of the parabola through the last three points (the path's own largest λ was
  // 3.5e-5 below the closed form; the vertex is 7e-7 above it).
  EXPECT_NEAR(r.lambda_critical / Pmax, 1.0, 1e-5);
  EXPECT_NEAR(h - r.critical_state.x(1, 2), wmax, 0.02 * wmax);
}

// Lee's frame (Lee, Manuel & Rossow 1968; Schweizerhof & Wriggers 1986): two members of
// length L = 120, pinned supports, load at L/5 from the knee; first limit load
// P L² / (E I) = 18.55 (the literature's 18.55 at E I / L² = 1). Here E = 720, A = 6, I = 2.
TEST(FrameClassic, LeesFrameLimitLoad) {
  FrameModel m;
  m.nodes.resize(4, 3);
  m.nodes << 0, 0, 0, 0, 0, 120, 24, 0, 120, 120, 0, 120;
  FrameSection s;
  s.A = 6;
  s.Iy = 2;
  s.Iz = 50;  // out of plane: stiff, the benchmark is planar
  s.J = 50;
  m.sections = {s};
  m.materials = {{"m", 720, 0.3, 0}};
  auto add = [&](int i, int j, int n) {
    FrameMember mb;
    mb.i = i;
    mb.j = j;
    mb.elements = n;
    m.members.push_back(mb);
  };
  add(0, 1, 10);
  add(1, 2, 2);
  add(2, 3, 8);
  m.supports = {fix(0, {true, true, true, true, false, true}),
                fix(3, {true, true, true, true, false, true})};
  m.loads = {{2, Vec3(0, 0, -1), Vec3::Zero()}};
  const FrameMesh mesh = discretize(m);
  const FrameAssembler asmb(mesh);
  ArcLengthOptions opt;
  opt.initial_lambda = 1;
  const ArcLengthResult r = arc_length(mesh, asmb, opt, reference_state(mesh));
  EXPECT_EQ(r.limit_type, LimitType::limit_point);
  std::printf("Lee's frame: P L^2/EI = %.4f (%s)\n", r.lambda_critical * 120 * 120 / (720 * 2),
              to_string(r.limit_type));
  EXPECT_NEAR(r.lambda_critical * 120 * 120 / (720 * 2) / 18.55, 1.0, 0.02);
}

// ---------------------------------------------------------------------------------------------
// Grid-shell model: loads and equilibrium.

namespace {
// A quad grid on a shallow paraboloid, 6 × 6 cells of 1 m, boundary supported.
PolyMesh quad_shell(std::vector<int>& supports) {
  PolyMesh m;
  const int n = 6;
  m.V.resize((n + 1) * (n + 1), 3);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = i - n / 2.0, y = j - n / 2.0;
      m.V.row(i * (n + 1) + j) << x, y, 1.5 - 0.08 * (x * x + y * y);
      if (i == 0 || j == 0 || i == n || j == n) supports.push_back(i * (n + 1) + j);
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j;
      m.faces.push_back({a, a + n + 1, a + n + 2, a + 1});
    }
  return m;
}
}  // namespace

TEST(GridshellFrame, NodalLoadsSumToTheTotalWeight) {
  std::vector<int> sup;
  const PolyMesh mesh = quad_shell(sup);
  analysis::GridshellFrameOptions o;
  o.area_load_kN_m2 = 0.5;
  const FrameModel m = analysis::gridshell_frame(mesh, sup, o);
  double area = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) area += polygon_area(mesh, f);
  const double W = total_mass(m) * 9.81;
  EXPECT_NEAR(total_mass(m), 8.44 * total_length(m), 0.001 * total_mass(m));  // 8.44 kg/m
  EXPECT_NEAR(total_load(m).z(), -(W + 500 * area), 1e-9 * W);
  EXPECT_NEAR(total_load(m).head<2>().norm(), 0, 1e-12);
  o.area_load_kN_m2 = 0;
  o.self_weight_at_bars = true;
  EXPECT_NEAR(total_load(analysis::gridshell_frame(mesh, sup, o)).z(), -W, 1e-9 * W);
}

TEST(GridshellFrame, LinearEquilibriumAndPath) {
  std::vector<int> sup;
  const PolyMesh mesh = quad_shell(sup);
  const FrameModel m = analysis::gridshell_frame(mesh, sup, {});
  analysis::FrameAnalysisOptions o;
  const analysis::FrameResult r = analysis::analyze_frame(m, o);
  EXPECT_LT(r.equilibrium_error, 1e-9);
  EXPECT_GT(r.delta_max_m, 0);
  ASSERT_TRUE(r.lambda_linear_buckling.has_value());
  ASSERT_TRUE(r.lambda_nonlinear.has_value());
  EXPECT_GT(*r.lambda_nonlinear, 1);
  EXPECT_NE(r.limit_type, LimitType::none);
  // The non-linear path starts on the linear solution: the first point's displacement per λ
  // matches δ within a few percent.
  ASSERT_GE(r.path.size(), 3u);
  EXPECT_NEAR(r.path[1].displacement / r.path[1].lambda / r.delta_max_m, 1.0, 0.05);
  // λ_δ (displacement span / 100) never exceeds the first critical point's λ.
  ASSERT_TRUE(r.lambda_displacement_limit.has_value());
  EXPECT_LE(*r.lambda_displacement_limit, *r.lambda_nonlinear * (1 + 1e-12));
  EXPECT_GT(*r.lambda_displacement_limit, 0);
  std::printf("quad grid-shell: lambda_LBA %.4f, lambda_nl %.4f (%s), %zu path points\n",
              *r.lambda_linear_buckling, *r.lambda_nonlinear, to_string(r.limit_type),
              r.path.size());
}

// Every joint pinned (joint loads straight into the supports): no displacement, no buckling,
// and no path to follow. The path used to start at λ = span / 2000 / 1e-300 and ran for
// minutes; now it is skipped and says why.
TEST(GridshellFrame, EveryJointPinnedHasNoPathToFollow) {
  std::vector<int> sup;
  const PolyMesh mesh = quad_shell(sup);
  std::vector<int> all(mesh.num_vertices());
  std::iota(all.begin(), all.end(), 0);
  const FrameModel m = analysis::gridshell_frame(mesh, all, {});
  const analysis::FrameResult r = analysis::analyze_frame(m, {});
  EXPECT_EQ(r.delta_max_m, 0.0);
  EXPECT_FALSE(r.lambda_linear_buckling.has_value());
  EXPECT_FALSE(r.lambda_nonlinear.has_value());
  EXPECT_TRUE(r.path.empty());
  EXPECT_EQ(r.nonlinear_stop_reason,
            "no displacement under the load (every loaded joint supported)");
}

TEST(FrameErrors, MechanismZeroLengthBadReferenceBadSection) {
  FrameModel m = straight_member(Vec3(0, 0, 0), Vec3(1, 0, 0), 2, circle_section(0.037), 2.1e11);
  m.loads = {{1, Vec3(0, 0, -1), Vec3::Zero()}};
  m.supports = {fix(0, {true, true, true, false, false, false})};  // free to spin about node 0
  try {
    analysis::analyze_frame(m, {});
    FAIL() << "mechanism not detected";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mechanism"), std::string::npos) << e.what();
  }
  FrameModel z = m;
  z.nodes.row(1) = z.nodes.row(0);
  EXPECT_THROW(discretize(z), Error);
  FrameModel b = m;
  b.members[0].j = 7;
  EXPECT_THROW(discretize(b), Error);
  FrameModel s = m;
  s.sections[0].A = 0;
  EXPECT_THROW(discretize(s), Error);
}

// ---------------------------------------------------------------------------------------------
// The command line.

#include <fstream>

#include <nlohmann/json.hpp>

#include "gridshell/io/files.h"
#include "gridshell/io/mesh_io.h"
#include "test_support.h"

namespace {
const char* kStarDomeJson = R"({
  "nodes": [[0,0,3.2346],
    [4.92125,8.52386,2.4472],[-4.92125,8.52386,2.4472],[-9.8425,0,2.4472],
    [-4.92125,-8.52386,2.4472],[4.92125,-8.52386,2.4472],[9.8425,0,2.4472],
    [0,19.685,0],[-17.04772,9.8425,0],[-17.04772,-9.8425,0],[0,-19.685,0],
    [17.04772,-9.8425,0],[17.04772,9.8425,0]],
  "sections": {"bar": {"A": 0.0155, "Iy": 1, "Iz": 1, "J": 1}},
  "materials": {"dome": {"E": 3.0e7, "nu": 0.3, "density": 0}},
  "members": [
    {"nodes":[0,1],"type":"truss"},{"nodes":[0,2],"type":"truss"},{"nodes":[0,3],"type":"truss"},
    {"nodes":[0,4],"type":"truss"},{"nodes":[0,5],"type":"truss"},{"nodes":[0,6],"type":"truss"},
    {"nodes":[1,2],"type":"truss"},{"nodes":[2,3],"type":"truss"},{"nodes":[3,4],"type":"truss"},
    {"nodes":[4,5],"type":"truss"},{"nodes":[5,6],"type":"truss"},{"nodes":[6,1],"type":"truss"},
    {"nodes":[1,7],"type":"truss"},{"nodes":[1,12],"type":"truss"},{"nodes":[2,7],"type":"truss"},
    {"nodes":[2,8],"type":"truss"},{"nodes":[3,8],"type":"truss"},{"nodes":[3,9],"type":"truss"},
    {"nodes":[4,9],"type":"truss"},{"nodes":[4,10],"type":"truss"},{"nodes":[5,10],"type":"truss"},
    {"nodes":[5,11],"type":"truss"},{"nodes":[6,11],"type":"truss"},{"nodes":[6,12],"type":"truss"}],
  "supports": [{"node":7},{"node":8},{"node":9},{"node":10},{"node":11},{"node":12}],
  "loads": [{"node": 0, "force": [0, 0, -1]}],
  "analysis": {"linear": true, "buckling": true, "nonlinear": true, "nonlinear_static": 100}
})";
}  // namespace

TEST(AnalyzeCli, StarDomeModelJson) {
  const auto dir = test::temp_dir("analyze_star");
  io::write_file_atomic(dir / "dome.json", kStarDomeJson);
  const auto r = test::run_gridshell(fmt::format(
      "analyze '{}' -o '{}' --quiet", (dir / "dome.json").string(), (dir / "out").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto rep = nlohmann::json::parse(io::read_file(dir / "out" / "report.json"));
  const auto& s = rep["structure"];
  EXPECT_EQ(s["limit_type"], "limit point");
  EXPECT_NEAR(s["lambda_nonlinear"].get<double>() / 146.7, 1.0, 0.02);
  EXPECT_NEAR(s["delta_max_m"].get<double>() * 220.46 / 0.20641, 1.0, 0.005);
  EXPECT_NEAR(s["lambda_linear_buckling"].get<double>() / 707, 1.0, 0.03);
  for (const char* f :
       {"nodes.csv", "beams.csv", "path.csv", "nodes_nonlinear.csv", "frame.vtp", "config.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / f)) << f;
  EXPECT_EQ(io::read_file(dir / "out" / "nodes.csv").substr(0, 29),
            "node,x,y,z,ux,uy,uz,support\n0");
}

TEST(AnalyzeCli, BadInputsExitTwo) {
  const auto dir = test::temp_dir("analyze_bad");
  std::string bad = kStarDomeJson;
  bad.replace(bad.find("[0,1]"), 5, "[0,99]");
  io::write_file_atomic(dir / "bad.json", bad);
  auto r = test::run_gridshell(
      fmt::format("analyze '{}' -o '{}'", (dir / "bad.json").string(), (dir / "o").string()));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("node 99"), std::string::npos) << r.err;
  std::string mech = kStarDomeJson;
  mech.replace(mech.find("{\"node\":7},"), 11, "");
  mech.replace(mech.find("{\"node\":8},"), 11, "");
  mech.replace(mech.find("{\"node\":9},"), 11, "");
  mech.replace(mech.find("{\"node\":10},"), 12, "");
  io::write_file_atomic(dir / "mech.json", mech);
  r = test::run_gridshell(
      fmt::format("analyze '{}' -o '{}'", (dir / "mech.json").string(), (dir / "o").string()));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("mechanism"), std::string::npos) << r.err;
  r = test::run_gridshell(fmt::format("analyze '{}' --elements 0 -o '{}'",
                                      (dir / "bad.json").string(), (dir / "o").string()));
  EXPECT_EQ(r.status, 2);
  r = test::run_gridshell(fmt::format("analyze '{}' --displacement-limit nan -o '{}'",
                                      (dir / "bad.json").string(), (dir / "o").string()));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--displacement-limit"), std::string::npos) << r.err;
}

TEST(AnalyzeCli, ObjSupportsCommentIsHonoured) {
  std::vector<int> sup;
  const PolyMesh mesh = quad_shell(sup);
  const std::vector<int> few = {0, 6, 42, 48, 3, 45};  // corners and two mid-edge joints
  const auto dir = test::temp_dir("analyze_obj");
  io::write_obj(dir / "g.obj", mesh, few);
  const auto r = test::run_gridshell(fmt::format("analyze '{}' --analyze linear -o '{}' --quiet",
                                                 (dir / "g.obj").string(), (dir / "out").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto rep = nlohmann::json::parse(io::read_file(dir / "out" / "report.json"));
  EXPECT_EQ(rep["structure"]["supports"], few.size());
  EXPECT_TRUE(rep["structure"]["lambda_nonlinear"].is_null());
  // Fewer supports than the whole boundary: larger deflection than the boundary-supported run.
  const FrameModel all = analysis::gridshell_frame(mesh, sup, {});
  analysis::FrameAnalysisOptions o;
  o.buckling = o.nonlinear = false;
  EXPECT_GT(rep["structure"]["delta_max_m"].get<double>(),
            analysis::analyze_frame(all, o).delta_max_m);
}

TEST(GridshellFrame, ImperfectionFollowsTheFirstBucklingMode) {
  std::vector<int> sup;
  const PolyMesh mesh = quad_shell(sup);
  const FrameModel m = analysis::gridshell_frame(mesh, sup, {});
  FrameMesh fm = discretize(m);
  const FrameAssembler asmb(fm);
  const LinearResult lin = linear_static(fm, asmb);
  const BucklingResult b = linear_buckling(fm, asmb, lin);
  ASSERT_FALSE(b.modes.empty());
  // The mode solves the buckling problem K φ = λ (−K_G) φ for its λ (matrices of the perfect
  // geometry: the assembler reads the mesh, so they are formed before it is perturbed).
  const Eigen::VectorXd& phi = b.modes[0];
  const SpMat K = asmb.linear_stiffness(), KG = asmb.geometric_stiffness(lin.axial);
  const Eigen::VectorXd Kphi = K * phi;
  EXPECT_LT((Kphi + b.lambdas[0] * (KG * phi)).norm(), 1e-6 * Kphi.norm());
  const Points X0 = fm.X;
  analysis::perturb_geometry(fm, b.modes[0], 0.02);
  EXPECT_NEAR((fm.X - X0).rowwise().norm().maxCoeff(), 0.02, 1e-12);  // modes: max |u| = 1
  // The perturbation is the mode itself, dof by dof.
  for (int v = 0; v < static_cast<int>(X0.rows()); ++v)
    for (int c = 0; c < 3; ++c) {
      const int eq = fm.dof[v][c];
      EXPECT_NEAR(fm.X(v, c) - X0(v, c), eq >= 0 ? 0.02 * phi(eq) : 0.0, 1e-14);
    }
  // The imperfect shell reaches its critical point no later than the perfect one (within the
  // bracket tolerance), and both are finite.
  analysis::FrameAnalysisOptions o;
  const analysis::FrameResult perfect = analysis::analyze_frame(m, o);
  o.imperfection = true;
  const analysis::FrameResult imperfect = analysis::analyze_frame(m, o);
  ASSERT_TRUE(perfect.lambda_nonlinear && imperfect.lambda_nonlinear);
  EXPECT_LE(*imperfect.lambda_nonlinear, *perfect.lambda_nonlinear * 1.001);
  EXPECT_GT(*imperfect.lambda_nonlinear, 0.3 * *perfect.lambda_nonlinear);
}

TEST(FrameEnergy, CantileverStrainEnergyIsHalfTheWorkOfTheLoad) {
  // Tip load P on a cantilever: U = P² L³ / (6 EI) (bending only; the axial part vanishes), the
  // same as ½ P δ. Per element, the energy grows towards the clamp as M² = P²(L − x)² does:
  // element k of n holds ((n−k)³ − (n−k−1)³) / n³ of the total.
  const double L = 2, EI = 1e4, P = 10;
  const int n = 4;
  FrameModel m = cantilever(L, n, EI);
  m.loads = {{1, Vec3(0, 0, -P), Vec3::Zero()}};
  const FrameMesh mesh = discretize(m);
  const FrameAssembler asmb(mesh);
  const LinearResult lin = linear_static(mesh, asmb);
  const std::vector<double> e = element_strain_energy(mesh, asmb, lin.u);
  ASSERT_EQ(static_cast<int>(e.size()), n);
  double total = 0;
  for (double x : e) total += x;
  const double exact = P * P * L * L * L / (6 * EI);
  EXPECT_NEAR(total / exact, 1.0, 1e-9);
  EXPECT_NEAR(total, 0.5 * mesh.load.dot(lin.u), 1e-12 * exact);
  for (int k = 0; k < n; ++k) {  // the element next to the clamp comes first (node 0 → 1)
    const double share = (std::pow(n - k, 3) - std::pow(n - k - 1, 3)) / std::pow(n, 3);
    EXPECT_NEAR(e[k] / exact, share, 1e-9) << k;
  }
  // Through analyze_frame: per member (one member here), and the buckling mode's energies are
  // normalised to add up to 1.
  m.loads = {{1, Vec3(-P, 0, 0), Vec3::Zero()}};
  const auto res = analysis::analyze_frame(m, {.linear = true, .buckling = true, .nonlinear = false});
  ASSERT_EQ(res.strain_energy.size(), 1u);
  EXPECT_NEAR(res.strain_energy[0], 0.5 * P * P * L / (m.sections[0].A * 1e6), 1e-9 * res.strain_energy[0]);
  ASSERT_EQ(res.mode_energy.size(), 1u);
  EXPECT_NEAR(res.mode_energy[0], 1.0, 1e-12);
}

// The assembler builds the sparsity pattern node block by node block; it must hold exactly the
// entries of the element matrices (each element's free dofs × free dofs, a truss's translations
// only) and every diagonal. A mixed model: beams split in two, trusses, a beam and a truss
// between the same two nodes, a node reached by trusses only, partial supports.
TEST(FrameAssembly, PatternIsTheUnionOfTheElementEntries) {
  FrameModel m;
  m.nodes.resize(5, 3);
  m.nodes << 0, 0, 0, 2, 0, 0.5, 4, 0, 0, 2, 2, 0.3, 2, -2, 1;
  m.sections = {circle_section(0.05)};
  m.materials = {{"steel", 210e9, 0.3, 7850}};
  const auto member = [](int i, int j, MemberType type, int elements) {
    FrameMember mb;
    mb.i = i;
    mb.j = j;
    mb.type = type;
    mb.elements = elements;
    return mb;
  };
  m.members = {member(0, 1, MemberType::beam, 2), member(1, 2, MemberType::beam, 1),
               member(1, 3, MemberType::beam, 2), member(1, 3, MemberType::truss, 1),
               member(0, 4, MemberType::truss, 1), member(2, 4, MemberType::truss, 1),
               member(3, 2, MemberType::truss, 1), member(3, 4, MemberType::truss, 1)};
  m.supports = {fix(0, {true, true, true, false, false, false}),
                fix(2, {true, true, true, true, false, false})};
  m.loads = {{1, Vec3(0, 0, -1e3), Vec3::Zero()}};
  const FrameMesh mesh = discretize(m);
  std::vector<Eigen::Triplet<double>> entries;
  for (const auto& e : mesh.elements)
    for (int a = 0; a < 12; ++a)
      for (int b = 0; b < 12; ++b) {
        if (e.truss && (a % 6 >= 3 || b % 6 >= 3)) continue;
        const int r = mesh.dof[a < 6 ? e.i : e.j][a % 6], c = mesh.dof[b < 6 ? e.i : e.j][b % 6];
        if (r >= 0 && c >= 0) entries.emplace_back(r, c, 1.0);
      }
  for (int d = 0; d < mesh.num_dofs; ++d) entries.emplace_back(d, d, 1.0);
  SpMat expected(mesh.num_dofs, mesh.num_dofs);
  expected.setFromTriplets(entries.begin(), entries.end());
  const FrameAssembler asmb(mesh);
  const SpMat& pattern = asmb.pattern();
  ASSERT_EQ(pattern.nonZeros(), expected.nonZeros());
  for (int c = 0; c <= mesh.num_dofs; ++c)
    ASSERT_EQ(pattern.outerIndexPtr()[c], expected.outerIndexPtr()[c]) << "column " << c;
  for (int k = 0; k < expected.nonZeros(); ++k)
    ASSERT_EQ(pattern.innerIndexPtr()[k], expected.innerIndexPtr()[k]) << "entry " << k;
  // The rotations of node 4 (trusses only) do not exist; node 3's do (a beam reaches it).
  EXPECT_EQ(mesh.dof[4][3], -1);
  EXPECT_GE(mesh.dof[3][3], 0);
  // And the stiffness assembled on it is the sum of the element matrices: K u = f holds for the
  // linear solution (the residual of the solve, relative to the load).
  const LinearResult lin = linear_static(mesh, asmb);
  const SpMat K = asmb.linear_stiffness();
  EXPECT_LT((K * lin.u - mesh.load).norm(), 1e-9 * mesh.load.norm());
}

TEST(LimitType, ReportWordsRoundTripAndAnOtherWordIsAnError) {
  // report.json keeps the CONTRACT's words: "limit point" | "bifurcation" | "none".
  for (const LimitType t : {LimitType::limit_point, LimitType::bifurcation, LimitType::none})
    EXPECT_EQ(parse_limit_type(to_string(t)), t);
  EXPECT_STREQ(to_string(LimitType::limit_point), "limit point");
  EXPECT_STREQ(to_string(LimitType::bifurcation), "bifurcation");
  EXPECT_STREQ(to_string(LimitType::none), "none");
  EXPECT_THROW(parse_limit_type("limit_point"), gridshell::Error);
}
