#pragma once
/// \file hollow_checks.h
/// EN 1993-1-1:2005 member checks of a structural hollow section (CHS, RHS/SHS; sections.h) from
/// a member's section forces (fem::MemberForces). Clause by clause (docs/checks.md):
///
/// * Class (§5.5, Table 5.2), ε = √(235/fy): CHS d/t ≤ 50ε², 70ε², 90ε² for classes 1, 2, 3;
///   RHS walls c/t with c = h − 3t and b − 3t (the table's note for hollow sections), as internal
///   parts in pure compression (conservative under bending): ≤ 33ε, 38ε, 42ε. Class 4 is not
///   checked (EN 1993-1-5's effective section is not implemented): its members fail with
///   utilisation max(elastic utilisation, slenderness / class-3 limit) > 1 and the governing check
///   "5.5 class 4" — never silently passed.
/// * Shear (§6.2.6): V_pl,Rd = Av fy / (√3 γM0), Av from §6.2.6(3) (CHS 2A/π, RHS Ah/(b+h) along
///   the height, Ab/(b+h) along the width). Torsion (§6.2.7): τ_t = T / (2 A_m t) ≤ fy/(√3 γM0);
///   with torsion the shear resistance is V_pl,T,Rd = [1 − τ_t / (fy/(√3 γM0))] V_pl,Rd (6.28).
///   Bending and shear (§6.2.8): V_Ed > 0.5 V_pl,T,Rd reduces the moment resistance about that
///   axis by (1 − ρ), ρ = (2 V_Ed / V_pl,T,Rd − 1)² (on the whole section: conservative).
/// * Axial force and bending (§6.2.9), at the member's worst moments (the envelope over its ends:
///   exact when both moments peak at the same end, conservative otherwise), n = N_Ed / N_pl,Rd:
///   class 1–2: M_N,y,Rd = M_pl,y,Rd (1 − n) / (1 − 0.5 a_w), M_N,z,Rd = M_pl,z,Rd (1 − n) /
///   (1 − 0.5 a_f) (6.39, 6.40; a_w = (A − 2bt)/A, a_f = (A − 2ht)/A, ≤ 0.5), for a CHS
///   M_N,Rd = M_pl,Rd (1 − n^1.7) (the CHS rule of the SCI/Tata "blue book", P363; EN 1993-1-1
///   gives none), then (6.41) (My/M_N,y)^α + (Mz/M_N,z)^β ≤ 1 with α = β = 2 (CHS) or
///   1.66 / (1 − 1.13 n²) ≤ 6 (RHS). Its utilisation is 1/λ, λ the factor on all forces at which
///   (6.41) reaches 1 (so that it scales like the other checks; bisection). Class 3: (6.42),
///   σ = N/A + My/Wel,y + Mz/Wel,z ≤ fy/γM0, utilisation σ γM0 / fy.
/// * Member buckling (§6.3.1): N_cr = π² E I / L_cr² about each axis, λ̄ = √(A fy / N_cr),
///   χ (6.49) with curve a (α = 0.21) for hot-finished and c (α = 0.49) for cold-formed hollow
///   sections (Table 6.2). Compressed members with bending: (6.61) and (6.62) with Annex B's k
///   factors (Table B.1) for members not susceptible to torsional deformation — closed hollow
///   sections, χ_LT = 1 — the "RHS sections" row (k_zz = Cmz(1 + (λ̄z − 0.2) n_z)) used for CHS
///   as well; Cm = 0.6 + 0.4ψ ≥ 0.4 (Table B.3, linear moment) from the member's end moments,
///   ψ = M_small / M_large signed (single curvature ψ > 0), or Cm = 0.9 when L_cr > L (a sway
///   mode, Table B.3's note), or 1 when the ends do not carry the largest moment. M_Rk = Wpl fy (class 1–2), Wel fy
///   (class 3). Utilisation: the larger left-hand side of (6.61), (6.62); compression only.
///   L_cr = buckling_length_factor × member length.
///
/// Cost: O(1) per member (the (6.41) bisection ~60 evaluations).

#include "gridshell/fem/frame_solver.h"
#include "gridshell/sections/sections.h"

namespace gridshell::checks {

struct HollowCheckOptions {
  double gamma_M0 = 1.0;  ///< EN 1993-1-1 §6.1 recommended value
  double gamma_M1 = 1.0;
  double buckling_length_factor = 1;  ///< L_cr = factor × member length
};

struct HollowCheck {
  int section_class = 0;   ///< 1 … 4
  double section = 0;      ///< cross-section utilisation: max of N+M, shear, torsion
  double buckling = 0;     ///< member buckling utilisation (6.61/6.62; pure compression 6.46)
  const char* section_governing = "";   ///< e.g. "6.2.9 N+M", "6.2.7 torsion", "5.5 class 4"
  const char* buckling_governing = "";  ///< "6.3.3 (6.61)", "6.3.3 (6.62)" or "" (not compressed)
  double slenderness_y = 0, slenderness_z = 0;  ///< λ̄ about y and z
  double chi_y = 1, chi_z = 1;                  ///< χ about y and z
};

/// Imperfection factor α of the hollow section's buckling curve: a (0.21) hot, c (0.49) cold.
double hollow_curve_alpha(sections::Process process);

/// Checks one member of section `profile` (CHS or RHS) with yield strength fy, modulus E and
/// length L [m] under `forces`.
HollowCheck check_hollow_member(const sections::Section& profile, const fem::MemberForces& forces,
                                double fy, double E, double L,
                                const HollowCheckOptions& options = {});

/// The cross-section utilisation only (for many states along a path).
double hollow_section_utilisation(const sections::Section& profile,
                                  const fem::MemberForces& forces, double fy,
                                  const HollowCheckOptions& options = {});

}  // namespace gridshell::checks
