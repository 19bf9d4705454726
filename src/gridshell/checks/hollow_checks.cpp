#include "gridshell/checks/hollow_checks.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gridshell/checks/member_checks.h"

namespace gridshell::checks {

namespace {

using sections::Section;
using sections::SectionProperties;
using sections::Shape;

/// The class (§5.5, Table 5.2) and the wall slenderness over its class-3 limit.
struct Classification {
  int cls = 1;
  double over = 0;  ///< slenderness / class-3 limit (> 1: class 4)
};
Classification classify(const Section& s, double fy) {
  const double eps = std::sqrt(235e6 / fy);
  double slenderness = 0;
  double limits[3];
  if (s.shape == Shape::chs) {
    slenderness = s.h / s.t;
    const double e2 = eps * eps;
    limits[0] = 50 * e2, limits[1] = 70 * e2, limits[2] = 90 * e2;
  } else {
    slenderness = (std::max(s.h, s.b) - 3 * s.t) / s.t;  // c = h − 3t, b − 3t
    limits[0] = 33 * eps, limits[1] = 38 * eps, limits[2] = 42 * eps;
  }
  Classification c;
  c.over = slenderness / limits[2];
  c.cls = slenderness <= limits[0] ? 1 : slenderness <= limits[1] ? 2 : slenderness <= limits[2] ? 3 : 4;
  return c;
}

/// ρ of §6.2.8(3): 0 up to half the shear resistance.
double shear_rho(double V, double Vpl) {
  if (!(Vpl > 0)) return V > 0 ? 1.0 : 0.0;
  if (V <= 0.5 * Vpl) return 0;
  const double r = 2 * V / Vpl - 1;
  return std::min(1.0, r * r);
}

/// The N + M check of a class 1–2 section, (6.39)–(6.41), as 1/λ.
double plastic_interaction(const Section& s, const SectionProperties& p, double N, double My,
                           double Mz, double Npl, double Mpl_y, double Mpl_z) {
  if (N == 0 && My == 0 && Mz == 0) return 0;
  const bool circular = s.shape == Shape::chs;
  const double aw = std::min(0.5, (p.A - 2 * s.b * s.t) / p.A);
  const double af = std::min(0.5, (p.A - 2 * s.h * s.t) / p.A);
  const auto lhs = [&](double lambda) {
    const double n = lambda * N / Npl;
    if (n >= 1) return 2.0;
    if (circular) {
      const double reduction = 1 - std::pow(n, 1.7);
      const double MNy = Mpl_y * reduction, MNz = Mpl_z * reduction;
      const double y = lambda * My / MNy, z = lambda * Mz / MNz;
      return y * y + z * z;  // α = β = 2
    }
    const double MNy = std::min(Mpl_y, Mpl_y * (1 - n) / (1 - 0.5 * aw));
    const double MNz = std::min(Mpl_z, Mpl_z * (1 - n) / (1 - 0.5 * af));
    const double a = std::min(6.0, 1.66 / (1 - 1.13 * n * n));
    return std::pow(lambda * My / MNy, a) + std::pow(lambda * Mz / MNz, a);
  };
  double hi = 1e300;
  if (N > 0) hi = std::min(hi, Npl / N);
  if (My > 0) hi = std::min(hi, Mpl_y / My);
  if (Mz > 0) hi = std::min(hi, Mpl_z / Mz);
  double lo = 0;
  // Bisection; once a step leaves the bracket unchanged (adjacent doubles) every later step
  // would too, so stopping there gives the same root as running all 80.
  for (int it = 0; it < 80; ++it) {
    const double mid = 0.5 * (lo + hi);
    double& end = lhs(mid) < 1 ? lo : hi;
    if (end == mid) break;
    end = mid;
  }
  return 1 / hi;
}

/// Cm of Table B.3 for a linear moment between end moments a and b (single curvature when they
/// have the same sign); 1 when the ends do not carry the member's largest moment.
double equivalent_moment_factor(const std::array<double, 2>& ends, double largest) {
  const double big = std::max(std::abs(ends[0]), std::abs(ends[1]));
  if (!(big > 0) || big < 0.999 * largest) return 1.0;
  const double psi = std::abs(ends[0]) >= std::abs(ends[1]) ? ends[1] / ends[0] : ends[0] / ends[1];
  return std::max(0.4, 0.6 + 0.4 * psi);
}

struct SectionResult {
  double u = 0;
  const char* governing = "";
};

SectionResult cross_section(const Section& s, const SectionProperties& p, const Classification& c,
                            const fem::MemberForces& f, double fy, const HollowCheckOptions& o) {
  const double fd = fy / o.gamma_M0;
  const double N = std::max(std::abs(f.N_max), std::abs(f.N_min));
  const double tau_rd = fd / std::sqrt(3.0);
  const double u_torsion = f.T / (2 * p.Am * s.t) / tau_rd;
  const double keep = std::max(0.0, 1 - u_torsion);  // (6.28)
  const double Vpl_y = keep * p.Av_y * tau_rd, Vpl_z = keep * p.Av_z * tau_rd;
  double u_shear = 0;
  for (const auto& [V, Vpl] : {std::pair{f.Vy, Vpl_y}, std::pair{f.Vz, Vpl_z}})
    if (V > 0) u_shear = std::max(u_shear, Vpl > 0 ? V / Vpl : u_torsion + V / (p.Av_y * tau_rd));
  // §6.2.8: shear along z acts with bending about y, along y with bending about z.
  const double red_y = std::max(1e-3, 1 - shear_rho(f.Vz, Vpl_z));
  const double red_z = std::max(1e-3, 1 - shear_rho(f.Vy, Vpl_y));
  double u_nm = 0;
  const char* nm = "";
  if (c.cls <= 2) {
    u_nm = plastic_interaction(s, p, N, f.My, f.Mz, p.A * fd, p.Wpl_y * fd * red_y,
                               p.Wpl_z * fd * red_z);
    nm = "6.2.9.1 N+M (6.41)";
  } else {
    u_nm = (N / p.A + f.My / (p.Wel_y * red_y) + f.Mz / (p.Wel_z * red_z)) / fd;
    nm = "6.2.9.2 N+M (6.42)";
    if (c.cls == 4) {
      u_nm = std::max(u_nm, c.over);
      nm = "5.5 class 4 (not checked)";
    }
  }
  SectionResult r{u_nm, nm};
  if (c.cls < 4) {
    if (u_shear > r.u) r = {u_shear, "6.2.6 shear"};
    if (u_torsion > r.u) r = {u_torsion, "6.2.7 torsion"};
  }
  return r;
}

}  // namespace

double hollow_curve_alpha(sections::Process process) {
  return process == sections::Process::hot ? 0.21 : 0.49;
}

double hollow_section_utilisation(const Section& s, const fem::MemberForces& f, double fy,
                                  const HollowCheckOptions& o) {
  const SectionProperties p = sections::properties(s);
  return cross_section(s, p, classify(s, fy), f, fy, o).u;
}

HollowCheck check_hollow_member(const Section& s, const fem::MemberForces& f, double fy, double E,
                                double L, const HollowCheckOptions& o) {
  const SectionProperties p = sections::properties(s);
  const Classification c = classify(s, fy);
  HollowCheck r;
  r.section_class = c.cls;
  const SectionResult cs = cross_section(s, p, c, f, fy, o);
  r.section = cs.u;
  r.section_governing = cs.governing;
  // §6.3.1 flexural buckling about each axis.
  const double Lcr = o.buckling_length_factor * L;
  const double pi2 = std::numbers::pi * std::numbers::pi;
  const double NRk = p.A * fy;
  const double Ncr_y = pi2 * E * p.Iy / (Lcr * Lcr), Ncr_z = pi2 * E * p.Iz / (Lcr * Lcr);
  r.slenderness_y = Ncr_y > 0 ? std::sqrt(NRk / Ncr_y) : 0;
  r.slenderness_z = Ncr_z > 0 ? std::sqrt(NRk / Ncr_z) : 0;
  const double alpha = hollow_curve_alpha(s.process);
  r.chi_y = buckling_reduction(r.slenderness_y, alpha);
  r.chi_z = buckling_reduction(r.slenderness_z, alpha);
  const double Nc = std::max(0.0, -f.N_min);
  if (!(Nc > 0)) return r;
  // §6.3.3 with Annex B (Table B.1), members not susceptible to torsional deformation.
  const bool plastic = c.cls <= 2;
  const double MRk_y = (plastic ? p.Wpl_y : p.Wel_y) * fy / o.gamma_M1;
  const double MRk_z = (plastic ? p.Wpl_z : p.Wel_z) * fy / o.gamma_M1;
  const double ny = Nc / (r.chi_y * NRk / o.gamma_M1), nz = Nc / (r.chi_z * NRk / o.gamma_M1);
  // Table B.3: 0.9 for a sway buckling mode (L_cr > L), else from the end moments.
  const bool sway = o.buckling_length_factor > 1;
  const double Cmy = sway ? 0.9 : equivalent_moment_factor(f.My_end, f.My);
  const double Cmz = sway ? 0.9 : equivalent_moment_factor(f.Mz_end, f.Mz);
  double kyy, kzz, kyz, kzy;
  if (plastic) {
    kyy = Cmy * std::min(1 + (r.slenderness_y - 0.2) * ny, 1 + 0.8 * ny);
    kzz = Cmz * std::min(1 + (r.slenderness_z - 0.2) * nz, 1 + 0.8 * nz);
    kyz = 0.6 * kzz;
    kzy = 0.6 * kyy;
  } else {
    kyy = Cmy * std::min(1 + 0.6 * r.slenderness_y * ny, 1 + 0.6 * ny);
    kzz = Cmz * std::min(1 + 0.6 * r.slenderness_z * nz, 1 + 0.6 * nz);
    kyz = kzz;
    kzy = 0.8 * kyy;
  }
  const double u61 = ny + kyy * f.My / MRk_y + kyz * f.Mz / MRk_z;
  const double u62 = nz + kzy * f.My / MRk_y + kzz * f.Mz / MRk_z;
  const bool bending = f.My > 0 || f.Mz > 0;
  r.buckling = std::max(u61, u62);
  r.buckling_governing = !bending ? "6.3.1 flexural buckling"
                         : u61 >= u62 ? "6.3.3 (6.61)"
                                      : "6.3.3 (6.62)";
  if (c.cls == 4) {
    r.buckling = std::max(r.buckling, c.over);
    r.buckling_governing = "5.5 class 4 (not checked)";
  }
  return r;
}

}  // namespace gridshell::checks
