#include "gridshell/fabrication/nesting.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>

#include <fmt/format.h>

#include "gridshell/core/error.h"
#include "gridshell/mesh/geometry.h"

namespace gridshell::fabrication {

namespace {

using Vec2 = Eigen::Vector2d;
constexpr double kPi = 3.14159265358979323846;

Vec2 rotate(const Vec2& p, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y()};
}

/// Convex hull (Andrew's monotone chain), counter-clockwise.
std::vector<Vec2> convex_hull(std::vector<Vec2> p) {
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (p.size() < 3) return p;
  auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Vec2> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  return h;
}

struct Box {
  Vec2 lo, hi;
  double w() const { return hi.x() - lo.x(); }
  double h() const { return hi.y() - lo.y(); }
};

Box bounds(const std::vector<Vec2>& p, double angle) {
  Box b{Vec2::Constant(1e300), Vec2::Constant(-1e300)};
  for (const Vec2& x : p) {
    const Vec2 y = rotate(x, angle);
    b.lo = b.lo.cwiseMin(y), b.hi = b.hi.cwiseMax(y);
  }
  return b;
}

/// The rotation that gives the outline its minimum-area bounding box, lying landscape.
double landscape_rotation(const std::vector<Vec2>& outline) {
  const std::vector<Vec2> hull = convex_hull(outline);
  double best = 0, best_area = 1e300;
  for (std::size_t k = 0; k < hull.size(); ++k) {
    const Vec2 d = hull[(k + 1) % hull.size()] - hull[k];
    if (!(d.norm() > 0)) continue;
    const double a = -std::atan2(d.y(), d.x());
    const Box b = bounds(hull, a);
    if (b.w() * b.h() < best_area * (1 - 1e-12)) best_area = b.w() * b.h(), best = a;
  }
  const Box b = bounds(outline, best);
  return b.h() > b.w() ? best + kPi / 2 : best;
}

}  // namespace

SheetOptions parse_sheet(const std::string& word) {
  SheetOptions o;
  const std::size_t x = word.find_first_of("xX");
  const auto bad = [&] {
    return Error("--sheet", fmt::format("'{}' is not WxH in metres with W, H > 0 (e.g. 2.5x1.25)",
                                        word));
  };
  if (x == std::string::npos) throw bad();
  const std::string ws = word.substr(0, x), hs = word.substr(x + 1);
  char* end = nullptr;
  o.width = std::strtod(ws.c_str(), &end);
  if (ws.empty() || *end != '\0') throw bad();
  o.height = std::strtod(hs.c_str(), &end);
  if (hs.empty() || *end != '\0') throw bad();
  if (!(o.width > 0) || !(o.height > 0) || !std::isfinite(o.width) || !std::isfinite(o.height))
    throw bad();
  if (o.width <= 2 * o.margin || o.height <= 2 * o.margin)
    throw Error("--sheet", fmt::format("'{}' leaves no room inside the {} m margins", word,
                                       o.margin));
  return o;
}

std::vector<Vec2> placed_outline(const std::vector<Vec2>& outline, const Placement& p) {
  std::vector<Vec2> q;
  q.reserve(outline.size());
  for (const Vec2& x : outline) q.push_back(rotate(x, p.rotation) + p.offset);
  return q;
}

Nesting nest_panels(const std::vector<std::vector<Vec2>>& outlines, const SheetOptions& o) {
  if (!(o.width > 2 * o.margin) || !(o.height > 2 * o.margin) || !(o.gap >= 0))
    throw Error("--sheet", "the sheet size must exceed twice its margin");
  Nesting nest;
  const int n = static_cast<int>(outlines.size());
  nest.placements.assign(n, Placement{});
  // Usable sheet, with every item grown by the gap (no gap needed after the last one).
  const double W = o.width - 2 * o.margin + o.gap, H = o.height - 2 * o.margin + o.gap;
  struct Item {
    int id;
    double rotation, w, h;  // padded size in the chosen orientation
  };
  std::vector<Item> items;
  for (int i = 0; i < n; ++i) {
    if (outlines[i].empty()) continue;
    double a = landscape_rotation(outlines[i]);
    Box b = bounds(outlines[i], a);
    double w = b.w() + o.gap, h = b.h() + o.gap;
    if (!(w <= W && h <= H)) {  // upright does not fit: try turned
      if (h <= W && w <= H) {
        a += kPi / 2;
        std::swap(w, h);
      } else {
        nest.oversize.push_back(i);
        continue;
      }
    }
    items.push_back({i, a, w, h});
  }
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    if (a.h != b.h) return a.h > b.h;
    if (a.w != b.w) return a.w > b.w;
    return a.id < b.id;
  });
  struct Shelf {
    int sheet;
    double y, h, x;
  };
  std::vector<Shelf> shelves;
  std::vector<double> sheet_top;  // used height per sheet
  for (const Item& it : items) {
    Shelf* s = nullptr;
    for (Shelf& sh : shelves)
      if (it.h <= sh.h && sh.x + it.w <= W) {
        s = &sh;
        break;
      }
    if (!s) {
      int sheet = -1;
      for (std::size_t k = 0; k < sheet_top.size() && sheet < 0; ++k)
        if (sheet_top[k] + it.h <= H) sheet = static_cast<int>(k);
      if (sheet < 0) {
        sheet = static_cast<int>(sheet_top.size());
        sheet_top.push_back(0);
      }
      shelves.push_back({sheet, sheet_top[sheet], it.h, 0});
      sheet_top[sheet] += it.h;
      s = &shelves.back();
    }
    const Box b = bounds(outlines[it.id], it.rotation);
    Placement& p = nest.placements[it.id];
    p.sheet = s->sheet;
    p.rotation = it.rotation;
    p.offset = Vec2(o.margin + s->x, o.margin + s->y) - b.lo;
    s->x += it.w;
    nest.used_area += std::abs(signed_area_2d(outlines[it.id]));
  }
  nest.sheets = static_cast<int>(sheet_top.size());
  std::sort(nest.oversize.begin(), nest.oversize.end());
  return nest;
}

}  // namespace gridshell::fabrication
