#include "gridshell/fabrication/panel_sheets.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "gridshell/io/files.h"

namespace gridshell::fabrication {

namespace {

using Vec2 = Eigen::Vector2d;

/// Millimetres with 0.001 mm resolution.
std::string mm(double x) {
  return fmt::format("{:.3f}", x * 1000);
}

struct Box {
  Vec2 lo = Vec2::Constant(1e300), hi = Vec2::Constant(-1e300);
  Vec2 centroid = Vec2::Zero();
};

Box box_of(const std::vector<Vec2>& q) {
  Box b;
  for (const auto& x : q) b.centroid += x, b.lo = b.lo.cwiseMin(x), b.hi = b.hi.cwiseMax(x);
  if (!q.empty()) b.centroid /= static_cast<double>(q.size());
  return b;
}

/// The outline as drawn: offset by half the kerf, then moved to page coordinates by `to_page`.
template <class F>
DrawnOutline drawn(int id, int sheet, const std::vector<Vec2>& placed, double font,
                   const PanelSheetOptions& o, F to_page) {
  DrawnOutline d;
  d.id = id;
  d.sheet = sheet;
  const Box b = box_of(placed);
  const std::vector<Vec2> cut = o.kerf > 0 ? offset_outline(placed, 0.5 * o.kerf) : placed;
  for (const Vec2& x : cut) d.points.push_back(to_page(x));
  d.label = to_page(b.centroid);
  d.font = font;
  return d;
}

}  // namespace

PanelSheets panel_sheets(const std::vector<std::vector<Vec2>>& outlines, const Nesting& nesting,
                         const SheetOptions& sheet, const PanelSheetOptions& o) {
  PanelSheets d;
  d.title_font = o.title;
  d.space = o.space;
  d.stroke = o.stroke;
  const double space = o.space;
  const double pitch = sheet.height + space;
  // The oversize row: each outline's box left to right, `space` apart.
  double oversize_w = 0, oversize_h = 0;
  std::vector<std::pair<int, Placement>> big;
  for (int id : nesting.oversize) {
    const Box b = box_of(outlines[id]);
    Placement p;
    p.offset = Vec2(oversize_w, 0) - b.lo;
    big.emplace_back(id, p);
    oversize_w += b.hi.x() - b.lo.x() + space;
    oversize_h = std::max(oversize_h, b.hi.y() - b.lo.y());
  }
  d.width = std::max(sheet.width, oversize_w);
  d.height = nesting.sheets * pitch + (big.empty() ? 0.0 : oversize_h + 2 * space) + space;
  d.title = fmt::format("gridshell panels: {} panels on {} sheets of {} x {} m ({} oversize)",
                        outlines.size(), nesting.sheets, io::format_number(sheet.width),
                        io::format_number(sheet.height), big.size());
  for (int k = 0; k < nesting.sheets; ++k) {
    const double top = space + k * pitch;
    d.sheets.push_back({k, 0.0, top, sheet.width, sheet.height});
    // y up on the sheet → y down on the page.
    const auto page = [&](const Vec2& p) { return Vec2(p.x(), top + sheet.height - p.y()); };
    for (std::size_t id = 0; id < outlines.size(); ++id) {
      const Placement& pl = nesting.placements[id];
      if (pl.sheet != k) continue;
      const auto q = placed_outline(outlines[id], pl);
      const Box b = box_of(q);
      const double font = std::clamp(0.25 * std::min(b.hi.x() - b.lo.x(), b.hi.y() - b.lo.y()),
                                     o.label_min, o.label_max);
      d.outlines.push_back(drawn(static_cast<int>(id), k, q, font, o, page));
    }
  }
  if (!big.empty()) {
    const double top = space + nesting.sheets * pitch + space;
    d.oversize_top = top;
    const auto page = [&](const Vec2& p) { return Vec2(p.x(), top + oversize_h - p.y()); };
    for (const auto& [id, pl] : big)
      d.outlines.push_back(
          drawn(id, -1, placed_outline(outlines[id], pl), o.label_max, o, page));
  }
  return d;
}

std::string panels_svg(const PanelSheets& d) {
  const double space = d.space;
  const auto point = [](const Vec2& p) { return mm(p.x()) + "," + mm(p.y()); };
  std::string s = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}mm\" height=\"{1}mm\" "
      "viewBox=\"0 0 {0} {1}\">\n"
      "<title>{2}</title>\n"
      "<style>polygon{{fill:#cfe3f3;stroke:#000;stroke-width:{3}}} .big{{fill:#f6c9c9;"
      "stroke:#c00}} rect{{fill:none;stroke:#888;stroke-width:{4}}} text{{font-family:sans-serif;"
      "text-anchor:middle;dominant-baseline:central}}</style>\n",
      mm(d.width), mm(d.height), d.title, 1000 * d.stroke, 2000 * d.stroke);
  const auto outline = [&](const DrawnOutline& o) {
    std::string points;
    for (const Vec2& x : o.points) {
      if (!points.empty()) points += ' ';
      points += point(x);
    }
    return fmt::format("<polygon{} points=\"{}\"/>\n<text x=\"{}\" y=\"{}\" font-size=\"{}\">{}"
                       "</text>\n",
                       o.oversize() ? " class=\"big\"" : "", points, mm(o.label.x()),
                       mm(o.label.y()), mm(o.font), o.id);
  };
  const double title = d.title_font;
  for (const SheetFrame& f : d.sheets) {
    s += fmt::format("<g id=\"sheet{}\">\n<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>\n"
                     "<text x=\"{}\" y=\"{}\" font-size=\"{}\">sheet {}</text>\n",
                     f.index, mm(f.left), mm(f.top), mm(f.width), mm(f.height),
                     mm(f.left + f.width / 2), mm(f.top - space / 2), mm(title), f.index);
    for (const DrawnOutline& o : d.outlines)
      if (o.sheet == f.index) s += outline(o);
    s += "</g>\n";
  }
  if (d.oversize_top >= 0) {
    s += fmt::format("<g id=\"oversize\">\n<text x=\"0\" y=\"{}\" font-size=\"{}\" "
                     "style=\"text-anchor:start\">larger than a sheet</text>\n",
                     mm(d.oversize_top - space / 2), mm(title));
    for (const DrawnOutline& o : d.outlines)
      if (o.oversize()) s += outline(o);
    s += "</g>\n";
  }
  s += "</svg>\n";
  return s;
}

exchange::DxfDrawing panels_dxf(const PanelSheets& d) {
  const double space = d.space;
  exchange::DxfDrawing x;
  x.units = exchange::DxfUnits::millimetres;
  x.layers = {{"SHEETS", 8}, {"PANELS", 5}, {"OVERSIZE", 1}, {"LABELS", 3}};
  const auto at = [&](const Vec2& p) { return Vec2(1000 * p.x(), 1000 * (d.height - p.y())); };
  for (const SheetFrame& f : d.sheets) {
    x.polylines.push_back({"SHEETS",
                           {at({f.left, f.top}), at({f.left + f.width, f.top}),
                            at({f.left + f.width, f.top + f.height}),
                            at({f.left, f.top + f.height})},
                           true});
    x.texts.push_back({"SHEETS", at({f.left + f.width / 2, f.top - space / 2}),
                       1000 * d.title_font, fmt::format("sheet {}", f.index)});
  }
  for (const DrawnOutline& o : d.outlines) {
    exchange::DxfPolyline p{o.oversize() ? "OVERSIZE" : "PANELS", {}, true};
    for (const Vec2& q : o.points) p.points.push_back(at(q));
    x.polylines.push_back(std::move(p));
    x.texts.push_back({"LABELS", at(o.label), 1000 * o.font, std::to_string(o.id)});
  }
  return x;
}

std::vector<Vec2> offset_outline(const std::vector<Vec2>& q, double distance) {
  const std::size_t n = q.size();
  if (n < 3 || !(distance > 0)) return q;
  std::vector<Vec2> out;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 a = q[(k + n - 1) % n], b = q[k], c = q[(k + 1) % n];
    const Vec2 e0 = (b - a).normalized(), e1 = (c - b).normalized();
    // Outward normals of a counter-clockwise outline: the edge direction turned clockwise.
    const Vec2 n0(e0.y(), -e0.x()), n1(e1.y(), -e1.x());
    const Vec2 bisector = n0 + n1;
    const double cos_half = bisector.norm() / 2;  // cos of half the turn between the normals
    if (cos_half > 0.25) {
      out.push_back(b + distance / cos_half * bisector.normalized());
    } else {  // a sharp corner: bevel instead of a miter longer than 4 × distance
      out.push_back(b + distance * n0);
      out.push_back(b + distance * n1);
    }
  }
  return out;
}

}  // namespace gridshell::fabrication
