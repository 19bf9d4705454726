#include "gridshell/io/frame_model_json.h"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/io/json.h"

namespace gridshell::io {

using nlohmann::json;

namespace {

double num(const json& j, const std::string& what, const std::string& subject) {
  if (!j.is_number()) throw Error(subject, what + " must be a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw Error(subject, what + " is not finite");
  return v;
}

Vec3 vec3(const json& j, const std::string& what, const std::string& subject) {
  if (!j.is_array() || j.size() != 3) throw Error(subject, what + " must be [x, y, z]");
  return Vec3(num(j[0], what, subject), num(j[1], what, subject), num(j[2], what, subject));
}

/// An integer that fits an int (node ids, element counts); larger ones are refused rather than
/// wrapped around into a valid-looking id.
int index(const json& j, const std::string& what, const std::string& subject) {
  if (!j.is_number_integer()) throw Error(subject, what + " must be an integer");
  const bool fits = j.is_number_unsigned()
                        ? j.get<std::uint64_t>() <= std::numeric_limits<int>::max()
                        : j.get<std::int64_t>() >= std::numeric_limits<int>::min() &&
                              j.get<std::int64_t>() <= std::numeric_limits<int>::max();
  if (!fits) throw Error(subject, what + fmt::format(" {} is out of range", j.dump()));
  return static_cast<int>(j.get<std::int64_t>());
}

std::vector<std::vector<int>> polygons(const json& j, const std::string& what,
                                       const std::string& subject) {
  std::vector<std::vector<int>> out;
  if (!j.is_array()) throw Error(subject, what + " must be a list of node lists");
  for (const auto& f : j) {
    if (!f.is_array() || f.size() < 3) throw Error(subject, what + ": a face needs >= 3 nodes");
    std::vector<int> p;
    for (const auto& v : f) p.push_back(index(v, what, subject));
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace

namespace {

using NameIndex = std::map<std::string, int>;

void read_nodes(const json& j, const std::string& subject, fem::FrameModel& m) {
  if (!j.contains("nodes") || !j["nodes"].is_array() || j["nodes"].empty())
    throw Error(subject, "'nodes' must be a non-empty list of [x, y, z]");
  m.nodes.resize(j["nodes"].size(), 3);
  for (size_t i = 0; i < j["nodes"].size(); ++i)
    m.nodes.row(i) = vec3(j["nodes"][i], fmt::format("nodes[{}]", i), subject).transpose();
}

/// A shaped section's dimension [model units].
double dim(const json& s, const char* key, const std::string& what, const std::string& subject) {
  if (!s.contains(key)) throw Error(subject, what + fmt::format(": needs '{}'", key));
  return num(s[key], what + "." + key, subject);
}

sections::Process process_of(const json& s, const std::string& what, const std::string& subject) {
  if (!s.contains("process")) return sections::Process::hot;
  if (s["process"] == "hot") return sections::Process::hot;
  if (s["process"] == "cold") return sections::Process::cold;
  throw Error(subject, what + ".process must be 'hot' or 'cold'");
}

/// {"shape": "circle", "diameter"} | {"shape": "chs", "d", "t", "process"?} |
/// {"shape": "rhs", "h", "b", "t", "process"?} (sections/sections.h).
fem::FrameSection shaped_section(const json& s, const std::string& name, const std::string& what,
                                 const std::string& subject) {
  sections::Section profile;
  if (s["shape"] == "circle") {
    profile = sections::bar(dim(s, "diameter", what, subject));
    if (!(profile.h > 0)) throw Error(subject, what + ": diameter must be > 0");
    return fem::circle_section(profile.h, name);
  }
  if (s["shape"] == "chs") {
    profile = sections::chs(dim(s, "d", what, subject), dim(s, "t", what, subject),
                            process_of(s, what, subject));
  } else if (s["shape"] == "rhs") {
    profile = sections::rhs(dim(s, "h", what, subject), dim(s, "b", what, subject),
                            dim(s, "t", what, subject), process_of(s, what, subject));
  } else {
    throw Error(subject, what + ": shape must be 'circle', 'chs' or 'rhs'");
  }
  try {
    sections::validate(profile, what);
  } catch (const Error& e) {
    throw Error(subject, e.message());
  }
  return fem::profile_section(profile, name);
}

/// "sections": {NAME: {"shape": …} (shaped_section) or {"A", "Iy", "Iz", "J"}, "up"?}.
NameIndex read_sections(const json& j, const std::string& subject, fem::FrameModel& m) {
  NameIndex sections;
  if (!j.contains("sections") || !j["sections"].is_object())
    throw Error(subject, "'sections' must be an object of named sections");
  for (const auto& [name, s] : j["sections"].items()) {
    const std::string what = fmt::format("sections.{}", name);
    if (!s.is_object()) throw Error(subject, what + " must be an object");
    fem::FrameSection sec;
    if (s.contains("shape")) {
      sec = shaped_section(s, name, what, subject);
    } else {
      for (const char* k : {"A", "Iy", "Iz", "J"})
        if (!s.contains(k)) throw Error(subject, what + fmt::format(": missing '{}'", k));
      sec.A = num(s["A"], what + ".A", subject);
      sec.Iy = num(s["Iy"], what + ".Iy", subject);
      sec.Iz = num(s["Iz"], what + ".Iz", subject);
      sec.J = num(s["J"], what + ".J", subject);
      if (s.contains("c")) sec.c = num(s["c"], what + ".c", subject);
    }
    if (s.contains("up")) sec.up = vec3(s["up"], what + ".up", subject);
    sec.name = name;
    sections[name] = static_cast<int>(m.sections.size());
    m.sections.push_back(sec);
  }
  return sections;
}

/// "materials": {NAME: {"E", "nu" (0.3), "density" (0), "fy" (Pa; absent: --steel's)}}.
NameIndex read_materials(const json& j, const std::string& subject, fem::FrameModel& m) {
  NameIndex materials;
  if (!j.contains("materials") || !j["materials"].is_object())
    throw Error(subject, "'materials' must be an object of named materials");
  for (const auto& [name, s] : j["materials"].items()) {
    const std::string what = fmt::format("materials.{}", name);
    if (!s.is_object() || !s.contains("E")) throw Error(subject, what + " needs 'E'");
    fem::FrameMaterial mat;
    mat.name = name;
    mat.E = num(s["E"], what + ".E", subject);
    mat.nu = s.contains("nu") ? num(s["nu"], what + ".nu", subject) : 0.3;
    mat.density = s.contains("density") ? num(s["density"], what + ".density", subject) : 0.0;
    if (s.contains("fy")) {
      mat.fy = num(s["fy"], what + ".fy", subject);
      if (!(mat.fy > 0)) throw Error(subject, what + ".fy must be a yield strength > 0 (Pa)");
    }
    materials[name] = static_cast<int>(m.materials.size());
    m.materials.push_back(mat);
  }
  return materials;
}

/// A member's section or material: the named one, or the only one there is.
int pick_name(const json& mj, const char* key, const NameIndex& names, const std::string& what,
              const std::string& subject) {
  if (!mj.contains(key)) {
    if (names.size() == 1) return names.begin()->second;
    throw Error(subject, what + fmt::format(" needs '{}'", key));
  }
  if (!mj[key].is_string()) throw Error(subject, what + fmt::format(".{} must be a name", key));
  const auto it = names.find(mj[key].get<std::string>());
  if (it == names.end())
    throw Error(subject, what + fmt::format(": unknown {} '{}'", key, mj[key].get<std::string>()));
  return it->second;
}

/// "members": [{"nodes": [i, j], "section"?, "material"?, "type"?, "elements"?, "up"?}].
void read_members(const json& j, const std::string& subject, const NameIndex& sections,
                  const NameIndex& materials, int default_elements, fem::FrameModel& m) {
  if (!j.contains("members") || !j["members"].is_array() || j["members"].empty())
    throw Error(subject, "'members' must be a non-empty list");
  for (size_t k = 0; k < j["members"].size(); ++k) {
    const json& mj = j["members"][k];
    const std::string what = fmt::format("members[{}]", k);
    if (!mj.is_object() || !mj.contains("nodes") || !mj["nodes"].is_array() ||
        mj["nodes"].size() != 2)
      throw Error(subject, what + " needs \"nodes\": [i, j]");
    fem::FrameMember mb;
    mb.i = index(mj["nodes"][0], what + ".nodes", subject);
    mb.j = index(mj["nodes"][1], what + ".nodes", subject);
    mb.section = pick_name(mj, "section", sections, what, subject);
    mb.material = pick_name(mj, "material", materials, what, subject);
    if (mj.contains("type")) {
      if (mj["type"] == "truss") {
        mb.type = fem::MemberType::truss;
      } else if (mj["type"] == "beam") {
        mb.type = fem::MemberType::beam;
      } else {
        throw Error(subject, what + ": type must be 'beam' or 'truss'");
      }
    }
    mb.elements = mj.contains("elements") ? index(mj["elements"], what + ".elements", subject)
                                          : default_elements;
    if (mb.type == fem::MemberType::truss) mb.elements = 1;
    if (mj.contains("up")) mb.up = vec3(mj["up"], what + ".up", subject);
    m.members.push_back(mb);
  }
}

/// "supports": [{"node", "fix": [dof names]}]; without "fix" a support is pinned.
void read_supports(const json& j, const std::string& subject, fem::FrameModel& m) {
  static const char* kNames[6] = {"ux", "uy", "uz", "rx", "ry", "rz"};
  if (!j["supports"].is_array()) throw Error(subject, "'supports' must be a list");
  for (const auto& sj : j["supports"]) {
    if (!sj.is_object() || !sj.contains("node")) throw Error(subject, "a support needs 'node'");
    fem::FrameSupport s;
    s.node = index(sj["node"], "supports.node", subject);
    if (sj.contains("fix")) {
      if (!sj["fix"].is_array()) throw Error(subject, "supports.fix must be a list");
      for (const auto& f : sj["fix"]) {
        bool found = false;
        for (int c = 0; c < 6; ++c)
          if (f.is_string() && f.get<std::string>() == kNames[c]) s.fix[c] = found = true;
        if (!found) throw Error(subject, "supports.fix: unknown dof (use ux uy uz rx ry rz)");
      }
    } else {
      s.fix = {true, true, true, false, false, false};  // pinned
    }
    m.supports.push_back(s);
  }
}

/// A surface (per area) or projected (per plan area) load q spread over the faces' nodes.
void add_face_load(const fem::FrameModel& m, const Vec3& q, bool projected, std::vector<Vec3>& F) {
  for (const auto& f : m.faces) {
    Vec3 va = Vec3::Zero();
    for (size_t c = 0; c < f.size(); ++c)
      va += m.nodes.row(f[c]).transpose().cross(m.nodes.row(f[(c + 1) % f.size()]).transpose());
    va *= 0.5;
    const double area = projected ? std::abs(va.z()) : va.norm();
    for (int v : f) F[v] += q * (area / static_cast<double>(f.size()));
  }
}

/// Each member's weight A ρ g L, half to each end node.
void add_self_weight(const fem::FrameModel& m, double g, std::vector<Vec3>& F) {
  for (size_t k = 0; k < m.members.size(); ++k) {
    const auto& mb = m.members[k];
    const double w = m.sections[mb.section].A * m.materials[mb.material].density * g *
                     fem::member_length(m, static_cast<int>(k));
    F[mb.i].z() -= 0.5 * w;
    F[mb.j].z() -= 0.5 * w;
  }
}

/// Nodal forces and moments per node (a load case before it becomes FrameModel::loads).
struct NodalSums {
  std::vector<Vec3> F, M;
};

/// A list of nodal, surface, projected and self_weight loads (MODEL.json's "loads" or a load
/// case's), summed per node (needs validated references: faces, sections, materials).
NodalSums sum_loads(const json& list, const std::string& what, const std::string& subject,
                    const fem::FrameModel& m) {
  const int n = m.num_nodes();
  if (!list.is_array()) throw Error(subject, fmt::format("'{}' must be a list", what));
  NodalSums out{std::vector<Vec3>(n, Vec3::Zero()), std::vector<Vec3>(n, Vec3::Zero())};
  std::vector<Vec3>&F = out.F, &M = out.M;
  for (const auto& lj : list) {
    if (!lj.is_object()) throw Error(subject, "a load must be an object");
    const std::string type = lj.contains("type") && lj["type"].is_string()
                                 ? lj["type"].get<std::string>()
                                 : std::string("nodal");
    if (type == "nodal") {
      if (!lj.contains("node")) throw Error(subject, "a nodal load needs 'node'");
      const int v = index(lj["node"], "loads.node", subject);
      if (v < 0 || v >= n) throw Error(subject, fmt::format("a load refers to node {}", v));
      if (lj.contains("force")) F[v] += vec3(lj["force"], "loads.force", subject);
      if (lj.contains("moment")) M[v] += vec3(lj["moment"], "loads.moment", subject);
    } else if (type == "surface" || type == "projected") {
      if (m.faces.empty())
        throw Error(subject, "a " + type + " load needs 'faces' (or 'triangles')");
      add_face_load(m, vec3(lj.value("q", json()), "loads.q", subject), type == "projected", F);
    } else if (type == "self_weight") {
      add_self_weight(m, lj.contains("g") ? num(lj["g"], "loads.g", subject) : 9.81, F);
    } else {
      throw Error(subject, "unknown load type '" + type + "'");
    }
  }
  return out;
}

/// The model's nodal loads from per-node sums (only loaded nodes).
std::vector<fem::NodalLoad> nodal_loads(const NodalSums& s) {
  std::vector<fem::NodalLoad> out;
  for (int v = 0; v < static_cast<int>(s.F.size()); ++v)
    if (s.F[v].squaredNorm() > 0 || s.M[v].squaredNorm() > 0) out.push_back({v, s.F[v], s.M[v]});
  return out;
}

/// "load_cases": {NAME: {"type": "permanent" | "variable", "loads": [...]}} and "combinations":
/// {NAME: {CASE: factor}} (absent: ULS = 1.35 Σ permanent + 1.5 Σ variable, SLS = Σ all, as
/// `design --loads eurocode`). Fills `out`'s combinations, each with its nodal loads.
void read_load_cases(const json& j, const std::string& subject, const fem::FrameModel& m,
                     FrameModelFile& out) {
  const json& cj = j["load_cases"];
  if (!cj.is_object() || cj.empty())
    throw Error(subject, "'load_cases' must be an object of named load cases");
  std::map<std::string, NodalSums> cases;
  std::map<std::string, bool> permanent;
  for (const auto& [name, c] : cj.items()) {
    const std::string what = "load_cases." + name;
    if (!c.is_object() || !c.contains("loads") || !c.contains("type"))
      throw Error(subject, what + " needs 'type' (permanent | variable) and 'loads'");
    if (c["type"] != "permanent" && c["type"] != "variable")
      throw Error(subject, what + ".type must be 'permanent' or 'variable'");
    permanent[name] = c["type"] == "permanent";
    cases[name] = sum_loads(c["loads"], what + ".loads", subject, m);
    out.load_cases.push_back({name, permanent[name] ? "permanent" : "variable"});
  }
  json comb = j.contains("combinations") ? j["combinations"] : json();
  if (comb.is_null()) {
    for (const auto& [name, p] : permanent) {
      comb["ULS"][name] = p ? 1.35 : 1.5;
      comb["SLS"][name] = 1.0;
    }
  }
  if (!comb.is_object() || comb.empty())
    throw Error(subject, "'combinations' must be an object of named combinations");
  const int n = m.num_nodes();
  for (const auto& [name, factors] : comb.items()) {
    const std::string what = "combinations." + name;
    if (!factors.is_object() || factors.empty())
      throw Error(subject, what + " must be an object {load case: factor}");
    ModelCombination c;
    c.name = name;
    NodalSums sum{std::vector<Vec3>(n, Vec3::Zero()), std::vector<Vec3>(n, Vec3::Zero())};
    for (const auto& [case_name, f] : factors.items()) {
      const auto it = cases.find(case_name);
      if (it == cases.end())
        throw Error(subject, fmt::format("{}: unknown load case '{}'", what, case_name));
      const std::string key = fmt::format("{}.{}", what, case_name);
      const double factor = num(f, key, subject);
      if (!(factor >= 0)) throw Error(subject, key + " must be >= 0");
      c.factors.emplace_back(case_name, factor);
      for (int v = 0; v < n; ++v) {
        sum.F[v] += factor * it->second.F[v];
        sum.M[v] += factor * it->second.M[v];
      }
    }
    c.loads = nodal_loads(sum);
    if (c.loads.empty()) throw Error(subject, what + " has no load");
    out.combinations.push_back(std::move(c));
  }
  // The primary combination (the model's loads, the one analysed in full): ULS, else the first.
  std::stable_partition(out.combinations.begin(), out.combinations.end(),
                        [](const ModelCombination& c) { return c.name == "ULS"; });
}

/// "analysis": {"linear", "buckling", "nonlinear": true/false, "nonlinear_static": factor,
/// "stop_displacement", "stop_lambda", "max_steps"}.
void read_analysis(const json& a, const std::string& subject, ModelAnalysisRequest& out) {
  if (!a.is_object()) throw Error(subject, "'analysis' must be an object");
  auto flag = [&](const char* key, std::optional<bool>& dst) {
    if (!a.contains(key)) return;
    if (!a[key].is_boolean())
      throw Error(subject, fmt::format("analysis.{} must be true/false", key));
    dst = a[key].get<bool>();
  };
  flag("linear", out.linear);
  flag("buckling", out.buckling);
  flag("nonlinear", out.nonlinear);
  if (a.contains("nonlinear_static")) {
    const double f = num(a["nonlinear_static"], "analysis.nonlinear_static", subject);
    if (!(f > 0)) throw Error(subject, "analysis.nonlinear_static must be > 0");
    out.nonlinear_static = f;
  }
  for (const auto& [key, dst] : {std::pair{"stop_displacement", &out.stop_displacement},
                                 std::pair{"stop_lambda", &out.stop_lambda}}) {
    if (!a.contains(key)) continue;
    const double v = num(a[key], fmt::format("analysis.{}", key), subject);
    if (!(v > 0)) throw Error(subject, fmt::format("analysis.{} must be > 0", key));
    *dst = v;
  }
  if (a.contains("max_steps")) {
    const int n = index(a["max_steps"], "analysis.max_steps", subject);
    if (n < 1 || n > 100000) throw Error(subject, "analysis.max_steps must be in 1..100000");
    out.max_steps = n;
  }
}

}  // namespace

FrameModelFile parse_frame_model(const std::string& text, const std::string& subject,
                                 int default_elements) {
  json j;
  try {
    j = parse_json(text, subject);
  } catch (const json::exception& e) {
    throw Error(subject, std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object()) throw Error(subject, "the model must be a JSON object");
  FrameModelFile out;
  fem::FrameModel& m = out.model;
  read_nodes(j, subject, m);
  const NameIndex sections = read_sections(j, subject, m);
  const NameIndex materials = read_materials(j, subject, m);
  read_members(j, subject, sections, materials, default_elements, m);
  if (j.contains("faces")) m.faces = polygons(j["faces"], "faces", subject);
  if (j.contains("triangles") && m.faces.empty())
    m.faces = polygons(j["triangles"], "triangles", subject);
  if (j.contains("supports")) read_supports(j, subject, m);
  // Validate references before the derived loads use them.
  fem::FrameModel check = m;
  fem::validate(check, subject);
  if (j.contains("loads") && j.contains("load_cases"))
    throw Error(subject, "give either 'loads' or 'load_cases' (with 'combinations')");
  if (j.contains("combinations") && !j.contains("load_cases"))
    throw Error(subject, "'combinations' need 'load_cases'");
  if (j.contains("loads")) m.loads = nodal_loads(sum_loads(j["loads"], "loads", subject, m));
  if (j.contains("load_cases")) {
    read_load_cases(j, subject, m, out);
    m.loads = out.combinations.front().loads;
  }
  if (j.contains("analysis")) read_analysis(j["analysis"], subject, out.analysis);
  fem::validate(m, subject);
  return out;
}

namespace {
json nodal_loads_json(const std::vector<fem::NodalLoad>& loads) {
  json list = json::array();
  for (const fem::NodalLoad& l : loads) {
    json lj{{"node", l.node}, {"force", {l.force.x(), l.force.y(), l.force.z()}}};
    if (l.moment.squaredNorm() > 0) lj["moment"] = {l.moment.x(), l.moment.y(), l.moment.z()};
    list.push_back(lj);
  }
  return list;
}
}  // namespace

nlohmann::json frame_model_to_json(
    const fem::FrameModel& m, const std::vector<NodalLoadCase>& cases,
    const std::vector<std::pair<std::string, std::vector<std::pair<std::string, double>>>>&
        combinations) {
  static const char* kDofs[6] = {"ux", "uy", "uz", "rx", "ry", "rz"};
  json j;
  j["nodes"] = json::array();
  for (int v = 0; v < m.num_nodes(); ++v) j["nodes"].push_back({m.nodes(v, 0), m.nodes(v, 1), m.nodes(v, 2)});
  j["members"] = json::array();
  for (const fem::FrameMember& mb : m.members) {
    json mj{{"nodes", {mb.i, mb.j}},
            {"section", m.sections[mb.section].name},
            {"material", m.materials[mb.material].name}};
    if (mb.up.squaredNorm() > 0) mj["up"] = {mb.up.x(), mb.up.y(), mb.up.z()};
    if (mb.type == fem::MemberType::truss) {
      mj["type"] = "truss";
    } else {
      mj["elements"] = mb.elements;
    }
    j["members"].push_back(mj);
  }
  j["sections"] = json::object();
  for (const fem::FrameSection& s : m.sections) j["sections"][s.name] = section_to_json(s);
  j["materials"] = json::object();
  for (const fem::FrameMaterial& mat : m.materials) {
    json mj{{"E", mat.E}, {"nu", mat.nu}, {"density", mat.density}};
    if (mat.fy > 0) mj["fy"] = mat.fy;
    j["materials"][mat.name] = mj;
  }
  j["supports"] = json::array();
  for (const fem::FrameSupport& s : m.supports) {
    json fix = json::array();
    for (int c = 0; c < 6; ++c)
      if (s.fix[c]) fix.push_back(kDofs[c]);
    j["supports"].push_back({{"node", s.node}, {"fix", fix}});
  }
  if (!m.faces.empty()) j["faces"] = m.faces;
  if (cases.empty()) {
    j["loads"] = nodal_loads_json(m.loads);
    return j;
  }
  for (const NodalLoadCase& c : cases)
    j["load_cases"][c.name] = {{"type", c.permanent ? "permanent" : "variable"},
                               {"loads", nodal_loads_json(c.loads)}};
  for (const auto& [name, factors] : combinations)
    for (const auto& [case_name, f] : factors) j["combinations"][name][case_name] = f;
  return j;
}

FrameModelFile read_frame_model(const std::filesystem::path& path, int default_elements) {
  return parse_frame_model(read_file(path), path.string(), default_elements);
}

std::vector<int> read_obj_supports_comment(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string(), "cannot open");
  std::string line;
  std::vector<int> ids;
  while (std::getline(in, line)) {
    if (line.rfind("# supports", 0) != 0) continue;
    std::istringstream ss(line.substr(10));
    std::string tok;
    while (ss >> tok) {
      try {
        size_t pos = 0;
        const int v = std::stoi(tok, &pos);
        if (pos != tok.size() || v < 0) throw std::invalid_argument(tok);
        ids.push_back(v);
      } catch (const std::exception&) {
        throw Error(path.string(), "malformed '# supports' line: '" + tok + "'");
      }
    }
  }
  return ids;
}

nlohmann::json section_to_json(const fem::FrameSection& s) {
  json j;
  const auto& p = s.profile;
  if (p && p->shape == sections::Shape::bar) {
    j = {{"shape", "circle"}, {"diameter", p->h}};
  } else if (p && p->shape == sections::Shape::chs) {
    j = {{"shape", "chs"}, {"d", p->h}, {"t", p->t}, {"process", sections::to_string(p->process)}};
  } else if (p && p->shape == sections::Shape::rhs) {
    j = {{"shape", "rhs"},
         {"h", p->h},
         {"b", p->b},
         {"t", p->t},
         {"process", sections::to_string(p->process)}};
  } else {
    j = {{"A", s.A}, {"Iy", s.Iy}, {"Iz", s.Iz}, {"J", s.J}};
    if (s.c > 0) j["c"] = s.c;
  }
  if (s.up.squaredNorm() > 0) j["up"] = {s.up.x(), s.up.y(), s.up.z()};
  return j;
}

}  // namespace gridshell::io
