#include "gridshell/fabrication/exchange_files.h"

#include <algorithm>
#include <map>

#include <fmt/format.h>

#include "gridshell/mesh/geometry.h"
#include "gridshell/sections/sections.h"

namespace gridshell::fabrication {

namespace {

/// The sections of the beams, parsed once per designation.
std::map<std::string, sections::Section> parsed_sections(const FabricationData& d) {
  std::map<std::string, sections::Section> out;
  for (const std::string& s : d.sections)
    if (!out.count(s)) out[s] = sections::parse_section(s, "section");
  return out;
}

}  // namespace

std::vector<int> cutting_order(const FabricationData& d) {
  std::vector<int> order(d.parts.beams.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const auto& ba = d.parts.beams[a];
    const auto& bb = d.parts.beams[b];
    if (d.sections[a] != d.sections[b]) return d.sections[a] < d.sections[b];
    if (ba.length != bb.length) return ba.length > bb.length;
    return a < b;
  });
  return order;
}

exchange::DxfDrawing cut_list_dxf(const FabricationData& d) {
  exchange::DxfDrawing x;
  x.units = exchange::DxfUnits::millimetres;
  x.layers = {{"BEAMS", 5}, {"LABELS", 3}};
  const auto sections = parsed_sections(d);
  constexpr double kLabel = 40;  // label height [mm]
  double y = 0;
  for (int id : cutting_order(d)) {
    const Beam& b = d.parts.beams[id];
    const double depth = 1000 * sections.at(d.sections[id]).h, length = 1000 * b.length;
    y -= std::max(depth, kLabel) + 2 * kLabel;
    x.polylines.push_back(
        {"BEAMS", {{0, y}, {length, y}, {length, y + depth}, {0, y + depth}}, true});
    x.texts.push_back({"LABELS", {0.5 * length, y + depth + kLabel}, kLabel,
                       fmt::format("beam {}  {}  L = {:.1f} mm  joints {}-{}", id, d.sections[id],
                                   length, b.i, b.j)});
  }
  return x;
}

exchange::GlbModel glb_model(const PolyMesh& mesh, const FabricationData& d) {
  exchange::GlbModel m;
  const auto sections = parsed_sections(d);
  for (const Beam& b : d.parts.beams) {
    exchange::GlbBeam g;
    g.a = mesh.vertex(b.i);
    g.b = mesh.vertex(b.j);
    Vec3 up = Vec3::Zero();
    for (int f : b.panels) {
      const Vec3 a = vector_area(mesh, f);
      if (a.norm() > 0) up += a.normalized();
    }
    g.up = up.norm() > 0 ? up : Vec3::UnitZ();
    const sections::Section& s = sections.at(d.sections[b.id]);
    g.round = s.shape != sections::Shape::rhs;
    g.height = s.h;
    g.width = s.b;
    m.beams.push_back(g);
  }
  for (const Panel& p : d.parts.panels) {
    std::vector<Vec3> corners;
    for (int v : p.joints) corners.push_back(mesh.vertex(v));
    m.panels.push_back(std::move(corners));
  }
  return m;
}

}  // namespace gridshell::fabrication
