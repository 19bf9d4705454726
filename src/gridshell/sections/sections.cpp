#include "gridshell/sections/sections.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <tuple>

#include <fmt/format.h>

#include "gridshell/core/error.h"

namespace gridshell::sections {

namespace {

constexpr double kPi = std::numbers::pi;

/// A solid rounded rectangle (width B along y, height H along z, corner radius r): area, second
/// moments and plastic moduli about its centroidal axes. Each corner lacks a spandrel (an r×r
/// square less a quarter disc) of area As = (1 − π/4) r² whose centroid lies e = r (10 − 3π) /
/// (12 − 3π) from the outer edges and whose second moment about that edge is r⁴ (1 − 5π/16).
struct Solid {
  double A, Iy, Iz, Wpl_y, Wpl_z;
};
Solid rounded_rectangle(double B, double H, double r) {
  const double As = (1 - kPi / 4) * r * r;
  const double e = r * (10 - 3 * kPi) / (12 - 3 * kPi);
  const double Ic = std::pow(r, 4) * (1 - 5 * kPi / 16) - As * e * e;  // about its centroid
  Solid s;
  s.A = B * H - 4 * As;
  s.Iy = B * H * H * H / 12 - 4 * (Ic + As * (H / 2 - e) * (H / 2 - e));
  s.Iz = H * B * B * B / 12 - 4 * (Ic + As * (B / 2 - e) * (B / 2 - e));
  s.Wpl_y = B * H * H / 4 - 4 * As * (H / 2 - e);
  s.Wpl_z = H * B * B / 4 - 4 * As * (B / 2 - e);
  return s;
}

SectionProperties bar_properties(double d) {
  SectionProperties p;
  p.A = kPi * d * d / 4;
  p.Iy = p.Iz = kPi * std::pow(d, 4) / 64;
  p.Wel_y = p.Wel_z = kPi * d * d * d / 32;
  p.Wpl_y = p.Wpl_z = d * d * d / 6;
  p.It = 2 * p.Iy;
  p.Wt = 2 * p.Wel_y;
  return p;
}

SectionProperties chs_properties(double d, double t) {
  SectionProperties p;
  const double di = d - 2 * t;
  p.A = kPi * (d * d - di * di) / 4;
  p.Iy = p.Iz = kPi * (std::pow(d, 4) - std::pow(di, 4)) / 64;
  p.Wel_y = p.Wel_z = 2 * p.Iy / d;
  p.Wpl_y = p.Wpl_z = (d * d * d - di * di * di) / 6;
  p.It = 2 * p.Iy;
  p.Wt = 2 * p.Wel_y;
  p.Av_y = p.Av_z = 2 * p.A / kPi;  // EN 1993-1-1 §6.2.6(3)(g)
  p.Am = kPi * (d - t) * (d - t) / 4;
  return p;
}

SectionProperties rhs_properties(double h, double b, double t, Process process) {
  SectionProperties p;
  std::tie(p.ro, p.ri) = corner_radii(t, process);
  const Solid o = rounded_rectangle(b, h, p.ro), i = rounded_rectangle(b - 2 * t, h - 2 * t, p.ri);
  p.A = o.A - i.A;
  p.Iy = o.Iy - i.Iy;
  p.Iz = o.Iz - i.Iz;
  p.Wel_y = p.Iy / (h / 2);
  p.Wel_z = p.Iz / (b / 2);
  p.Wpl_y = o.Wpl_y - i.Wpl_y;
  p.Wpl_z = o.Wpl_z - i.Wpl_z;
  // EN 10210-2 / EN 10219-2: the thin-walled closed section of the median line.
  const double Rc = (p.ro + p.ri) / 2;
  const double perimeter = 2 * ((b - t) + (h - t)) - 2 * Rc * (4 - kPi);
  p.Am = (b - t) * (h - t) - Rc * Rc * (4 - kPi);
  p.It = t * t * t * perimeter / 3 + 4 * p.Am * p.Am * t / perimeter;
  p.Wt = p.It / (t + 2 * p.Am / perimeter);
  // EN 1993-1-1 §6.2.6(3)(f): load parallel to the depth A h / (b + h), to the width A b / (b + h).
  p.Av_z = p.A * h / (b + h);
  p.Av_y = p.A * b / (b + h);
  return p;
}

/// Millimetres as the series print them: integers without decimals, else one decimal
/// ("88.9", "120", "21.3"); thicknesses always with one decimal ("4.0").
std::string mm(double metres, bool one_decimal) {
  const double v = std::round(metres * 1e4) / 10;  // 0.1 mm
  if (!one_decimal && v == std::round(v)) return fmt::format("{:.0f}", v);
  return fmt::format("{:.1f}", v);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

/// Splits "88.9x4.0" into numbers (millimetres → metres); throws on anything else.
std::vector<double> sizes(const std::string& text, const std::string& subject,
                          const std::string& whole) {
  std::vector<double> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = text.find_first_of("x*", start);
    const std::string part = text.substr(start, end == std::string::npos ? end : end - start);
    double v = 0;
    const char* first = part.data();
    const char* last = part.data() + part.size();
    const auto [ptr, ec] = std::from_chars(first, last, v);
    if (part.empty() || ec != std::errc() || ptr != last || !std::isfinite(v))
      throw Error(subject, fmt::format("'{}': '{}' is not a size in millimetres", whole, part));
    out.push_back(v / 1000);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

void check_range(double v, double lo, double hi, const char* what, const std::string& subject,
                 const Section& s) {
  if (!(v >= lo && v <= hi))
    throw Error(subject, fmt::format("{}: {} must be {} … {} mm", designation(s), what, lo * 1000,
                                     hi * 1000));
}

// The common sizes of the series' tables [mm]: (outside size(s), thicknesses).
struct Row {
  double h, b;
  std::vector<double> t;
};
const std::vector<Row>& chs_rows() {
  static const std::vector<Row> rows = {
      {21.3, 0, {2.3, 2.6, 3.2}},           {26.9, 0, {2.3, 2.6, 3.2}},
      {33.7, 0, {2.6, 3.2, 4.0}},           {42.4, 0, {2.6, 3.2, 4.0}},
      {48.3, 0, {2.6, 3.2, 4.0, 5.0}},      {60.3, 0, {2.6, 3.2, 4.0, 5.0}},
      {76.1, 0, {2.9, 3.2, 4.0, 5.0, 6.3}}, {88.9, 0, {3.2, 4.0, 5.0, 6.3}},
      {114.3, 0, {3.6, 4.0, 5.0, 6.3}},     {139.7, 0, {4.0, 5.0, 6.3, 8.0, 10.0}},
      {168.3, 0, {4.0, 5.0, 6.3, 8.0, 10.0}}, {193.7, 0, {5.0, 6.3, 8.0, 10.0, 12.5}},
      {219.1, 0, {5.0, 6.3, 8.0, 10.0, 12.5}}, {244.5, 0, {6.3, 8.0, 10.0, 12.5}},
      {273.0, 0, {6.3, 8.0, 10.0, 12.5}},   {323.9, 0, {6.3, 8.0, 10.0, 12.5}},
      {355.6, 0, {8.0, 10.0, 12.5}},        {406.4, 0, {8.0, 10.0, 12.5}},
      {457.0, 0, {10.0, 12.5}},             {508.0, 0, {10.0, 12.5}}};
  return rows;
}
const std::vector<Row>& rhs_rows() {
  static const std::vector<Row> rows = {
      {40, 40, {3.2, 4.0, 5.0}},         {50, 50, {3.2, 4.0, 5.0, 6.3}},
      {60, 60, {3.2, 4.0, 5.0, 6.3}},    {70, 70, {4.0, 5.0, 6.3}},
      {80, 80, {4.0, 5.0, 6.3, 8.0}},    {90, 90, {4.0, 5.0, 6.3, 8.0}},
      {100, 100, {4.0, 5.0, 6.3, 8.0, 10.0}}, {120, 120, {5.0, 6.3, 8.0, 10.0}},
      {140, 140, {5.0, 6.3, 8.0, 10.0}}, {150, 150, {5.0, 6.3, 8.0, 10.0}},
      {160, 160, {6.3, 8.0, 10.0}},      {180, 180, {6.3, 8.0, 10.0, 12.5}},
      {200, 200, {6.3, 8.0, 10.0, 12.5}}, {250, 250, {8.0, 10.0, 12.5}},
      {300, 300, {8.0, 10.0, 12.5}},     {350, 350, {10.0, 12.5}},
      {400, 400, {10.0, 12.5}},          {50, 30, {3.2, 4.0}},
      {60, 40, {3.2, 4.0, 5.0}},         {80, 40, {3.2, 4.0, 5.0}},
      {90, 50, {3.6, 4.0, 5.0}},         {100, 50, {3.2, 4.0, 5.0, 6.3}},
      {100, 60, {4.0, 5.0, 6.3}},        {120, 60, {4.0, 5.0, 6.3}},
      {120, 80, {5.0, 6.3, 8.0}},        {140, 80, {5.0, 6.3, 8.0}},
      {150, 100, {5.0, 6.3, 8.0, 10.0}}, {160, 80, {5.0, 6.3, 8.0}},
      {200, 100, {5.0, 6.3, 8.0, 10.0}}, {200, 120, {6.3, 8.0, 10.0}},
      {250, 150, {6.3, 8.0, 10.0, 12.5}}, {300, 200, {8.0, 10.0, 12.5}},
      {400, 200, {8.0, 10.0, 12.5}}};
  return rows;
}

bool same(double a, double b) { return std::abs(a - b) < 1e-5; }

}  // namespace

const char* to_string(Shape shape) {
  switch (shape) {
    case Shape::bar:
      return "bar";
    case Shape::chs:
      return "chs";
    case Shape::rhs:
      return "rhs";
  }
  return "?";
}

const char* to_string(Process process) { return process == Process::hot ? "hot" : "cold"; }

bool operator==(const Section& a, const Section& b) {
  return a.shape == b.shape && a.process == b.process && a.h == b.h && a.b == b.b && a.t == b.t;
}

Section bar(double d) { return {Shape::bar, Process::hot, d, 0, 0}; }
Section chs(double d, double t, Process process) { return {Shape::chs, process, d, 0, t}; }
Section rhs(double h, double b, double t, Process process) {
  return {Shape::rhs, process, h, b, t};
}

std::pair<double, double> corner_radii(double t, Process process) {
  if (process == Process::hot) return {1.5 * t, 1.0 * t};  // EN 10210-2
  const double ro = t <= 0.006 + 1e-9 ? 2 * t : t <= 0.010 + 1e-9 ? 2.5 * t : 3 * t;  // EN 10219-2
  return {ro, ro - t};
}

void validate(const Section& s, const std::string& subject) {
  switch (s.shape) {
    case Shape::bar:
      check_range(s.h, 0.001, 0.5, "the diameter", subject, s);
      return;
    case Shape::chs:
      check_range(s.h, 0.005, 2.5, "the diameter", subject, s);
      check_range(s.t, 0.0005, 0.12, "the thickness", subject, s);
      if (!(s.t < s.h / 2))
        throw Error(subject, fmt::format("{}: the thickness must be less than half the diameter",
                                         designation(s)));
      return;
    case Shape::rhs: {
      check_range(s.h, 0.005, 2.5, "the height", subject, s);
      check_range(s.b, 0.005, 2.5, "the width", subject, s);
      check_range(s.t, 0.0005, 0.12, "the thickness", subject, s);
      const double ro = corner_radii(s.t, s.process).first;
      if (!(2 * ro < std::min(s.h, s.b)))
        throw Error(subject,
                    fmt::format("{}: the wall is too thick for the sides (corner radius {} mm)",
                                designation(s), ro * 1000));
      return;
    }
  }
}

SectionProperties properties(const Section& s) {
  validate(s, "section");
  SectionProperties p = s.shape == Shape::bar   ? bar_properties(s.h)
                        : s.shape == Shape::chs ? chs_properties(s.h, s.t)
                                                : rhs_properties(s.h, s.b, s.t, s.process);
  p.iy = std::sqrt(p.Iy / p.A);
  p.iz = std::sqrt(p.Iz / p.A);
  p.mass = kSteelDensity * p.A;
  return p;
}

std::string designation(const Section& s) {
  std::string d;
  if (s.shape == Shape::bar) return "bar " + mm(s.h, false);
  if (s.shape == Shape::chs) {
    d = "CHS " + mm(s.h, false) + "x" + mm(s.t, true);
  } else if (same(s.h, s.b)) {
    d = "SHS " + mm(s.h, false) + "x" + mm(s.b, false) + "x" + mm(s.t, true);
  } else {
    d = "RHS " + mm(s.h, false) + "x" + mm(s.b, false) + "x" + mm(s.t, true);
  }
  return s.process == Process::cold ? d + " cold" : d;
}

Section parse_section(const std::string& text, const std::string& subject) {
  std::vector<std::string> words;
  {
    std::string w;
    for (char c : lower(text) + " ") {
      if (std::isspace(static_cast<unsigned char>(c))) {
        if (!w.empty()) words.push_back(w);
        w.clear();
      } else {
        w += c;
      }
    }
  }
  Process process = Process::hot;
  if (!words.empty() && (words.back() == "cold" || words.back() == "hot")) {
    process = words.back() == "cold" ? Process::cold : Process::hot;
    words.pop_back();
  }
  if (words.size() != 2)
    throw Error(subject, fmt::format("'{}' is not a section (e.g. 'CHS 88.9x4.0', 'RHS 120x60x4', "
                                     "'SHS 100x5', 'bar 37', optionally followed by 'cold')",
                                     text));
  const std::string& series_word = words[0];
  const std::vector<double> v = sizes(words[1], subject, text);
  Section s;
  if (series_word == "bar" && v.size() == 1) {
    s = bar(v[0]);
    if (process == Process::cold) throw Error(subject, "a solid bar has no cold-formed series");
  } else if (series_word == "chs" && v.size() == 2) {
    s = chs(v[0], v[1], process);
  } else if (series_word == "rhs" && v.size() == 3) {
    s = rhs(v[0], v[1], v[2], process);
  } else if (series_word == "shs" && (v.size() == 2 || v.size() == 3)) {
    if (v.size() == 3 && !same(v[0], v[1]))
      throw Error(subject, fmt::format("'{}': an SHS has equal sides (use RHS)", text));
    s = rhs(v[0], v[0], v.back(), process);
  } else if (series_word == "bar" || series_word == "chs" || series_word == "rhs" ||
             series_word == "shs") {
    throw Error(subject, fmt::format("'{}': a {} takes {} sizes in millimetres", text,
                                     series_word,
                                     series_word == "bar"   ? "1 (diameter)"
                                     : series_word == "chs" ? "2 (d x t)"
                                     : series_word == "rhs" ? "3 (h x b x t)"
                                                            : "2 (b x t)"));
  } else {
    throw Error(subject, fmt::format("'{}': unknown series '{}' (known: CHS, RHS, SHS, bar)",
                                     text, words[0]));
  }
  validate(s, subject);
  return s;
}

std::vector<Section> series(Shape shape, Process process) {
  std::vector<Section> out;
  if (shape == Shape::bar) {
    for (int d = 10; d <= 80; ++d) out.push_back(bar(d / 1000.0));
  } else {
    for (const Row& r : shape == Shape::chs ? chs_rows() : rhs_rows())
      for (double t : r.t)
        out.push_back(shape == Shape::chs ? chs(r.h / 1000, t / 1000, process)
                                          : rhs(r.h / 1000, r.b / 1000, t / 1000, process));
  }
  std::vector<std::pair<double, std::string>> key;
  key.reserve(out.size());
  for (const Section& s : out) key.emplace_back(properties(s).A, designation(s));
  std::vector<std::size_t> order(out.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  std::vector<Section> sorted;
  sorted.reserve(out.size());
  for (std::size_t k : order) sorted.push_back(out[k]);
  return sorted;
}

std::vector<Section> parse_series(const std::string& word, const std::string& subject) {
  const std::string w = lower(word);
  for (Shape shape : {Shape::chs, Shape::rhs, Shape::bar})
    for (Process process : {Process::hot, Process::cold}) {
      if (shape == Shape::bar && process == Process::cold) continue;
      const std::string name = std::string(to_string(shape)) +
                               (process == Process::cold ? " cold" : "");
      if (w == name) return series(shape, process);
    }
  throw Error(subject, fmt::format("'{}' is not a section series (chs, rhs, bar; 'chs cold', "
                                   "'rhs cold' for cold-formed)",
                                   word));
}

bool is_standard(const Section& s) {
  if (s.shape == Shape::bar) {  // the bar series: whole millimetres, Ø10 … Ø80
    const double mm = s.h * 1000;
    return std::abs(mm - std::round(mm)) < 1e-6 && mm >= 10 - 1e-6 && mm <= 80 + 1e-6;
  }
  for (const Row& r : s.shape == Shape::chs ? chs_rows() : rhs_rows()) {
    if (!same(r.h / 1000, s.h) || !same(r.b / 1000, s.b)) continue;
    for (double t : r.t)
      if (same(t / 1000, s.t)) return true;
  }
  return false;
}

std::optional<Section> find_standard(const std::string& text) {
  const Section s = parse_section(text);
  if (!is_standard(s)) return std::nullopt;
  return s;
}

}  // namespace gridshell::sections
