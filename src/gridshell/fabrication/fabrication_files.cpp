#include "gridshell/fabrication/fabrication_files.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <tbb/parallel_invoke.h>

#include "gridshell/core/error.h"
#include "gridshell/exchange/glb.h"
#include "gridshell/fabrication/exchange_files.h"
#include "gridshell/fabrication/panel_sheets.h"
#include "gridshell/io/files.h"
#include "gridshell/mesh/topology.h"

namespace gridshell::fabrication {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string num(double x) {
  return io::format_number(x);
}

template <class T, class F>
std::string joined(const std::vector<T>& v, F f) {
  std::string s;
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (k) s += ' ';
    s += f(v[k]);
  }
  return s;
}

std::string ints(const std::vector<int>& v) {
  return joined(v, [](int i) { return std::to_string(i); });
}

}  // namespace

FabricationData fabrication_data(const PolyMesh& mesh, const std::vector<int>& supports,
                                 const BeamResults& beams, const FabricationFileOptions& options) {
  FabricationData d;
  const Topology topo = build_topology(mesh);
  for (const auto* values : {&beams.axial_force, &beams.utilisation, &beams.buckling_utilisation})
    if (!values->empty() && static_cast<int>(values->size()) != topo.num_edges())
      throw Error("fabrication",
                  fmt::format("{} beam results for {} beams", values->size(), topo.num_edges()));
  d.parts = fabrication_parts(mesh, topo, supports, options.parts);
  d.axial_force = beams.axial_force;
  d.utilisation = beams.utilisation;
  d.buckling_utilisation = beams.buckling_utilisation;
  d.governing = beams.governing;
  if (!d.governing.empty() && static_cast<int>(d.governing.size()) != topo.num_edges())
    throw Error("fabrication", "governing checks and beams disagree in number");
  const int beams_n = topo.num_edges();
  if (!options.beam_sections.empty()) {
    if (static_cast<int>(options.beam_sections.size()) != beams_n ||
        options.beam_areas.size() != options.beam_sections.size())
      throw Error("fabrication", "beam sections and beams disagree in number");
    d.sections = options.beam_sections;
    d.areas = options.beam_areas;
  } else {
    d.sections.assign(beams_n, options.section.empty()
                                   ? fmt::format("bar {:g}", options.bar_diameter * 1000)
                                   : options.section);
    d.areas.assign(beams_n, options.section_area > 0
                                ? options.section_area
                                : kPi * options.bar_diameter * options.bar_diameter / 4);
  }
  std::vector<std::vector<Vec2>> outlines;
  outlines.reserve(d.parts.panels.size());
  for (const Panel& p : d.parts.panels) outlines.push_back(p.flat.outline);
  d.nesting = nest_panels(outlines, options.sheet);
  return d;
}

std::string joints_csv(const FabricationData& d) {
  std::string s = "joint,x,y,z,valence,support,beams,angles_deg\n";
  for (const Joint& j : d.parts.joints)
    s += fmt::format("{},{},{},{},{},{},{},{}\n", j.id, num(j.position.x()), num(j.position.y()),
                     num(j.position.z()), j.valence, int(j.support), ints(j.beams),
                     joined(j.angles_deg, num));
  return s;
}

std::string beams_csv(const FabricationData& d) {
  std::string s =
      "beam,node_i,node_j,length,axial_force,utilisation,buckling_utilisation,length_class,"
      "panels,section,governing\n";
  const auto cell = [](const std::vector<double>& v, int id) {
    return v.empty() ? std::string() : num(v[id]);
  };
  for (const Beam& b : d.parts.beams)
    s += fmt::format("{},{},{},{},{},{},{},{},{},{},{}\n", b.id, b.i, b.j, num(b.length),
                     cell(d.axial_force, b.id), cell(d.utilisation, b.id),
                     cell(d.buckling_utilisation, b.id), b.length_class, ints(b.panels),
                     d.sections[b.id], d.governing.empty() ? std::string() : d.governing[b.id]);
  return s;
}

std::string panels_csv(const FabricationData& d) {
  std::string s =
      "panel,sides,joints,area,planarity,edge_length_error,sheet,rotation_deg,offset_x,offset_y,"
      "outline,out_of_plane_mm\n";
  for (const Panel& p : d.parts.panels) {
    const Placement& pl = d.nesting.placements[p.id];
    std::string outline;
    for (std::size_t k = 0; k < p.flat.outline.size(); ++k) {
      if (k) outline += ' ';
      outline += num(p.flat.outline[k].x());
      outline += ' ';
      outline += num(p.flat.outline[k].y());
    }
    s += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\n", p.id, p.joints.size(),
                     ints(p.joints), num(p.area), num(p.flat.planarity),
                     num(p.flat.edge_length_error), pl.sheet, num(pl.rotation * 180 / kPi),
                     num(pl.offset.x()), num(pl.offset.y()), outline, num(1e3 * p.flat.out_of_plane));
  }
  return s;
}

namespace {

std::vector<std::vector<Eigen::Vector2d>> flat_outlines(const FabricationData& d) {
  std::vector<std::vector<Eigen::Vector2d>> out;
  for (const Panel& p : d.parts.panels) out.push_back(p.flat.outline);
  return out;
}

}  // namespace

std::string panels_svg(const FabricationData& d, const SheetOptions& sheet) {
  return fabrication::panels_svg(panel_sheets(flat_outlines(d), d.nesting, sheet));
}

nlohmann::json bill_of_materials(const FabricationData& d, const FabricationFileOptions& o) {
  const Fabrication& f = d.parts;
  nlohmann::json j;
  j["joints"] = f.joints.size();
  j["beams"] = f.beams.size();
  j["panels"] = f.panels.size();
  int supports = 0;
  std::map<int, int> valence;
  for (const Joint& jt : f.joints) supports += jt.support, ++valence[jt.valence];
  j["support_joints"] = supports;
  nlohmann::json val = nlohmann::json::object();
  for (const auto& [k, v] : valence) val[std::to_string(k)] = v;
  j["joint_valence"] = val;
  j["total_length_m"] = f.total_length;
  j["bar_diameter_m"] = o.bar_diameter;
  j["bar_density_kg_m3"] = o.bar_density;
  // Per section: beams, length and mass (one row unless the design is sized).
  std::map<std::string, std::array<double, 3>> per;
  double mass = 0;
  for (const Beam& b : f.beams) {
    const double m = o.bar_density * d.areas[b.id] * b.length;
    auto& row = per[d.sections[b.id]];
    row[0] += 1, row[1] += b.length, row[2] += m;
    mass += m;
  }
  if (per.size() <= 1) {
    j["section"] = d.sections.empty() ? std::string() : d.sections.front();
    j["section_area_m2"] = d.areas.empty() ? 0.0 : d.areas.front();
  } else {
    j["section"] = fmt::format("{} sections", per.size());
  }
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& [name, row] : per)
    rows.push_back({{"designation", name}, {"beams", static_cast<int>(row[0])},
                    {"length_m", row[1]}, {"mass_kg", row[2]}});
  j["sections"] = rows;
  j["mass_kg"] = mass;
  j["distinct_beam_lengths"] = f.distinct_lengths;
  j["length_resolution_m"] = o.parts.length_resolution;
  double lmin = f.beams.empty() ? 0 : 1e300, lmax = 0;
  for (const Beam& b : f.beams) lmin = std::min(lmin, b.length), lmax = std::max(lmax, b.length);
  j["beam_length_min_m"] = lmin;
  j["beam_length_max_m"] = lmax;
  double area = 0, planarity = 0, edge_error = 0, out_of_plane = 0;
  for (const Panel& p : f.panels) {
    area += p.area;
    out_of_plane = std::max(out_of_plane, p.flat.out_of_plane);
    planarity = std::max(planarity, p.flat.planarity);
    edge_error = std::max(edge_error, p.flat.edge_length_error);
  }
  j["panel_area_m2"] = area;
  j["planarity_max"] = planarity;
  j["out_of_plane_max_mm"] = 1e3 * out_of_plane;
  j["flat_edge_length_error_max"] = edge_error;
  j["sheet_m"] = {o.sheet.width, o.sheet.height};
  j["sheets_used"] = d.nesting.sheets;
  j["sheet_utilisation"] =
      d.nesting.sheets ? d.nesting.used_area / (d.nesting.sheets * o.sheet.width * o.sheet.height)
                       : 0.0;
  j["oversize_panels"] = d.nesting.oversize;
  j["nesting"] =
      "shelf packing (first-fit decreasing height) of minimum-area bounding boxes, 90-degree turns";
  return j;
}

nlohmann::json write_fabrication_files(const std::filesystem::path& dir, const PolyMesh& mesh,
                                       const std::vector<int>& supports, const BeamResults& beams,
                                       const FabricationFileOptions& options) {
  const FabricationData d = fabrication_data(mesh, supports, beams, options);
  // Independent files, written side by side (the drawings and the GLB are most of the time).
  tbb::parallel_invoke(
      [&] {
        io::write_file_atomic(dir / "joints.csv", joints_csv(d));
        io::write_file_atomic(dir / "beams.csv", beams_csv(d));
        io::write_file_atomic(dir / "panels.csv", panels_csv(d));
      },
      [&] {
        const PanelSheets sheets = panel_sheets(flat_outlines(d), d.nesting, options.sheet);
        io::write_file_atomic(dir / "panels.svg", panels_svg(sheets));
        exchange::write_dxf(dir / "panels.dxf", panels_dxf(sheets));
      },
      [&] { exchange::write_dxf(dir / "beams.dxf", cut_list_dxf(d)); },
      [&] { exchange::write_glb(dir / "gridshell.glb", glb_model(mesh, d)); });
  return bill_of_materials(d, options);
}

}  // namespace gridshell::fabrication
