#include "gridshell/checks/member_checks.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "gridshell/checks/hollow_checks.h"
#include "gridshell/core/error.h"

namespace gridshell::checks {

SteelGrade parse_steel_grade(const std::string& word) {
  for (SteelGrade g : {SteelGrade::s235, SteelGrade::s275, SteelGrade::s355})
    if (word == to_string(g)) return g;
  throw Error("--steel", "'" + word + "' is not one of S235, S275, S355");
}

const char* to_string(SteelGrade grade) {
  switch (grade) {
    case SteelGrade::s235:
      return "S235";
    case SteelGrade::s275:
      return "S275";
    case SteelGrade::s355:
      return "S355";
  }
  return "?";
}

double yield_strength(SteelGrade grade) {
  switch (grade) {
    case SteelGrade::s235:
      return 235e6;
    case SteelGrade::s275:
      return 275e6;
    case SteelGrade::s355:
      return 355e6;
  }
  return 0;
}

double buckling_reduction(double slenderness, double alpha) {
  if (!(slenderness > 0.2)) return 1.0;
  const double l2 = slenderness * slenderness;
  const double phi = 0.5 * (1 + alpha * (slenderness - 0.2) + l2);
  return std::min(1.0, 1.0 / (phi + std::sqrt(phi * phi - l2)));
}

namespace {

struct SectionCapacity {
  double A = 0, Wy = 0, Wz = 0, Imin = 0;
};

SectionCapacity capacity(const fem::FrameSection& s) {
  const double c = s.c > 0 ? s.c : std::sqrt(s.A / std::numbers::pi);
  return {s.A, s.Iy / c, s.Iz / c, std::min(s.Iy, s.Iz)};
}

double section_utilisation(const SectionCapacity& c, const fem::MemberForces& f, double fy) {
  const double N = std::max(std::abs(f.N_max), std::abs(f.N_min));
  const double bending = c.Wy == c.Wz ? f.M / c.Wy : f.My / c.Wy + f.Mz / c.Wz;
  return N / (c.A * fy) + bending / fy;
}

/// The member's fy: its material's when set (MODEL.json), else the options'.
double member_fy(const fem::FrameModel& model, const fem::FrameMember& mb,
                 const MemberCheckOptions& o) {
  const double fy = model.materials[mb.material].fy;
  return fy > 0 ? fy : o.fy;
}

void check_inputs(const fem::FrameModel& model, const std::vector<fem::MemberForces>& forces,
                  const MemberCheckOptions& o) {
  if (forces.size() != model.members.size())
    throw Error("checks", fmt::format("{} member forces for {} members", forces.size(),
                                      model.members.size()));
  if (!(o.fy > 0) || !std::isfinite(o.fy)) throw Error("checks", "fy must be > 0");
}

}  // namespace

namespace {

/// The section's hollow profile, or null for the bar's check.
const sections::Section* hollow_profile(const fem::FrameSection& s) {
  const auto& p = s.profile;
  return p && p->shape != sections::Shape::bar ? &*p : nullptr;
}

HollowCheckOptions hollow_options(const MemberCheckOptions& o) {
  return {o.gamma_M0, o.gamma_M1, o.buckling_length_factor};
}

/// The bar's checks (§6.2.1(7) and §6.3.1 with curve `alpha`).
MemberCheck bar_check(const fem::FrameModel& model, int m, const fem::FrameSection& section,
                      const fem::MemberForces& f, double fy, const MemberCheckOptions& o) {
  const fem::FrameMember& mb = model.members[m];
  const SectionCapacity c = capacity(section);
  MemberCheck r;
  r.section = section_utilisation(c, f, fy);
  const double E = model.materials[mb.material].E;
  const double L = o.buckling_length_factor * fem::member_length(model, m);
  const double Ncr = std::numbers::pi * std::numbers::pi * E * c.Imin / (L * L);
  r.slenderness = Ncr > 0 ? std::sqrt(c.A * fy / Ncr) : 0;
  r.chi = buckling_reduction(r.slenderness, o.alpha);
  const double compression = std::max(0.0, -f.N_min);
  r.buckling = compression / (r.chi * c.A * fy);
  if (compression > 0) r.buckling_governing = "6.3.1 flexural buckling";
  return r;
}

MemberCheck hollow_check(const fem::FrameModel& model, int m, const sections::Section& profile,
                         const fem::MemberForces& f, double fy, const MemberCheckOptions& o) {
  const fem::FrameMember& mb = model.members[m];
  const HollowCheck h =
      check_hollow_member(profile, f, fy, model.materials[mb.material].E,
                          fem::member_length(model, m), hollow_options(o));
  MemberCheck r;
  r.section = h.section;
  r.buckling = h.buckling;
  const bool y_governs = h.chi_y <= h.chi_z;
  r.slenderness = y_governs ? h.slenderness_y : h.slenderness_z;
  r.chi = y_governs ? h.chi_y : h.chi_z;
  r.section_class = h.section_class;
  r.section_governing = h.section_governing;
  r.buckling_governing = h.buckling_governing;
  return r;
}

}  // namespace

MemberCheck check_member(const fem::FrameModel& model, int m, const fem::FrameSection& section,
                         const fem::MemberForces& forces, const MemberCheckOptions& o) {
  const double fy = member_fy(model, model.members[m], o);
  const sections::Section* profile = hollow_profile(section);
  return profile ? hollow_check(model, m, *profile, forces, fy, o)
                 : bar_check(model, m, section, forces, fy, o);
}

MemberChecks check_members(const fem::FrameModel& model,
                           const std::vector<fem::MemberForces>& forces,
                           const MemberCheckOptions& o) {
  check_inputs(model, forces, o);
  if (!(o.gamma_M0 > 0) || !(o.gamma_M1 > 0) || !std::isfinite(o.gamma_M0) ||
      !std::isfinite(o.gamma_M1))
    throw Error("checks", "gamma_M0 and gamma_M1 must be > 0");
  MemberChecks out;
  out.members.resize(forces.size());
  for (size_t m = 0; m < forces.size(); ++m) {
    MemberCheck& r = out.members[m];
    r = check_member(model, static_cast<int>(m), model.sections[model.members[m].section],
                     forces[m], o);
    if (out.section_worst < 0 || r.section > out.section_max) {
      out.section_max = r.section;
      out.section_worst = static_cast<int>(m);
      out.section_governing = r.section_governing;
    }
    if (forces[m].N_min < 0 && (out.buckling_worst < 0 || r.buckling > out.buckling_max)) {
      out.buckling_max = r.buckling;
      out.buckling_worst = static_cast<int>(m);
      out.buckling_governing = r.buckling_governing;
    }
  }
  return out;
}

double max_section_utilisation(const fem::FrameModel& model,
                               const std::vector<fem::MemberForces>& forces,
                               const MemberCheckOptions& o) {
  check_inputs(model, forces, o);
  double u = 0;
  for (size_t m = 0; m < forces.size(); ++m) {
    const fem::FrameMember& mb = model.members[m];
    const double fy = member_fy(model, mb, o);
    const fem::FrameSection& s = model.sections[mb.section];
    const sections::Section* profile = hollow_profile(s);
    u = std::max(u, profile ? hollow_section_utilisation(*profile, forces[m], fy, hollow_options(o))
                            : section_utilisation(capacity(s), forces[m], fy));
  }
  return u;
}

}  // namespace gridshell::checks
