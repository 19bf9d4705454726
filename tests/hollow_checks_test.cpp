// EN 1993-1-1 member checks of hollow sections (checks/hollow_checks.h): cantilevers of CHS and
// RHS, hot-finished and cold-formed, under axial force, bending about each axis, shear and
// torsion, analysed by the frame solver and checked against hand calculations written here from
// the code's formulas. The section properties of the hand calculations are integrated
// numerically over the cross-section (a fine grid of points), not taken from sections.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>

#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/checks/hollow_checks.h"
#include "gridshell/checks/member_checks.h"
#include "gridshell/core/error.h"
#include "gridshell/fem/frame_solver.h"
#include "gridshell/io/frame_model_json.h"
#include "test_support.h"

using namespace gridshell;
using namespace gridshell::fem;

namespace {
constexpr double kPi = std::numbers::pi, kE = 210e9, kFy = 355e6;

/// Numerically integrated properties of a region given by `inside(y, z)` in [−B/2, B/2] ×
/// [−H/2, H/2] (n × n midpoints).
struct Hand {
  double A = 0, Iy = 0, Iz = 0, Wply = 0, Wplz = 0;
};
Hand integrate(double B, double H, const std::function<bool(double, double)>& inside) {
  const int n = 3000;
  const double dy = B / n, dz = H / n, dA = dy * dz;
  Hand h;
  for (int a = 0; a < n; ++a) {
    const double y = -B / 2 + (a + 0.5) * dy;
    for (int c = 0; c < n; ++c) {
      const double z = -H / 2 + (c + 0.5) * dz;
      if (!inside(y, z)) continue;
      h.A += dA;
      h.Iy += z * z * dA;
      h.Iz += y * y * dA;
      h.Wply += std::abs(z) * dA;
      h.Wplz += std::abs(y) * dA;
    }
  }
  return h;
}
bool in_rounded(double B, double H, double r, double y, double z) {
  y = std::abs(y), z = std::abs(z);
  if (y > B / 2 || z > H / 2) return false;
  const double cy = B / 2 - r, cz = H / 2 - r;
  if (y <= cy || z <= cz) return true;
  return (y - cy) * (y - cy) + (z - cz) * (z - cz) <= r * r;
}
/// RHS of height h (along z), width b, wall t, corner radii ro, ri (EN 10210-2: 1.5t, t;
/// EN 10219-2, t ≤ 6 mm: 2t, t).
Hand hand_rhs(double h, double b, double t, double ro, double ri) {
  return integrate(b, h, [&](double y, double z) {
    return in_rounded(b, h, ro, y, z) && !in_rounded(b - 2 * t, h - 2 * t, ri, y, z);
  });
}
Hand hand_chs(double d, double t) {
  return integrate(d, d, [&](double y, double z) {
    const double r2 = y * y + z * z;
    return r2 <= d * d / 4 && r2 > (d / 2 - t) * (d / 2 - t);
  });
}

/// χ of EN 1993-1-1 (6.49).
double chi(double lambda_bar, double alpha) {
  if (lambda_bar <= 0.2) return 1;
  const double phi = 0.5 * (1 + alpha * (lambda_bar - 0.2) + lambda_bar * lambda_bar);
  return std::min(1.0, 1 / (phi + std::sqrt(phi * phi - lambda_bar * lambda_bar)));
}

/// λ at which f(λ) (increasing) reaches 1, by bisection; the utilisation is 1/λ.
double one_over_lambda(const std::function<double(double)>& f, double hi) {
  double lo = 0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) < 1 ? lo : hi) = mid;
  }
  return 1 / hi;
}

/// A horizontal cantilever along +x (local y = global y, local z = global z), clamped at node 0,
/// loaded at the tip by F and M; 4 elements.
FrameModel cantilever(const sections::Section& s, double L, const Vec3& F, const Vec3& M) {
  FrameModel m;
  m.nodes.resize(2, 3);
  m.nodes << 1.0, 2.0, 3.0, 1.0 + L, 2.0, 3.0;
  m.sections = {profile_section(s)};
  m.materials = {{"steel", kE, 0.3, 7850}};
  FrameMember mb;
  mb.i = 0, mb.j = 1, mb.elements = 4;
  m.members = {mb};
  m.supports = {{0, {true, true, true, true, true, true}}};
  m.loads = {{1, F, M}};
  return m;
}

checks::MemberChecks checked(const FrameModel& m, double length_factor = 1) {
  const FrameMesh mesh = discretize(m);
  const FrameAssembler assembler(mesh);
  const LinearResult lin = linear_static(mesh, assembler);
  checks::MemberCheckOptions o;
  o.fy = kFy;
  o.buckling_length_factor = length_factor;
  return checks::check_members(m, member_forces(mesh, element_section_forces(mesh, assembler, lin.u)), o);
}

}  // namespace

// CHS 88.9x4.0 hot-finished (class 1: d/t = 22 ≤ 50ε²), cantilever 2 m (L_cr = 2L, sway: Cm =
// 0.9) under compression and tip loads along y and z: (6.41) with M_N = M_pl(1 − n^1.7),
// α = β = 2, and (6.61)/(6.62) with curve a.
TEST(HollowChecks, ChsCantileverUnderCompressionAndBiaxialBending) {
  const double d = 0.0889, t = 0.004, L = 2.0, N = 60e3, Fy = 1.2e3, Fz = 2.0e3;
  const checks::MemberChecks c =
      checked(cantilever(sections::chs(d, t), L, Vec3(-N, Fy, Fz), Vec3::Zero()), 2.0);
  const Hand h = hand_chs(d, t);
  const double My = Fz * L, Mz = Fy * L, M = std::hypot(My, Mz);
  const double Npl = h.A * kFy, Mpl = h.Wply * kFy;
  const double u_cs = one_over_lambda(
      [&](double l) {
        const double n = l * N / Npl;
        return n >= 1 ? 2.0 : std::pow(l * M / (Mpl * (1 - std::pow(n, 1.7))), 2);
      },
      std::min(Npl / N, Mpl / M));
  EXPECT_EQ(c.members[0].section_class, 1);
  EXPECT_NEAR(c.members[0].section, u_cs, 0.005 * u_cs);
  EXPECT_STREQ(c.members[0].section_governing, "6.2.9.1 N+M (6.41)");
  // Buckling: L_cr = 4 m, both axes alike.
  const double Lcr = 2 * L, lam = std::sqrt(h.A * kFy / (kPi * kPi * kE * h.Iy / (Lcr * Lcr)));
  const double x = chi(lam, 0.21), n = N / (x * Npl);
  const double k = 0.9 * std::min(1 + (lam - 0.2) * n, 1 + 0.8 * n);
  const double u61 = n + k * My / Mpl + 0.6 * k * Mz / Mpl;
  const double u62 = n + 0.6 * k * My / Mpl + k * Mz / Mpl;
  EXPECT_NEAR(c.members[0].buckling, std::max(u61, u62), 0.005 * std::max(u61, u62));
  EXPECT_STREQ(c.members[0].buckling_governing, "6.3.3 (6.61)");  // My > Mz
  EXPECT_NEAR(c.members[0].chi, x, 1e-3 * x);
}

// RHS 120x60x5 cold-formed (ro = 2t, ri = t; class 1: c/t = 21), cantilever 1 m along x with
// its height along z: (6.39)/(6.40)/(6.41) with α = β = 1.66/(1 − 1.13n²); curve c.
TEST(HollowChecks, ColdRhsCantileverUnderCompressionAndBiaxialBending) {
  const double hh = 0.120, b = 0.060, t = 0.005, L = 1.0, N = 80e3, Fy = 1.0e3, Fz = 3.0e3;
  const checks::MemberChecks c = checked(
      cantilever(sections::rhs(hh, b, t, sections::Process::cold), L, Vec3(-N, Fy, Fz),
                 Vec3::Zero()),
      2.0);
  const Hand h = hand_rhs(hh, b, t, 2 * t, t);
  const double My = Fz * L, Mz = Fy * L;
  const double Npl = h.A * kFy, Mply = h.Wply * kFy, Mplz = h.Wplz * kFy;
  const double aw = std::min(0.5, (h.A - 2 * b * t) / h.A), af = std::min(0.5, (h.A - 2 * hh * t) / h.A);
  const double u_cs = one_over_lambda(
      [&](double l) {
        const double n = l * N / Npl;
        if (n >= 1) return 2.0;
        const double MNy = std::min(Mply, Mply * (1 - n) / (1 - 0.5 * aw));
        const double MNz = std::min(Mplz, Mplz * (1 - n) / (1 - 0.5 * af));
        const double a = std::min(6.0, 1.66 / (1 - 1.13 * n * n));
        return std::pow(l * My / MNy, a) + std::pow(l * Mz / MNz, a);
      },
      std::min({Npl / N, Mply / My, Mplz / Mz}));
  EXPECT_EQ(c.members[0].section_class, 1);
  EXPECT_NEAR(c.members[0].section, u_cs, 0.005 * u_cs);
  const double Lcr = 2 * L;
  const double lam_y = std::sqrt(h.A * kFy / (kPi * kPi * kE * h.Iy / (Lcr * Lcr)));
  const double lam_z = std::sqrt(h.A * kFy / (kPi * kPi * kE * h.Iz / (Lcr * Lcr)));
  const double ny = N / (chi(lam_y, 0.49) * Npl), nz = N / (chi(lam_z, 0.49) * Npl);
  const double kyy = 0.9 * std::min(1 + (lam_y - 0.2) * ny, 1 + 0.8 * ny);
  const double kzz = 0.9 * std::min(1 + (lam_z - 0.2) * nz, 1 + 0.8 * nz);
  const double u61 = ny + kyy * My / Mply + 0.6 * kzz * Mz / Mplz;
  const double u62 = nz + 0.6 * kyy * My / Mply + kzz * Mz / Mplz;
  EXPECT_GT(u62, u61);  // the weak axis buckles
  EXPECT_NEAR(c.members[0].buckling, u62, 0.005 * u62);
  EXPECT_STREQ(c.members[0].buckling_governing, "6.3.3 (6.62)");
}

// SHS 100x100x5 hot-finished: torsion alone (6.2.7), shear reduced by torsion (6.28), and the
// moment resistance reduced by shear (6.2.8, ρ = (2V/V_pl,T,Rd − 1)²).
TEST(HollowChecks, HotShsUnderTorsionShearAndBending) {
  const double a = 0.100, t = 0.005, ro = 1.5 * t, ri = t;
  const sections::Section s = sections::rhs(a, a, t);
  const Hand h = hand_rhs(a, a, t, ro, ri);
  const double Rc = (ro + ri) / 2, Am = (a - t) * (a - t) - Rc * Rc * (4 - kPi);
  const double tau_rd = kFy / std::sqrt(3.0);
  const double Vpl = h.A * a / (2 * a) * tau_rd;  // Av = A h / (b + h)
  {  // torsion only
    const double T = 12e3;
    const checks::MemberChecks c = checked(cantilever(s, 1.0, Vec3::Zero(), Vec3(T, 0, 0)));
    const double u = T / (2 * Am * t) / tau_rd;
    EXPECT_NEAR(c.members[0].section, u, 0.005 * u);
    EXPECT_STREQ(c.members[0].section_governing, "6.2.7 torsion");
    EXPECT_EQ(c.members[0].buckling, 0.0);
  }
  {  // torsion and shear: V below half the resistance, shear governs
    const double T = 6e3, V = 60e3, L = 0.1;
    const checks::MemberChecks c = checked(cantilever(s, L, Vec3(0, 0, V), Vec3(T, 0, 0)));
    const double uT = T / (2 * Am * t) / tau_rd, u = V / ((1 - uT) * Vpl);
    EXPECT_LT(u, 0.5);
    EXPECT_NEAR(c.members[0].section, u, 0.005 * u);
    EXPECT_STREQ(c.members[0].section_governing, "6.2.6 shear");
  }
  {  // torsion, high shear and bending: the reduced moment resistance governs
    const double T = 6e3, V = 90e3, L = 0.25;
    const checks::MemberChecks c = checked(cantilever(s, L, Vec3(0, 0, V), Vec3(T, 0, 0)));
    const double uT = T / (2 * Am * t) / tau_rd, VplT = (1 - uT) * Vpl;
    const double rho = std::pow(2 * V / VplT - 1, 2);
    const double u = V * L / (h.Wply * kFy * (1 - rho));
    EXPECT_GT(V / VplT, 0.5);
    EXPECT_NEAR(c.members[0].section, u, 0.005 * u);
    EXPECT_STREQ(c.members[0].section_governing, "6.2.9.1 N+M (6.41)");
  }
}

// CHS 323.9x6.3 hot (d/t = 51: class 3 in S355, 46.3 < 51 ≤ 59.6): (6.42) and the class-3 k
// factors; a cantilever with L_cr = L has ψ = 0 at its ends (tip moment 0): Cm = 0.6.
TEST(HollowChecks, Class3ChsUsesElasticResistanceAndClass3Factors) {
  const double d = 0.3239, t = 0.0063, L = 6.0, N = 500e3, Fz = 20e3;
  const checks::MemberChecks c =
      checked(cantilever(sections::chs(d, t), L, Vec3(-N, 0, Fz), Vec3::Zero()));
  const Hand h = hand_chs(d, t);
  const double Wel = h.Iy / (d / 2), My = Fz * L;
  EXPECT_EQ(c.members[0].section_class, 3);
  const double u_cs = (N / h.A + My / Wel) / kFy;
  EXPECT_NEAR(c.members[0].section, u_cs, 0.005 * u_cs);
  EXPECT_STREQ(c.members[0].section_governing, "6.2.9.2 N+M (6.42)");
  const double lam = std::sqrt(h.A * kFy / (kPi * kPi * kE * h.Iy / (L * L)));
  const double n = N / (chi(lam, 0.21) * h.A * kFy);
  const double kyy = 0.6 * std::min(1 + 0.6 * lam * n, 1 + 0.6 * n);
  const double u61 = n + kyy * My / (Wel * kFy);
  EXPECT_NEAR(c.members[0].buckling, u61, 0.005 * u61);
}

/// A column along +x, pinned at both ends (node 0: translations and twist, node 1: transverse
/// translations), compressed by N at node 1, with nodal moments Mi at node 0 and Mj at node 1
/// (global = local axes: y, z); 4 elements.
FrameModel column(const sections::Section& s, double L, double N, const Vec3& Mi, const Vec3& Mj) {
  FrameModel m;
  m.nodes.resize(2, 3);
  m.nodes << 0.0, 0.0, 0.0, L, 0.0, 0.0;
  m.sections = {profile_section(s)};
  m.materials = {{"steel", kE, 0.3, 7850}};
  FrameMember mb;
  mb.i = 0, mb.j = 1, mb.elements = 4;
  m.members = {mb};
  m.supports = {{0, {true, true, true, true, false, false}}, {1, {false, true, true, false, false, false}}};
  m.loads = {{0, Vec3::Zero(), Mi}, {1, Vec3(-N, 0, 0), Mj}};
  return m;
}

// RHS 150x100x6.3 hot (class 1), pinned column 3 m (L_cr = L): equal-sense end moments about y
// bend it in double curvature, ψ = −0.5 → C_my = 0.4; opposite moments about z bend it
// uniformly, ψ = 1 → C_mz = 1 (Table B.3). Curve a.
TEST(HollowChecks, HotRhsColumnTakesCmFromItsEndMoments) {
  const double hh = 0.150, b = 0.100, t = 0.0063, L = 3.0, N = 300e3;
  const double My = 15e3, Mz = 3e3;
  const checks::MemberChecks c = checked(
      column(sections::rhs(hh, b, t), L, N, Vec3(0, My, Mz), Vec3(0, 0.5 * My, -Mz)));
  const Hand h = hand_rhs(hh, b, t, 1.5 * t, t);
  const double Npl = h.A * kFy, Mply = h.Wply * kFy, Mplz = h.Wplz * kFy;
  const double lam_y = std::sqrt(h.A * kFy / (kPi * kPi * kE * h.Iy / (L * L)));
  const double lam_z = std::sqrt(h.A * kFy / (kPi * kPi * kE * h.Iz / (L * L)));
  const double ny = N / (chi(lam_y, 0.21) * Npl), nz = N / (chi(lam_z, 0.21) * Npl);
  const double kyy = 0.4 * std::min(1 + (lam_y - 0.2) * ny, 1 + 0.8 * ny);
  const double kzz = 1.0 * std::min(1 + (lam_z - 0.2) * nz, 1 + 0.8 * nz);
  const double u61 = ny + kyy * My / Mply + 0.6 * kzz * Mz / Mplz;
  const double u62 = nz + 0.6 * kyy * My / Mply + kzz * Mz / Mplz;
  EXPECT_EQ(c.members[0].section_class, 1);
  EXPECT_NEAR(c.members[0].buckling, std::max(u61, u62), 0.005 * std::max(u61, u62));
  // The cross-section at the end with both largest moments (node 0).
  const double aw = std::min(0.5, (h.A - 2 * b * t) / h.A), af = std::min(0.5, (h.A - 2 * hh * t) / h.A);
  const double u_cs = one_over_lambda(
      [&](double l) {
        const double n = l * N / Npl;
        if (n >= 1) return 2.0;
        const double a = std::min(6.0, 1.66 / (1 - 1.13 * n * n));
        return std::pow(l * My / std::min(Mply, Mply * (1 - n) / (1 - 0.5 * aw)), a) +
               std::pow(l * Mz / std::min(Mplz, Mplz * (1 - n) / (1 - 0.5 * af)), a);
      },
      std::min({Npl / N, Mply / My, Mplz / Mz}));
  EXPECT_NEAR(c.members[0].section, u_cs, 0.005 * u_cs);
}

// CHS 114.3x5.0 cold (class 1), pinned column 4 m under N and a uniform moment about y
// (ψ = 1, C_m = 1): (6.61) with curve c.
TEST(HollowChecks, ColdChsColumnUnderUniformMoment) {
  const double d = 0.1143, t = 0.005, L = 4.0, N = 150e3, M = 5e3;
  const checks::MemberChecks c = checked(column(sections::chs(d, t, sections::Process::cold), L, N,
                                                Vec3(0, M, 0), Vec3(0, -M, 0)));
  const Hand h = hand_chs(d, t);
  const double Npl = h.A * kFy, Mpl = h.Wply * kFy;
  const double lam = std::sqrt(h.A * kFy / (kPi * kPi * kE * h.Iy / (L * L)));
  const double x = chi(lam, 0.49), n = N / (x * Npl);
  const double k = std::min(1 + (lam - 0.2) * n, 1 + 0.8 * n);
  const double u61 = n + k * M / Mpl;
  EXPECT_NEAR(c.members[0].buckling, u61, 0.005 * u61);
  EXPECT_STREQ(c.members[0].buckling_governing, "6.3.3 (6.61)");
  EXPECT_NEAR(c.members[0].chi, x, 1e-3 * x);
}

TEST(HollowChecks, Class4FailsWithAReason) {
  // CHS 508x6.3 in S355: d/t = 80.6 > 90ε² = 59.6.
  const checks::MemberChecks c =
      checked(cantilever(sections::chs(0.508, 0.0063), 3.0, Vec3(-1e3, 0, 0), Vec3::Zero()));
  EXPECT_EQ(c.members[0].section_class, 4);
  EXPECT_GT(c.members[0].section, 1.0);
  EXPECT_NEAR(c.members[0].section, (0.508 / 0.0063) / (90 * 235.0 / 355), 1e-9);
  EXPECT_STREQ(c.members[0].section_governing, "5.5 class 4 (not checked)");
  EXPECT_GT(c.members[0].buckling, 1.0);
}

TEST(HollowChecks, SolidBarKeepsItsLinearCheck) {
  const checks::MemberChecks c =
      checked(cantilever(sections::bar(0.037), 2.0, Vec3(-5e3, 0, 100), Vec3::Zero()));
  const double A = kPi * 0.037 * 0.037 / 4, W = kPi * std::pow(0.037, 3) / 32;
  const double u = 5e3 / (A * kFy) + 200 / (W * kFy);
  EXPECT_NEAR(c.members[0].section, u, 1e-3 * u);
  EXPECT_EQ(c.members[0].section_class, 0);
  EXPECT_STREQ(c.members[0].section_governing, "6.2.1(7) N+M");
}

// The member's own `up` turns the section: an RHS whose height is along global y (up = y) bends
// about its strong axis under a load along y; its tip deflection is F L³ / (3 E I_strong).
TEST(HollowChecks, MemberUpTurnsTheSection) {
  const sections::Section s = sections::rhs(0.12, 0.06, 0.004);
  const double L = 2.0, F = 1e3;
  FrameModel m = cantilever(s, L, Vec3(0, F, 0), Vec3::Zero());
  m.members[0].up = Vec3(0.3, 1, 0);  // made orthogonal to the member: y
  const FrameMesh mesh = discretize(m);
  const FrameAssembler assembler(mesh);
  const LinearResult lin = linear_static(mesh, assembler);
  const double Istrong = m.sections[0].Iy;
  EXPECT_NEAR(lin.displacement(1, 1), F * L * L * L / (3 * kE * Istrong), 1e-6 * F * L * L * L / (3 * kE * Istrong));
  const auto f = member_forces(mesh, element_section_forces(mesh, assembler, lin.u));
  EXPECT_NEAR(f[0].My, F * L, 1e-6 * F * L);  // strong-axis moment
  EXPECT_LT(f[0].Mz, 1e-6 * F * L);
  EXPECT_NEAR(f[0].Vz, F, 1e-6 * F);
}

// gridshell_frame stands an RHS along the surface normal: on a flat roof every member's local z
// is vertical.
TEST(HollowChecks, GridshellRhsStandsAlongTheNormal) {
  PolyMesh mesh;
  mesh.V.resize(6, 3);
  mesh.V << 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0;
  mesh.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}};
  analysis::GridshellFrameOptions o;
  o.section = "RHS 120x60x4";
  const FrameModel m = analysis::gridshell_frame(mesh, {0, 2, 3, 5}, o);
  EXPECT_EQ(m.sections[0].name, "RHS 120x60x4.0");
  for (const FrameMember& mb : m.members) EXPECT_NEAR(std::abs(mb.up.z()), 1.0, 1e-12);
  o.section = "bar 37";
  for (const FrameMember& mb : analysis::gridshell_frame(mesh, {0, 2, 3, 5}, o).members)
    EXPECT_EQ(mb.up, Vec3::Zero());
  o.section = "CHS 10x20";
  EXPECT_THROW(analysis::gridshell_frame(mesh, {0, 2, 3, 5}, o), Error);
}

TEST(HollowChecks, ModelJsonReadsAndWritesShapedSections) {
  const std::string text = R"({
    "nodes": [[0,0,0],[2,0,0]],
    "sections": {"c": {"shape": "chs", "d": 0.0889, "t": 0.004, "process": "cold"},
                 "r": {"shape": "rhs", "h": 0.12, "b": 0.06, "t": 0.004}},
    "materials": {"steel": {"E": 2.1e11}},
    "members": [{"nodes": [0, 1], "section": "r", "up": [0, 1, 0]}],
    "supports": [{"node": 0, "fix": ["ux","uy","uz","rx","ry","rz"]}],
    "loads": [{"node": 1, "force": [0, 0, -1000]}]})";
  const io::FrameModelFile f = io::parse_frame_model(text, "model.json");
  ASSERT_EQ(f.model.sections.size(), 2u);
  for (const FrameSection& s : f.model.sections) {
    ASSERT_TRUE(s.profile.has_value());
    const nlohmann::json j = io::section_to_json(s);
    const sections::Section& p = *s.profile;
    EXPECT_EQ(j["shape"], sections::to_string(p.shape));
    EXPECT_EQ(j["process"], sections::to_string(p.process));
  }
  EXPECT_EQ(f.model.members[0].up, Vec3(0, 1, 0));
  EXPECT_EQ(io::section_to_json(circle_section(0.037))["shape"], "circle");
  FrameSection generic;
  generic.A = 1, generic.Iy = 2, generic.Iz = 3, generic.J = 4;
  EXPECT_EQ(io::section_to_json(generic)["J"], 4);
  EXPECT_THROW(io::parse_frame_model(R"({"nodes": [[0,0,0],[1,0,0]],
    "sections": {"c": {"shape": "chs", "d": 0.01, "t": 0.02}}, "materials": {"s": {"E": 1}},
    "members": [{"nodes": [0, 1]}]})", "m.json"), Error);
}

TEST(HollowChecks, CommandLineRefusesBadSections) {
  for (const char* bad : {"CHS 10x20", "IPE 200", "CHS -88.9x4", "RHS 0x60x4"}) {
    const test::RunResult r = test::run_gridshell(
        std::string("baseline builtin:dome --kind quad --length 400 --section '") + bad + "'");
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find("--section"), std::string::npos) << r.err;
  }
}

// A grid-shell of RHS members end to end: report.json names the section and the governing
// clauses, beams.csv carries the designation, the mass is the RHS's.
TEST(HollowChecks, BaselineWithAnRhsReportsItsSection) {
  const auto d = test::temp_dir("hollow_baseline");
  const test::RunResult r = test::run_gridshell(
      "baseline builtin:dome --kind quad --length 400 --analyze linear --quiet --section "
      "'RHS 120x60x4 cold' -o " + d.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto report = nlohmann::json::parse(test::slurp(d / "report.json"));
  const auto& st = report["structure"];
  EXPECT_EQ(st["section"]["designation"], "RHS 120x60x4.0 cold");
  EXPECT_EQ(st["section"]["standard"], true);
  EXPECT_TRUE(st["utilisation_check"].is_string());
  const double A = sections::properties(sections::rhs(0.12, 0.06, 0.004, sections::Process::cold)).A;
  EXPECT_NEAR(st["mass_kg"].get<double>(), 7850 * A * st["total_length_m"].get<double>(),
              1e-9 * st["mass_kg"].get<double>());
  const std::string beams = test::slurp(d / "beams.csv");
  EXPECT_NE(beams.find(",section,governing\n"), std::string::npos);
  EXPECT_NE(beams.find("RHS 120x60x4.0 cold"), std::string::npos);
}
