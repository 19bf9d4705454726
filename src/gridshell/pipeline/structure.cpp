#include "gridshell/pipeline/structure.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>

#include <fmt/format.h>

#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/pipeline/design.h"

namespace gridshell {

analysis::GridshellFrameOptions analysed_frame(const DesignOptions& options,
                                               const DesignResult& result) {
  analysis::GridshellFrameOptions f = options.frame;
  if (result.sizing) f.member_sections = result.sizing->member_sections;
  return f;
}

analysis::FrameResult analyze_gridshell(const PolyMesh& mesh, const std::vector<int>& supports,
                                        analysis::AnalysisLevel level,
                                        const analysis::GridshellFrameOptions& frame,
                                        const analysis::FrameAnalysisOptions& options) {
  analysis::FrameAnalysisOptions o = analysis::at_level(options, level);
  if (o.subject == "model") o.subject = "analysis";
  return analysis::analyze_frame(analysis::gridshell_frame(mesh, supports, frame), o);
}

GridshellStructure analyze_structure(const PolyMesh& mesh, const std::vector<int>& supports,
                                     const analysis::GridshellFrameOptions& frame,
                                     const analysis::FrameAnalysisOptions& options,
                                     const StructureOptions& s) {
  GridshellStructure out;
  out.frame = frame;
  if (s.sizing == sizing::MemberSizing::given) {
    out.result = analyze_gridshell(mesh, supports, s.level, frame, options);
    return out;
  }
  sizing::SizingResult sized =
      sizing::size_members(mesh, supports, frame, options, s.level, s.sizing_options);
  out.frame.member_sections = sized.member_sections;
  out.result = sized.final.results.at(sized.primary);
  out.sizing = std::move(sized);
  return out;
}

fabrication::BeamResults member_envelope(const sizing::SizingResult& sz) {
  fabrication::BeamResults b;
  const analysis::FrameResult& primary = sz.final.results.at(sz.primary);
  b.axial_force = primary.axial_force;
  const std::size_t n = primary.checks.members.size();
  b.utilisation.assign(n, 0.0);
  b.buckling_utilisation.assign(n, 0.0);
  b.governing.assign(n, std::string());
  std::vector<double> worst(n, -1.0);
  for (std::size_t k = 0; k < sz.combinations.size() && k < sz.final.results.size(); ++k) {
    if (!sz.combinations[k].uls) continue;
    const auto& members = sz.final.results[k].checks.members;
    for (std::size_t m = 0; m < n && m < members.size(); ++m) {
      const checks::MemberCheck& c = members[m];
      b.utilisation[m] = std::max(b.utilisation[m], c.section);
      b.buckling_utilisation[m] = std::max(b.buckling_utilisation[m], c.buckling);
      const bool buckling = c.buckling > c.section;
      const double u = buckling ? c.buckling : c.section;
      if (u > worst[m]) {
        worst[m] = u;
        b.governing[m] =
            fmt::format("{} under {}", buckling ? c.buckling_governing : c.section_governing,
                        sz.combinations[k].name);
      }
    }
  }
  return b;
}

std::vector<std::string> member_designations(const analysis::GridshellFrameOptions& frame) {
  std::vector<std::string> out;
  for (const sections::Section& s : frame.member_sections) out.push_back(sections::designation(s));
  return out;
}

double plan_area(const PolyMesh& mesh) {
  double a = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) a += std::abs(vector_area(mesh, f).z());
  return a;
}

nlohmann::json steel_block(const PolyMesh& mesh, const analysis::GridshellFrameOptions& frame,
                           double carbon_factor) {
  const Topology topo = build_topology(mesh);
  std::map<std::string, std::array<double, 3>> per;  // members, length, mass
  double mass = 0;
  const sections::Section given = *analysis::member_section(frame).profile;
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    const sections::Section& s = frame.member_sections.empty() ? given : frame.member_sections[e];
    const double L = (mesh.vertex(topo.edges[e][1]) - mesh.vertex(topo.edges[e][0])).norm();
    const double m = sections::properties(s).A * frame.density * L;
    auto& row = per[sections::designation(s)];
    row[0] += 1, row[1] += L, row[2] += m;
    mass += m;
  }
  const double plan = plan_area(mesh);
  nlohmann::json j;
  j["mass_kg"] = mass;
  j["plan_area_m2"] = plan;
  j["mass_kg_per_m2"] = plan > 0 ? nlohmann::json(mass / plan) : nlohmann::json();
  j["carbon_factor_kgCO2e_per_kg"] = carbon_factor;
  j["carbon_kgCO2e"] = mass * carbon_factor;
  j["distinct_sections"] = per.size();
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& [name, row] : per)
    rows.push_back({{"designation", name},
                    {"members", static_cast<int>(row[0])},
                    {"length_m", row[1]},
                    {"mass_kg", row[2]}});
  j["sections"] = rows;
  return j;
}

nlohmann::json sizing_block(const sizing::SizingResult& r, const PolyMesh& mesh,
                            const analysis::GridshellFrameOptions& frame,
                            const sizing::SizingOptions& o, double carbon_factor) {
  analysis::GridshellFrameOptions sized = frame;
  sized.member_sections = r.member_sections;
  nlohmann::json j = steel_block(mesh, sized, carbon_factor);
  j["sized"] = r.sized;
  j["convergence"] = r.convergence;
  if (!r.failure.empty()) j["failure"] = r.failure;
  // CONTRACT.md's names of the same figures.
  j["sections_distinct"] = j["distinct_sections"];
  j["carbon_kgco2e"] = j["carbon_kgCO2e"];
  if (!r.sized) j["failing_check"] = r.failure;
  j["iterations"] = r.iterations;
  j["groups"] = o.groups;
  j["catalogue_size"] = o.catalogue.size();
  j["lambda_min"] = o.lambda_min;
  j["lambda_lba_target"] = r.lambda_lba_target;
  nlohmann::json history = nlohmann::json::array();
  for (const sizing::SizingStep& s : r.history)
    history.push_back({{"iteration", s.iteration},
                       {"phase", s.phase},
                       {"mass_kg", s.mass_kg},
                       {"utilisation_max", s.utilisation_max},
                       {"delta_ratio", s.delta_ratio},
                       {"lambda", s.lambda},
                       {"changed", s.changed},
                       {"seconds", s.seconds}});
  j["history"] = history;
  return j;
}

}  // namespace gridshell
