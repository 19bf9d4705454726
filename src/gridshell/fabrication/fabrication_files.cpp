#include "gridshell/fabrication/fabrication_files.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "gridshell/core/error.h"
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

/// Millimetres with 0.01 mm resolution for the SVG.
std::string mm(double x) {
  return fmt::format("{:.2f}", x * 1000);
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

std::string panels_svg(const FabricationData& d, const SheetOptions& sheet) {
  // Sheets stacked top to bottom, 100 mm apart; oversize panels in a row below them.
  const double space = 0.1;
  const double pitch = sheet.height + space;
  double oversize_w = 0, oversize_h = 0;
  std::vector<std::pair<int, Placement>> big;
  for (int id : d.nesting.oversize) {
    const auto& q = d.parts.panels[id].flat.outline;
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = -lo;
    for (const auto& x : q) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    Placement p;
    p.offset = Eigen::Vector2d(oversize_w, 0) - lo;
    big.emplace_back(id, p);
    oversize_w += hi.x() - lo.x() + space;
    oversize_h = std::max(oversize_h, hi.y() - lo.y());
  }
  const double width = std::max(sheet.width, oversize_w);
  const double height =
      d.nesting.sheets * pitch + (big.empty() ? 0.0 : oversize_h + 2 * space) + space;
  std::string s = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}mm\" height=\"{1}mm\" "
      "viewBox=\"0 0 {0} {1}\">\n"
      "<title>gridshell panels: {2} panels on {3} sheets of {4} x {5} m ({6} oversize)</title>\n"
      "<style>polygon{{fill:#cfe3f3;stroke:#000;stroke-width:1}} .big{{fill:#f6c9c9;"
      "stroke:#c00}} rect{{fill:none;stroke:#888;stroke-width:2}} text{{font-family:sans-serif;"
      "text-anchor:middle;dominant-baseline:central}}</style>\n",
      mm(width), mm(height), d.parts.panels.size(), d.nesting.sheets, num(sheet.width),
      num(sheet.height), big.size());
  // A point on sheet k (y up) in SVG millimetres (y down).
  auto svg_point = [&](const Eigen::Vector2d& p, double top) {
    return mm(p.x()) + "," + mm(top + sheet.height - p.y());
  };
  for (int k = 0; k < d.nesting.sheets; ++k) {
    const double top = space + k * pitch;
    s += fmt::format("<g id=\"sheet{}\">\n<rect x=\"0\" y=\"{}\" width=\"{}\" height=\"{}\"/>\n"
                     "<text x=\"{}\" y=\"{}\" font-size=\"30\">sheet {}</text>\n",
                     k, mm(top), mm(sheet.width), mm(sheet.height), mm(sheet.width / 2),
                     mm(top - space / 2), k);
    for (const Panel& p : d.parts.panels) {
      const Placement& pl = d.nesting.placements[p.id];
      if (pl.sheet != k) continue;
      const auto q = placed_outline(p.flat.outline, pl);
      Eigen::Vector2d c = Eigen::Vector2d::Zero(), lo = Eigen::Vector2d::Constant(1e300),
                      hi = -lo;
      for (const auto& x : q) c += x, lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
      c /= static_cast<double>(q.size());
      const double font = std::clamp(0.25 * std::min(hi.x() - lo.x(), hi.y() - lo.y()), 0.01, 0.08);
      s += "<polygon points=\"" + joined(q, [&](const Eigen::Vector2d& x) {
             return svg_point(x, top);
           }) + "\"/>\n";
      s += fmt::format("<text x=\"{}\" y=\"{}\" font-size=\"{}\">{}</text>\n", mm(c.x()),
                       mm(top + sheet.height - c.y()), mm(font), p.id);
    }
    s += "</g>\n";
  }
  if (!big.empty()) {
    const double top = space + d.nesting.sheets * pitch + space;
    s += fmt::format("<g id=\"oversize\">\n<text x=\"0\" y=\"{}\" font-size=\"30\" "
                     "style=\"text-anchor:start\">larger than a sheet</text>\n",
                     mm(top - space / 2));
    for (const auto& [id, pl] : big) {
      const auto q = placed_outline(d.parts.panels[id].flat.outline, pl);
      Eigen::Vector2d c = Eigen::Vector2d::Zero();
      for (const auto& x : q) c += x;
      c /= static_cast<double>(q.size());
      // y up inside a band of height oversize_h.
      auto pt = [&](const Eigen::Vector2d& x) {
        return mm(x.x()) + "," + mm(top + oversize_h - x.y());
      };
      s += "<polygon class=\"big\" points=\"" + joined(q, pt) + "\"/>\n";
      s += fmt::format("<text x=\"{}\" y=\"{}\" font-size=\"80\">{}</text>\n", mm(c.x()),
                       mm(top + oversize_h - c.y()), id);
    }
    s += "</g>\n";
  }
  s += "</svg>\n";
  return s;
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
  io::write_file_atomic(dir / "joints.csv", joints_csv(d));
  io::write_file_atomic(dir / "beams.csv", beams_csv(d));
  io::write_file_atomic(dir / "panels.csv", panels_csv(d));
  io::write_file_atomic(dir / "panels.svg", panels_svg(d, options.sheet));
  return bill_of_materials(d, options);
}

}  // namespace gridshell::fabrication
