#include "gridshell/analysis/gridshell_frame.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "gridshell/core/error.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"

namespace gridshell::analysis {

std::vector<double> tributary_areas(const PolyMesh& mesh) {
  std::vector<double> a(mesh.num_vertices(), 0.0);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const double area = polygon_area(mesh, f);
    const auto& face = mesh.faces[f];
    for (int v : face) a[v] += area / static_cast<double>(face.size());
  }
  return a;
}

LoadModel parse_load_model(const std::string& word) {
  for (LoadModel m : {LoadModel::paper, LoadModel::eurocode})
    if (word == to_string(m)) return m;
  throw Error("--loads", "'" + word + "' is not one of paper, eurocode");
}

const char* to_string(LoadModel model) {
  return model == LoadModel::paper ? "paper" : "eurocode";
}

const char* to_string(Combination combination) {
  return combination == Combination::uls ? "ULS" : "SLS";
}

std::pair<double, double> partial_factors(Combination combination) {
  return combination == Combination::uls ? std::pair{1.35, 1.5} : std::pair{1.0, 1.0};
}

double snow_shape_factor(double slope_deg) {
  if (slope_deg <= 30) return 0.8;
  if (slope_deg < 60) return 0.8 * (60 - slope_deg) / 30;
  return 0.0;
}

LoadCases eurocode_load_cases(const PolyMesh& mesh, const std::vector<double>& bar_weight_per_m,
                              const GridshellFrameOptions& o) {
  const int n = mesh.num_vertices();
  LoadCases c{std::vector<double>(n, 0.0), std::vector<double>(n, 0.0),
              std::vector<double>(n, 0.0)};
  const Topology topo = build_topology(mesh);
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    const int i = topo.edges[e][0], j = topo.edges[e][1];
    const double w = bar_weight_per_m[e] * (mesh.vertex(j) - mesh.vertex(i)).norm();
    c.G1[i] -= 0.5 * w;
    c.G1[j] -= 0.5 * w;
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto& face = mesh.faces[f];
    Vec3 a = Vec3::Zero();
    for (std::size_t k = 0; k < face.size(); ++k)
      a += mesh.vertex(face[k]).cross(mesh.vertex(face[(k + 1) % face.size()]));
    const double area = 0.5 * a.norm(), plan = 0.5 * std::abs(a.z());
    if (!(area > 0)) continue;
    const double slope = std::acos(std::clamp(plan / area, 0.0, 1.0)) * 180 / std::numbers::pi;
    const double share = 1.0 / static_cast<double>(face.size());
    for (int v : face) {
      c.G2[v] -= o.glass_kN_m2 * 1e3 * area * share;
      c.Q[v] -= snow_shape_factor(slope) * o.snow_kN_m2 * 1e3 * plan * share;
    }
  }
  return c;
}

fem::FrameSection member_section(const GridshellFrameOptions& o) {
  if (!o.section.empty())
    return fem::profile_section(sections::parse_section(o.section, "--section"));
  if (!(o.diameter > 0) || !std::isfinite(o.diameter)) throw Error("--diameter", "must be > 0");
  return fem::circle_section(o.diameter, "bar");
}

Points vertex_normals(const PolyMesh& mesh) {
  Points n = Points::Zero(mesh.num_vertices(), 3);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 a = vector_area(mesh, f);
    for (int v : mesh.faces[f]) n.row(v) += a.transpose();
  }
  for (int v = 0; v < n.rows(); ++v) {
    const double len = n.row(v).norm();
    if (len > 0) n.row(v) /= len;
  }
  return n;
}

namespace {

/// Each member's local z: the mean of its joints' normals made orthogonal to it, for sections
/// whose axes matter (RHS).
void set_member_axes(const PolyMesh& mesh, fem::FrameModel& m) {
  const Points normals = vertex_normals(mesh);
  for (fem::FrameMember& mb : m.members) {
    Vec3 n = (normals.row(mb.i) + normals.row(mb.j)).transpose();
    const Vec3 x = (mesh.vertex(mb.j) - mesh.vertex(mb.i)).normalized();
    n -= n.dot(x) * x;
    if (n.norm() < 1e-6) continue;  // no usable normal: the default rule
    mb.up = n.normalized();
  }
}

}  // namespace

std::vector<LoadCase> eurocode_cases(const PolyMesh& mesh,
                                     const std::vector<double>& bar_weight_per_m,
                                     const GridshellFrameOptions& o) {
  const LoadCases base = eurocode_load_cases(mesh, bar_weight_per_m, o);
  const auto vertical = [](const std::vector<double>& fz) {
    std::vector<Vec3> F(fz.size(), Vec3::Zero());
    for (std::size_t v = 0; v < fz.size(); ++v) F[v].z() = fz[v];
    return F;
  };
  std::vector<LoadCase> cases;
  cases.push_back({"G1", true, 1.0, "G1", "EN 1991-1-1 self-weight of the bars", vertical(base.G1)});
  cases.push_back({"G2", true, 1.0, "G2", "glass and cladding (--glass)", vertical(base.G2)});
  // Snow: EN 1990 Table A1.1, ψ0 = 0.5 (CEN, sites at most 1000 m above sea level).
  constexpr double kSnowPsi0 = 0.5;
  cases.push_back({"S", false, kSnowPsi0, "snow", "EN 1991-1-3 5.3.3 (i): undrifted, mu1",
                   vertical(base.Q)});
  for (int axis = 0; axis < 2; ++axis)
    for (int side : {-1, 1}) {
      bool cylindrical = false;
      const std::vector<double> mu = snow_shape_factors(mesh, axis, side, &cylindrical);
      const std::string name =
          fmt::format("S_{}{}", axis == 0 ? "x" : "y", side < 0 ? "-" : "+");
      cases.push_back({name, false, kSnowPsi0, "snow",
                       cylindrical ? "EN 1991-1-3 5.3.5 Figure 5.6 (ii): drifted, mu3 and 0.5 mu3"
                                   : "EN 1991-1-3 5.3.3 Figure 5.3 (ii)/(iii): drifted, mu1 and "
                                     "0.5 mu1",
                       snow_forces(mesh, mu, o.snow_kN_m2)});
    }
  for (const FileLoadCase& f : o.load_cases)
    cases.push_back({f.name, f.permanent, f.permanent ? 1.0 : f.psi0, f.name,
                     "file " + f.path, load_case_forces(mesh, f)});
  return cases;
}

std::vector<double> bar_weights_per_m(const fem::FrameModel& model,
                                      const GridshellFrameOptions& o) {
  std::vector<double> w(model.members.size(), 0.0);
  if (!o.self_weight) return w;
  for (std::size_t k = 0; k < w.size(); ++k)
    w[k] = o.density * o.g * model.sections[model.members[k].section].A;
  return w;
}

namespace {

/// The frame's sections and each member's index into them: `member_sections` (distinct ones in
/// order of first use) or the one section of the options.
std::vector<fem::FrameSection> frame_sections(const GridshellFrameOptions& o, std::size_t members,
                                              std::vector<int>& index) {
  index.assign(members, 0);
  if (o.member_sections.empty()) return {member_section(o)};
  if (o.member_sections.size() != members)
    throw Error("sections", fmt::format("{} member sections for {} members",
                                        o.member_sections.size(), members));
  std::vector<fem::FrameSection> out;
  std::vector<sections::Section> seen;
  for (std::size_t k = 0; k < members; ++k) {
    const sections::Section& s = o.member_sections[k];
    const auto it = std::find(seen.begin(), seen.end(), s);
    if (it != seen.end()) {
      index[k] = static_cast<int>(it - seen.begin());
      continue;
    }
    index[k] = static_cast<int>(seen.size());
    seen.push_back(s);
    out.push_back(fem::profile_section(s));
  }
  return out;
}

}  // namespace

fem::FrameModel gridshell_frame(const PolyMesh& mesh, const std::vector<int>& supports,
                                const GridshellFrameOptions& o) {
  if (o.elements < 1) throw Error("--elements", "must be >= 1");
  if (!(o.area_load_kN_m2 >= 0) && !(o.area_load_kN_m2 < 0))
    throw Error("--area-load", "is not a number");
  const Topology topo = build_topology(mesh);
  fem::FrameModel m;
  m.nodes = mesh.V;
  m.faces = mesh.faces;
  std::vector<int> index;
  m.sections = frame_sections(o, topo.edges.size(), index);
  m.materials = {{"steel", o.E, o.nu, o.density}};
  for (std::size_t k = 0; k < topo.edges.size(); ++k) {
    fem::FrameMember mb;
    mb.i = topo.edges[k][0];
    mb.j = topo.edges[k][1];
    mb.section = index[k];
    mb.elements = o.elements;
    m.members.push_back(mb);
  }
  if (std::any_of(m.sections.begin(), m.sections.end(), [](const fem::FrameSection& s) {
        return s.profile && s.profile->shape == sections::Shape::rhs;
      }))
    set_member_axes(mesh, m);
  for (int s : supports) {
    if (s < 0 || s >= mesh.num_vertices()) throw Error("supports", "a support id is out of range");
    m.supports.push_back({s, {true, true, true, false, false, false}});
  }
  const int n = mesh.num_vertices();
  std::vector<double> fz(n, 0.0);
  if (o.loads == LoadModel::eurocode) {
    if (!(o.glass_kN_m2 >= 0) || !std::isfinite(o.glass_kN_m2))
      throw Error("--glass", "must be a load >= 0 (kN/m²)");
    if (!(o.snow_kN_m2 >= 0) || !std::isfinite(o.snow_kN_m2))
      throw Error("--snow", "must be a load >= 0 (kN/m²)");
    if (o.area_load_kN_m2 != 0)
      throw Error("--area-load",
                  "with --loads eurocode give the surface loads as --glass and --snow");
    const std::vector<LoadCase> cases = eurocode_cases(mesh, bar_weights_per_m(m, o), o);
    const std::string name = !o.combination_name.empty() ? o.combination_name
                             : o.combination == Combination::uls ? "ULS"
                                                                 : "SLS";
    const std::vector<LoadCombination> combinations = eurocode_combinations(cases);
    const auto it = std::find_if(combinations.begin(), combinations.end(),
                                 [&](const LoadCombination& c) { return c.name == name; });
    if (it == combinations.end()) throw Error("combination", "no combination named " + name);
    const std::vector<Vec3> F = combine(cases, *it);
    for (int v = 0; v < n; ++v)
      if (F[v].squaredNorm() > 0) m.loads.push_back({v, F[v], Vec3::Zero()});
    return m;
  }
  const std::vector<double> w = bar_weights_per_m(m, o);
  double weight = 0;
  for (std::size_t k = 0; k < w.size(); ++k)
    weight += w[k] * fem::member_length(m, static_cast<int>(k));
  const std::vector<double> trib = tributary_areas(mesh);
  double area = 0;
  for (double t : trib) area += t;
  if (o.self_weight) {
    if (o.self_weight_at_bars || !(area > 0)) {
      for (int k = 0; k < static_cast<int>(m.members.size()); ++k) {
        const double wk = w[k] * fem::member_length(m, k);
        fz[m.members[k].i] -= 0.5 * wk;
        fz[m.members[k].j] -= 0.5 * wk;
      }
    } else {
      for (int v = 0; v < n; ++v) fz[v] -= weight * trib[v] / area;
    }
  }
  if (o.area_load_kN_m2 != 0)
    for (int v = 0; v < n; ++v) fz[v] -= o.area_load_kN_m2 * 1e3 * trib[v];
  for (int v = 0; v < n; ++v)
    if (fz[v] != 0) m.loads.push_back({v, Vec3(0, 0, fz[v]), Vec3::Zero()});
  return m;
}

}  // namespace gridshell::analysis
