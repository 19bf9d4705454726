#pragma once
/// \file member_checks.h
/// Steel member checks of a frame (a grid-shell's bars) from its section forces, per
/// EN 1993-1-1:2005 with γM0 = γM1 = 1:
///
/// * Cross-section (§6.2.1(7), the conservative linear elastic interaction):
///   u = |N| / (A fy) + M / (W fy), with M the resultant bending moment √(My² + Mz²) when the
///   section is axisymmetric (Wy = Wz, e.g. the solid circle), else My / Wy + Mz / Wz.
///   W = I / c: c the outer-fibre distance, FrameSection::c, or when that is 0 the solid circle
///   of area A (c = d/2 = √(A/π)), the grid-shell's bar. N and M are the member's envelope over its element
///   ends (fem::MemberForces): the largest |N| with the largest M — exact when N is constant along
///   the member (loads only at joints, linear analysis), otherwise on the safe side.
/// * Flexural buckling (§6.3.1): u_b = N_Ed / (χ A fy) for compressed members (0 otherwise),
///   N_cr = π² E I_min / L_cr², λ̄ = √(A fy / N_cr), Φ = ½ [1 + α (λ̄ − 0.2) + λ̄²],
///   χ = 1 / (Φ + √(Φ² − λ̄²)) ≤ 1 (eq. 6.49). Buckling curve c, α = 0.49 (Table 6.1): EN 1993-1-1
///   Table 6.2 assigns curve c to "U-, T- and solid sections" about any axis (S235–S420). The
///   buckling length is the member length (joint to joint, pinned–pinned, L_cr = L): a stated,
///   conservative choice for the rigidly jointed bars of a grid-shell, whose global (snap-through)
///   buckling is the separate λ of the frame analysis. No bending–buckling interaction (§6.3.3).
///
/// These two are the checks of the solid bar and of sections given only by their constants
/// (MODEL.json {A, Iy, Iz, J}). Members of a hollow section (FrameSection::profile CHS or RHS)
/// get the full EN 1993-1-1 checks of hollow_checks.h instead: class, plastic or elastic
/// resistance, N + biaxial bending + shear + torsion (§6.2), member buckling with the curve of
/// the process and the interaction (6.61)/(6.62) (§6.3.3, Annex B).
///
/// fy per grade for thickness t ≤ 40 mm (EN 1993-1-1 Table 3.1): S235 235, S275 275, S355 355 MPa.
/// Cost: O(members).

#include <string>
#include <vector>

#include "gridshell/fem/frame_model.h"
#include "gridshell/fem/frame_solver.h"

namespace gridshell::checks {

/// The steel grade; the option words of `--steel`.
enum class SteelGrade { s235, s275, s355 };
SteelGrade parse_steel_grade(const std::string& word);  ///< throws Error("--steel")
const char* to_string(SteelGrade grade);
/// Yield strength fy [Pa] for t ≤ 40 mm.
double yield_strength(SteelGrade grade);

/// Imperfection factor α of buckling curve c (EN 1993-1-1 Table 6.1).
inline constexpr double kCurveCAlpha = 0.49;

/// Reduction factor χ for flexural buckling at relative slenderness λ̄ (eq. 6.49); 1 for
/// λ̄ ≤ 0.2.
double buckling_reduction(double slenderness, double alpha = kCurveCAlpha);

struct MemberCheckOptions {
  double fy = 355e6;  ///< yield strength [Pa] of members whose material has none (fy = 0)
  double alpha = kCurveCAlpha;        ///< buckling curve imperfection factor
  double buckling_length_factor = 1;  ///< L_cr = factor × member length
  double gamma_M0 = 1.0;  ///< partial factor of cross-sections (hollow sections; bar: 1)
  double gamma_M1 = 1.0;  ///< partial factor of member buckling (hollow sections; bar: 1)
};

struct MemberCheck {
  double section = 0;      ///< cross-section utilisation (§6.2.1(7))
  double buckling = 0;     ///< flexural buckling utilisation (§6.3.1); 0 unless compressed
  double slenderness = 0;  ///< λ̄
  double chi = 1;          ///< χ (hollow sections: the smaller of χy, χz)
  int section_class = 0;   ///< EN 1993-1-1 class of a hollow section; 0 for the bar's check
  const char* section_governing = "6.2.1(7) N+M";  ///< the clause that governs `section`
  const char* buckling_governing = "";  ///< the clause that governs `buckling` ("" if none)
};

struct MemberChecks {
  std::vector<MemberCheck> members;
  double section_max = 0;
  int section_worst = -1;  ///< member id, −1 when there are no members
  double buckling_max = 0;
  int buckling_worst = -1;  ///< −1 when no member is compressed
  const char* section_governing = "";   ///< the clause at section_worst
  const char* buckling_governing = "";  ///< the clause at buckling_worst
};

/// Checks every member of `model` under `forces` (one per member). Throws Error("checks") when
/// the sizes disagree or fy is not positive.
MemberChecks check_members(const fem::FrameModel& model,
                           const std::vector<fem::MemberForces>& forces,
                           const MemberCheckOptions& options = {});

/// Member m of `model` checked as if it had `section` (its length, material and fy from the
/// model): the check check_members makes, for trying other sections (sizing/sizing.h).
MemberCheck check_member(const fem::FrameModel& model, int m, const fem::FrameSection& section,
                         const fem::MemberForces& forces, const MemberCheckOptions& options = {});

/// The largest cross-section utilisation only (for many states along a path).
double max_section_utilisation(const fem::FrameModel& model,
                               const std::vector<fem::MemberForces>& forces,
                               const MemberCheckOptions& options = {});

}  // namespace gridshell::checks
