#include "gridshell/analysis/load_cases.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/core/error.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/nearest.h"

namespace gridshell::analysis {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

double parse_number(const std::string& cell, const std::string& path, int line) {
  try {
    std::size_t pos = 0;
    const double v = std::stod(cell, &pos);
    if (pos != cell.size()) throw std::invalid_argument(cell);
    if (!std::isfinite(v)) throw Error(path, fmt::format("line {}: '{}' is not finite", line, cell));
    return v;
  } catch (const Error&) {
    throw;
  } catch (const std::exception&) {
    throw Error(path, fmt::format("line {}: '{}' is not a number", line, cell));
  }
}

/// The file's header picks what its rows are.
FileLoadCase::Given given_of(const std::vector<std::string>& header, const std::string& path) {
  const auto is = [&](std::initializer_list<const char*> names) {
    if (header.size() != names.size()) return false;
    std::size_t k = 0;
    for (const char* n : names)
      if (header[k++] != n) return false;
    return true;
  };
  if (is({"vertex", "pressure_kN_m2"})) return FileLoadCase::Given::surface_vertex;
  if (is({"panel", "pressure_kN_m2"})) return FileLoadCase::Given::panel;
  if (is({"joint", "fx_kN", "fy_kN", "fz_kN"})) return FileLoadCase::Given::joint;
  throw Error(path,
              "the header must be 'vertex,pressure_kN_m2', 'panel,pressure_kN_m2' or "
              "'joint,fx_kN,fy_kN,fz_kN'");
}

/// Area vector (Newell) and area centroid of a polygon.
std::pair<Vec3, Vec3> area_and_centroid(const PolyMesh& mesh, const std::vector<int>& face) {
  Vec3 mean = Vec3::Zero();
  for (int v : face) mean += mesh.vertex(v);
  mean /= static_cast<double>(face.size());
  Vec3 a = Vec3::Zero(), c = Vec3::Zero();
  double total = 0;
  for (std::size_t k = 0; k < face.size(); ++k) {
    const Vec3 p = mesh.vertex(face[k]), q = mesh.vertex(face[(k + 1) % face.size()]);
    a += p.cross(q);
    const double t = 0.5 * (p - mean).cross(q - mean).norm();
    c += t * (mean + p + q) / 3;
    total += t;
  }
  return {0.5 * a, total > 0 ? Vec3(c / total) : mean};
}

}  // namespace

FileLoadCase read_load_case_file(const std::string& spec) {
  const auto eq = spec.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
    throw Error("--load-case", "'" + spec + "' is not NAME=FILE.csv");
  FileLoadCase c;
  c.name = spec.substr(0, eq);
  c.path = spec.substr(eq + 1);
  if (const auto colon = c.name.find(':'); colon != std::string::npos) {
    const std::string mark = c.name.substr(colon + 1);
    c.name = c.name.substr(0, colon);
    if (mark == "permanent") {
      c.permanent = true;
      c.psi0 = 1;
    } else if (mark != "variable") {
      throw Error("--load-case", "'" + mark + "' is not a marker (permanent or variable)");
    }
  }
  if (c.name.empty() || c.name.find_first_of(" \t\"") != std::string::npos)
    throw Error("--load-case", "'" + spec + "': the name must be a word");
  static const std::set<std::string> kReserved{"G1", "G2", "S", "S_x-", "S_x+", "S_y-", "S_y+"};
  if (kReserved.count(c.name))
    throw Error("--load-case", "'" + c.name + "' is the name of a built-in load case");
  std::ifstream in(c.path);
  if (!in) throw Error(c.path, "cannot open the load case file");
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!trim(line).empty()) break;
  }
  if (trim(line).empty()) throw Error(c.path, "empty load case file");
  c.given = given_of(split_csv(trim(line)), c.path);
  const std::size_t cols = c.given == FileLoadCase::Given::joint ? 4 : 2;
  std::set<int> seen;
  while (std::getline(in, line)) {
    ++line_no;
    if (trim(line).empty()) continue;
    const std::vector<std::string> cells = split_csv(trim(line));
    if (cells.size() != cols)
      throw Error(c.path, fmt::format("line {}: {} columns, expected {}", line_no, cells.size(), cols));
    const double id = parse_number(cells[0], c.path, line_no);
    if (id != std::floor(id) || id < 0 || id > 1e9)
      throw Error(c.path, fmt::format("line {}: '{}' is not an id", line_no, cells[0]));
    const int i = static_cast<int>(id);
    if (!seen.insert(i).second) throw Error(c.path, fmt::format("line {}: id {} again", line_no, i));
    c.ids.push_back(i);
    if (c.given == FileLoadCase::Given::joint) {
      c.force.emplace_back(parse_number(cells[1], c.path, line_no),
                           parse_number(cells[2], c.path, line_no),
                           parse_number(cells[3], c.path, line_no));
    } else {
      c.pressure.push_back(parse_number(cells[1], c.path, line_no));
    }
  }
  if (c.ids.empty()) throw Error(c.path, "no rows below the header");
  return c;
}

void attach_surface(FileLoadCase& c, const TriMesh& surface) {
  if (c.given != FileLoadCase::Given::surface_vertex)
    throw Error(c.path, "joint and panel load cases apply to a grid-shell (gridshell analyze); "
                        "a design's load case is 'vertex,pressure_kN_m2' on the input surface");
  const int n = surface.num_vertices();
  if (static_cast<int>(c.ids.size()) != n)
    throw Error(c.path, fmt::format("{} vertices given, the input surface has {}", c.ids.size(), n));
  for (int id : c.ids)
    if (id >= n) throw Error(c.path, fmt::format("vertex {} is not on the input surface", id));
  c.surface = std::make_shared<const TriMesh>(surface);
}

namespace {

/// The input surface's upward orientation: +1 when its area vector's z is ≥ 0, else −1.
double surface_orientation(const TriMesh& s) {
  double z = 0;
  for (int f = 0; f < s.num_faces(); ++f) {
    const Vec3 a = s.V.row(s.F(f, 0)).transpose(), b = s.V.row(s.F(f, 1)).transpose(),
               c = s.V.row(s.F(f, 2)).transpose();
    z += (b - a).cross(c - a).z();
  }
  return z >= 0 ? 1.0 : -1.0;
}

/// Per panel: the pressure [kN/m²] interpolated from the input surface at the closest point to
/// the area centroid, and the surface's (oriented) normal there.
std::vector<std::pair<double, Vec3>> surface_pressures(const PolyMesh& mesh,
                                                       const FileLoadCase& c) {
  const TriMesh& s = *c.surface;
  std::vector<double> p(s.num_vertices(), 0.0);
  for (std::size_t k = 0; k < c.ids.size(); ++k) p[c.ids[k]] = c.pressure[k];
  std::vector<std::vector<int>> around(s.num_vertices());
  for (int f = 0; f < s.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) around[s.F(f, k)].push_back(f);
  const double orient = surface_orientation(s);
  Points centroids(mesh.num_faces(), 3);
  for (int f = 0; f < mesh.num_faces(); ++f)
    centroids.row(f) = area_and_centroid(mesh, mesh.faces[f]).second.transpose();
  const auto near = nearest_points(s.V, centroids, 8);
  std::vector<std::pair<double, Vec3>> out(mesh.num_faces(), {0.0, Vec3(0, 0, 1)});
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 q = centroids.row(f).transpose();
    double best = std::numeric_limits<double>::infinity();
    for (int v : near[f])
      for (int t : around[v]) {
        const Vec3 a = s.V.row(s.F(t, 0)).transpose(), b = s.V.row(s.F(t, 1)).transpose(),
                   cc = s.V.row(s.F(t, 2)).transpose();
        const Vec3 n = (b - a).cross(cc - a);
        if (!(n.norm() > 0)) continue;
        const TrianglePoint tp = closest_point_on_triangle(q, a, b, cc);
        const double d = (tp.point - q).squaredNorm();
        if (d >= best) continue;
        best = d;
        out[f] = {tp.bary(0) * p[s.F(t, 0)] + tp.bary(1) * p[s.F(t, 1)] + tp.bary(2) * p[s.F(t, 2)],
                  orient * n.normalized()};
      }
  }
  return out;
}

}  // namespace

std::vector<Vec3> load_case_forces(const PolyMesh& mesh, const FileLoadCase& c) {
  const int n = mesh.num_vertices();
  std::vector<Vec3> F(n, Vec3::Zero());
  if (c.given == FileLoadCase::Given::joint) {
    for (std::size_t k = 0; k < c.ids.size(); ++k) {
      if (c.ids[k] >= n)
        throw Error(c.path, fmt::format("joint {} is not in the grid-shell ({} joints)", c.ids[k], n));
      F[c.ids[k]] += 1e3 * c.force[k];
    }
    return F;
  }
  std::vector<std::pair<double, Vec3>> per_face(mesh.num_faces(), {0.0, Vec3(0, 0, 1)});
  if (c.given == FileLoadCase::Given::panel) {
    for (std::size_t k = 0; k < c.ids.size(); ++k) {
      if (c.ids[k] >= mesh.num_faces())
        throw Error(c.path, fmt::format("panel {} is not in the grid-shell ({} panels)", c.ids[k],
                                        mesh.num_faces()));
      per_face[c.ids[k]].first = c.pressure[k];
    }
    // Panels face up overall (the grid's own orientation, flipped when it faces down).
    Vec3 total = Vec3::Zero();
    for (const auto& face : mesh.faces) total += area_and_centroid(mesh, face).first;
    for (auto& pf : per_face) pf.second = Vec3(0, 0, total.z() >= 0 ? 1 : -1);
  } else {
    if (!c.surface) throw Error(c.path, "the load case has no input surface to interpolate on");
    per_face = surface_pressures(mesh, c);
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto& face = mesh.faces[f];
    Vec3 a = area_and_centroid(mesh, face).first;
    // The panel's own normal, turned to agree with the reference orientation.
    if (a.dot(per_face[f].second) < 0) a = -a;
    const Vec3 force = -per_face[f].first * 1e3 * a;  // p × area, against the normal
    for (int v : face) F[v] += force / static_cast<double>(face.size());
  }
  return F;
}

double cylindrical_snow_factor(double rise, double width) {
  if (!(width > 0)) return 0.8;
  return std::min(2.0, 0.2 + 10 * std::max(0.0, rise) / width);
}

namespace {
/// The rise of the roof along `axis`: its highest joint above the highest joint within 5 % of
/// the plan extent from either end of the axis; and that extent.
std::pair<double, double> rise_along(const PolyMesh& mesh, int axis) {
  const double lo = mesh.V.col(axis).minCoeff(), hi = mesh.V.col(axis).maxCoeff();
  const double b = hi - lo, band = 0.05 * b;
  double top = -std::numeric_limits<double>::infinity(), ends = top;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double x = mesh.V(v, axis), z = mesh.V(v, 2);
    top = std::max(top, z);
    if (x <= lo + band || x >= hi - band) ends = std::max(ends, z);
  }
  return {top - ends, b};
}

/// Slope [degrees] and plan area of a face (area vector).
std::pair<double, double> slope_and_plan(const Vec3& a) {
  const double area = a.norm(), plan = std::abs(a.z());
  if (!(area > 0)) return {0.0, 0.0};
  return {std::acos(std::clamp(plan / area, 0.0, 1.0)) * 180 / std::numbers::pi, plan};
}
}  // namespace

std::vector<double> snow_shape_factors(const PolyMesh& mesh, int axis, int side,
                                       bool* cylindrical) {
  std::vector<double> mu(mesh.num_faces(), 0.0);
  double mu3 = 0, centre = 0;
  if (axis >= 0 && mesh.num_vertices() > 0) {
    const auto [rise, width] = rise_along(mesh, axis);
    mu3 = cylindrical_snow_factor(rise, width);
    centre = 0.5 * (mesh.V.col(axis).minCoeff() + mesh.V.col(axis).maxCoeff());
  }
  const bool cyl = axis >= 0 && mu3 > 0.8;
  if (cylindrical) *cylindrical = cyl;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto [a, c] = area_and_centroid(mesh, mesh.faces[f]);
    const double slope = slope_and_plan(a).first;
    if (axis < 0) {
      mu[f] = snow_shape_factor(slope);
      continue;
    }
    const bool leeward = side > 0 ? c(axis) > centre : c(axis) < centre;
    const double full = cyl ? (slope <= 60 ? mu3 : 0.0) : snow_shape_factor(slope);
    mu[f] = leeward ? full : 0.5 * full;
  }
  return mu;
}

std::vector<Vec3> snow_forces(const PolyMesh& mesh, const std::vector<double>& mu, double s_k) {
  std::vector<Vec3> F(mesh.num_vertices(), Vec3::Zero());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto& face = mesh.faces[f];
    Vec3 a = Vec3::Zero();
    for (std::size_t k = 0; k < face.size(); ++k)
      a += mesh.vertex(face[k]).cross(mesh.vertex(face[(k + 1) % face.size()]));
    const double plan = 0.5 * std::abs(a.z());
    const double share = 1.0 / static_cast<double>(face.size());
    for (int v : face) F[v].z() -= mu[f] * s_k * 1e3 * plan * share;
  }
  return F;
}

std::vector<LoadCombination> eurocode_combinations(const std::vector<LoadCase>& cases) {
  constexpr double kGammaG = 1.35, kGammaGinf = 1.0, kGammaQ = 1.5;
  std::vector<const LoadCase*> permanent, snow, files;
  for (const LoadCase& c : cases)
    (c.permanent ? permanent : c.action == "snow" ? snow : files).push_back(&c);
  std::vector<LoadCombination> out;
  const auto add = [&](const LoadCase& lead, bool uls, double gamma_g, const std::string& name) {
    LoadCombination c;
    c.name = name;
    c.uls = uls;
    c.leading = lead.name;
    const double gq = uls ? kGammaQ : 1.0;
    for (const LoadCase* g : permanent) c.factors.emplace_back(g->name, uls ? gamma_g : 1.0);
    c.factors.emplace_back(lead.name, gq);
    // Accompanying: the undrifted snow when a file case leads, every other variable file case.
    if (lead.action != "snow")
      for (const LoadCase* s : snow)
        if (s->name == "S") c.factors.emplace_back(s->name, gq * s->psi0);
    for (const LoadCase* f : files)
      if (f != &lead) c.factors.emplace_back(f->name, gq * f->psi0);
    out.push_back(std::move(c));
  };
  for (const bool uls : {true, false}) {
    const std::string prefix = uls ? "ULS" : "SLS";
    for (const LoadCase* s : snow) add(*s, uls, kGammaG, s->name == "S" ? prefix : prefix + "_" + s->name);
    for (const LoadCase* f : files) {
      add(*f, uls, kGammaG, prefix + "_" + f->name);
      Vec3 net = Vec3::Zero();
      for (const Vec3& x : f->F) net += x;
      if (uls && net.z() > 0) add(*f, uls, kGammaGinf, prefix + "_" + f->name + "_Ginf");
    }
  }
  // Without variable actions: the permanent ones alone.
  if (snow.empty() && files.empty() && !permanent.empty()) {
    for (const bool uls : {true, false}) {
      LoadCombination c;
      c.name = uls ? "ULS" : "SLS";
      c.uls = uls;
      for (const LoadCase* g : permanent) c.factors.emplace_back(g->name, uls ? kGammaG : 1.0);
      out.push_back(std::move(c));
    }
  }
  // The primary first: "ULS" (snow leading), else the first ULS.
  std::stable_partition(out.begin(), out.end(),
                        [](const LoadCombination& c) { return c.name == "ULS"; });
  return out;
}

std::vector<Vec3> combine(const std::vector<LoadCase>& cases, const LoadCombination& c) {
  std::vector<Vec3> F;
  for (const auto& term : c.factors) {
    const std::string& name = term.first;  // (a plain name: Clang 14 captures no bindings)
    const double factor = term.second;
    const auto it = std::find_if(cases.begin(), cases.end(),
                                 [&](const LoadCase& lc) { return lc.name == name; });
    if (it == cases.end()) throw Error("combination " + c.name, "unknown load case " + name);
    if (F.empty()) F.assign(it->F.size(), Vec3::Zero());
    for (std::size_t v = 0; v < F.size() && v < it->F.size(); ++v) F[v] += factor * it->F[v];
  }
  return F;
}

}  // namespace gridshell::analysis
