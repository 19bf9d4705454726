#include "gridshell/fem/frame_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "gridshell/core/error.h"
#include "gridshell/mesh/topology.h"

namespace gridshell::fem {

FrameSection circle_section(double diameter, const std::string& name) {
  FrameSection s;
  s.name = name;
  const double pi = std::numbers::pi;
  s.A = pi * diameter * diameter / 4;
  s.Iy = s.Iz = pi * std::pow(diameter, 4) / 64;
  s.J = 2 * s.Iy;
  s.profile = sections::bar(diameter);
  return s;
}

FrameSection profile_section(const sections::Section& profile, const std::string& name) {
  if (profile.shape == sections::Shape::bar)
    return circle_section(profile.h, name.empty() ? sections::designation(profile) : name);
  const sections::SectionProperties p = sections::properties(profile);
  FrameSection s;
  s.name = name.empty() ? sections::designation(profile) : name;
  s.A = p.A;
  s.Iy = p.Iy;
  s.Iz = p.Iz;
  s.J = p.It;
  s.c = std::max(profile.h, profile.b) / 2;
  s.profile = profile;
  return s;
}

double member_length(const FrameModel& model, int m) {
  const FrameMember& mb = model.members[m];
  return (model.nodes.row(mb.j) - model.nodes.row(mb.i)).norm();
}

double total_length(const FrameModel& model) {
  double L = 0;
  for (int m = 0; m < static_cast<int>(model.members.size()); ++m) L += member_length(model, m);
  return L;
}

double total_mass(const FrameModel& model) {
  double M = 0;
  for (int m = 0; m < static_cast<int>(model.members.size()); ++m) {
    const FrameMember& mb = model.members[m];
    M += model.sections[mb.section].A * model.materials[mb.material].density *
         member_length(model, m);
  }
  return M;
}

Vec3 total_load(const FrameModel& model) {
  Vec3 F = Vec3::Zero();
  for (const NodalLoad& l : model.loads) F += l.force;
  return F;
}

void validate(const FrameModel& model, const std::string& subject) {
  const int n = model.num_nodes();
  if (n == 0) throw Error(subject, "the model has no nodes");
  if (model.members.empty()) throw Error(subject, "the model has no members");
  if (!model.nodes.allFinite()) throw Error(subject, "a node coordinate is not finite");
  const int ns = static_cast<int>(model.sections.size());
  const int nm = static_cast<int>(model.materials.size());
  for (const FrameSection& s : model.sections) {
    const std::string what = fmt::format("section '{}'", s.name);
    if (!(s.A > 0) || !std::isfinite(s.A)) throw Error(subject, what + ": area A must be > 0");
    if (!(s.Iy > 0) || !(s.Iz > 0) || !(s.J > 0) || !std::isfinite(s.Iy) || !std::isfinite(s.Iz) ||
        !std::isfinite(s.J))
      throw Error(subject, what + ": Iy, Iz and J must be > 0");
    if (!s.up.allFinite()) throw Error(subject, what + ": 'up' is not finite");
  }
  for (const FrameMaterial& m : model.materials) {
    const std::string what = fmt::format("material '{}'", m.name);
    if (!(m.E > 0) || !std::isfinite(m.E)) throw Error(subject, what + ": E must be > 0");
    if (!(m.nu > -1 && m.nu < 0.5)) throw Error(subject, what + ": nu must be in (-1, 0.5)");
    if (!(m.density >= 0) || !std::isfinite(m.density))
      throw Error(subject, what + ": density must be >= 0");
  }
  const double diag = bbox_diagonal(model.nodes);
  for (int k = 0; k < static_cast<int>(model.members.size()); ++k) {
    const FrameMember& mb = model.members[k];
    if (mb.i < 0 || mb.i >= n || mb.j < 0 || mb.j >= n)
      throw Error(subject, fmt::format("member {} refers to node {} of {} nodes", k,
                                       (mb.i < 0 || mb.i >= n) ? mb.i : mb.j, n));
    if (mb.section < 0 || mb.section >= ns)
      throw Error(subject, fmt::format("member {} has an unknown section", k));
    if (mb.material < 0 || mb.material >= nm)
      throw Error(subject, fmt::format("member {} has an unknown material", k));
    if (mb.elements < 1 || mb.elements > 1000)
      throw Error(subject, fmt::format("member {}: elements must be in 1..1000", k));
    if (!mb.up.allFinite()) throw Error(subject, fmt::format("member {}: 'up' is not finite", k));
    const double L = member_length(model, k);
    if (!(L > 1e-12 * std::max(diag, 1e-300)))
      throw Error(subject, fmt::format("member {} (nodes {}–{}) has zero length", k, mb.i, mb.j));
  }
  for (const FrameSupport& s : model.supports)
    if (s.node < 0 || s.node >= n)
      throw Error(subject, fmt::format("a support refers to node {} of {} nodes", s.node, n));
  for (const NodalLoad& l : model.loads) {
    if (l.node < 0 || l.node >= n)
      throw Error(subject, fmt::format("a load refers to node {} of {} nodes", l.node, n));
    if (!l.force.allFinite() || !l.moment.allFinite())
      throw Error(subject, fmt::format("the load at node {} is not finite", l.node));
  }
  for (const auto& f : model.faces)
    for (int v : f)
      if (v < 0 || v >= n) throw Error(subject, fmt::format("a face refers to node {}", v));
}

}  // namespace gridshell::fem
