#include "gridshell/report/report_html.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <string_view>

#include <fmt/format.h>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/flat_panels.h"
#include "gridshell/optimize/metrics.h"
#include "gridshell/report/assets.h"

namespace gridshell::report {

namespace fs = std::filesystem;

namespace {

constexpr const char* kSubject = "report.html";

/// The first `rows` rows of `p` (model nodes beyond the joints are dropped).
Points first_rows(const Points& p, int rows) {
  if (p.rows() < rows) throw Error(kSubject, "fewer model nodes than joints");
  return p.topRows(rows);
}

void fill_structure(ReportInput& in, const analysis::FrameResult& r) {
  const int n = static_cast<int>(in.joints.rows());
  in.axial_force = r.axial_force;
  if (r.displacement.rows() > 0) in.displacement = first_rows(r.displacement, n);
  in.buckling_lambdas = r.buckling_lambdas;
  for (const Points& m : r.buckling_modes) in.buckling_modes.push_back(first_rows(m, n));
  in.buckling_lambdas.resize(std::min(in.buckling_lambdas.size(), in.buckling_modes.size()));
  in.buckling_modes.resize(in.buckling_lambdas.size());
  // Cross-section and member buckling utilisation, as beams.csv's `utilisation` and
  // `buckling_utilisation` columns (same member order).
  if (r.checks.members.size() == in.axial_force.size()) {
    in.utilisation.clear();
    in.buckling_utilisation.clear();
    for (const checks::MemberCheck& c : r.checks.members) {
      in.utilisation.push_back(c.section);
      in.buckling_utilisation.push_back(c.buckling);
    }
  }
}

/// JSON text of a string, `<` escaped, invalid UTF-8 replaced.
std::string json_text(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

/// Appends `x` with `digits` significant digits; throws for NaN or inf.
void number(std::string& out, double x, int digits, const char* what) {
  if (!std::isfinite(x)) throw Error(kSubject, fmt::format("{} is not finite", what));
  fmt::format_to(std::back_inserter(out), "{:.{}g}", x, digits);
}

/// A JSON array of numbers.
void numbers(std::string& out, const std::vector<double>& v, int digits, const char* what) {
  out += '[';
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i) out += ',';
    number(out, v[i], digits, what);
  }
  out += ']';
}

/// A flat [x0,y0,z0,x1,…] array.
void flat_points(std::string& out, const Points& p, int digits, const char* what) {
  out += '[';
  for (Eigen::Index i = 0; i < p.rows(); ++i)
    for (int c = 0; c < 3; ++c) {
      if (i || c) out += ',';
      number(out, p(i, c), digits, what);
    }
  out += ']';
}

void check_size(std::size_t size, std::size_t expected, const char* what, const char* per) {
  if (size != 0 && size != expected)
    throw Error(kSubject, fmt::format("{} has {} values for {} {}", what, size, expected, per));
}

void check_input(const ReportInput& in) {
  const int n = static_cast<int>(in.joints.rows());
  auto check_joint = [&](int v, const char* what) {
    if (v < 0 || v >= n)
      throw Error(kSubject, fmt::format("{} refers to joint {} of {}", what, v, n));
  };
  for (const auto& b : in.beams) {
    check_joint(b[0], "a beam");
    check_joint(b[1], "a beam");
  }
  for (const auto& f : in.panels) {
    if (f.size() < 3) throw Error(kSubject, "a panel has fewer than 3 joints");
    for (int v : f) check_joint(v, "a panel");
  }
  for (int v : in.supports) check_joint(v, "a support");
  check_size(in.axial_force.size(), in.beams.size(), "axial_force", "beams");
  check_size(in.utilisation.size(), in.beams.size(), "utilisation", "beams");
  check_size(in.buckling_utilisation.size(), in.beams.size(), "buckling_utilisation", "beams");
  check_size(in.beam_sections.size(), in.beams.size(), "beam_sections", "beams");
  check_size(static_cast<std::size_t>(in.displacement.rows()), n, "displacement", "joints");
  check_size(in.density.size(), in.panels.size(), "density", "panels");
  check_size(in.planarity.size(), in.panels.size(), "planarity", "panels");
  check_size(in.out_of_plane_mm.size(), in.panels.size(), "out_of_plane_mm", "panels");
  if (in.buckling_modes.size() != in.buckling_lambdas.size())
    throw Error(kSubject, "buckling modes and their lambdas differ in number");
  for (const Points& m : in.buckling_modes)
    if (m.rows() != n) throw Error(kSubject, "a buckling mode does not have one row per joint");
}

std::string base64(std::string_view bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16 |
                       static_cast<unsigned char>(bytes[i + 1]) << 8 |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string html_escape(std::string_view s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace

ReportInput gridshell_report_input(const PolyMesh& mesh, const std::vector<int>& supports,
                                   const analysis::FrameResult* structure) {
  ReportInput in;
  in.joints = mesh.V;
  in.beams = build_topology(mesh).edges;
  in.panels = mesh.faces;
  in.supports = supports;
  if (mesh.num_faces() > 0) {
    in.planarity = mesh_metrics(mesh).planarity;
    in.out_of_plane_mm = panel_shape(mesh).out_of_plane;
    for (double& d : in.out_of_plane_mm) d *= 1e3;
  }
  if (structure) fill_structure(in, *structure);
  return in;
}

ReportInput frame_report_input(const fem::FrameModel& model, const std::vector<int>& supports,
                               const analysis::FrameResult& structure) {
  ReportInput in;
  in.joints = model.nodes;
  for (const auto& m : model.members) in.beams.push_back({m.i, m.j});
  in.panels = model.faces;
  in.supports = supports;
  fill_structure(in, structure);
  if (model.sections.size() > 1)
    for (const auto& m : model.members)
      in.beam_sections.push_back(model.sections.at(m.section).name);
  return in;
}

std::vector<Figure> read_figures(const fs::path& dir) {
  std::vector<Figure> figures;
  std::error_code ec;
  const fs::path folder = dir / "figures";
  if (!fs::is_directory(folder, ec)) return figures;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".png") continue;
    figures.push_back({entry.path().filename().string(), io::read_file(entry.path())});
  }
  std::sort(figures.begin(), figures.end(),
            [](const Figure& a, const Figure& b) { return a.name < b.name; });
  return figures;
}

std::string report_data_json(const ReportInput& in, const std::vector<Figure>& figures) {
  check_input(in);
  std::string out;
  out.reserve(64 * (in.joints.rows() + in.beams.size()) + 1024);
  out += "{\"version\":1,\"title\":" + json_text(in.title);
  out += ",\"joints\":";
  flat_points(out, in.joints, 6, "a joint coordinate");
  out += ",\"beams\":[";
  for (std::size_t b = 0; b < in.beams.size(); ++b)
    fmt::format_to(std::back_inserter(out), "{}{},{}", b ? "," : "", in.beams[b][0],
                   in.beams[b][1]);
  out += "],\"panels\":[";
  for (std::size_t f = 0; f < in.panels.size(); ++f) {
    out += f ? ",[" : "[";
    for (std::size_t k = 0; k < in.panels[f].size(); ++k)
      fmt::format_to(std::back_inserter(out), "{}{}", k ? "," : "", in.panels[f][k]);
    out += ']';
  }
  out += "],\"supports\":" + nlohmann::json(in.supports).dump();
  out += ",\"axial_force\":";
  numbers(out, in.axial_force, 5, "an axial force");
  out += ",\"displacement\":";
  flat_points(out, in.displacement, 5, "a displacement");
  out += ",\"density\":";
  numbers(out, in.density, 5, "a density");
  out += ",\"planarity\":";
  numbers(out, in.planarity, 5, "a planarity");
  out += ",\"out_of_plane_mm\":";
  numbers(out, in.out_of_plane_mm, 5, "an out-of-plane distance");
  out += ",\"utilisation\":";
  numbers(out, in.utilisation, 5, "a utilisation");
  out += ",\"buckling_utilisation\":";
  numbers(out, in.buckling_utilisation, 5, "a buckling utilisation");
  out += ",\"beam_sections\":" + json_text(in.beam_sections);
  out += ",\"buckling\":{\"lambdas\":";
  numbers(out, in.buckling_lambdas, 6, "a buckling lambda");
  out += ",\"modes\":[";
  for (std::size_t k = 0; k < in.buckling_modes.size(); ++k) {
    if (k) out += ',';
    flat_points(out, in.buckling_modes[k], 4, "a buckling mode");
  }
  out += "]},\"report\":" + json_text(in.report) + ",\"config\":" + json_text(in.config);
  out += ",\"figures\":[";
  for (std::size_t i = 0; i < figures.size(); ++i) {
    if (i) out += ',';
    out += "{\"name\":" + json_text(figures[i].name) + ",\"src\":\"data:image/png;base64,";
    out += base64(figures[i].png);
    out += "\"}";
  }
  out += "]}";
  // `<` only occurs inside JSON strings here; as \u003c it cannot close the script element.
  std::string escaped;
  escaped.reserve(out.size());
  for (char c : out) {
    if (c == '<')
      escaped += "\\u003c";
    else
      escaped += c;
  }
  return escaped;
}

std::string report_html(const ReportInput& input, const std::vector<Figure>& figures) {
  const std::string_view page = report_template();
  const std::string data = report_data_json(input, figures);
  const std::string_view viewer = viewer_script();
  std::string out;
  out.reserve(page.size() + data.size() + viewer.size());
  // Placeholders are looked up in the template only, never in what was filled in.
  std::size_t at = 0;
  for (;;) {
    const std::size_t p = page.find('@', at);
    if (p == std::string_view::npos) break;
    const std::string_view rest = page.substr(p);
    std::string_view key;
    for (std::string_view k : {"@TITLE@", "@DATA@", "@VIEWER@"})
      if (rest.substr(0, k.size()) == k) key = k;
    out += page.substr(at, p - at);
    if (key.empty()) {
      out += '@';
      at = p + 1;
      continue;
    }
    if (key == "@TITLE@") out += html_escape(input.title);
    if (key == "@DATA@") out += data;
    if (key == "@VIEWER@") out += viewer;
    at = p + key.size();
  }
  out += page.substr(at);
  return out;
}

ReportWritten write_report_html(const fs::path& dir, const ReportInput& input) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Figure> figures = read_figures(dir);
  const std::string page = report_html(input, figures);
  ReportWritten w;
  w.path = dir / "report.html";
  io::write_file_atomic(w.path, page);
  w.bytes = page.size();
  w.figures = static_cast<int>(figures.size());
  w.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return w;
}

}  // namespace gridshell::report
