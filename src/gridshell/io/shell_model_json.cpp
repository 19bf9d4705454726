// MODEL.json → ShellModel. See shell_model_json.h.

#include "gridshell/io/shell_model_json.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/io/json.h"

namespace gridshell::io {

namespace {

using nlohmann::json;

double number(const json& j, const std::string& subject, const std::string& where) {
  if (!j.is_number() || !std::isfinite(j.get<double>()))
    throw Error(subject, where + " must be a finite number");
  return j.get<double>();
}

Vec3 vec3(const json& j, const std::string& subject, const std::string& where) {
  if (!j.is_array() || j.size() != 3) throw Error(subject, where + " must be [x, y, z]");
  return Vec3(number(j[0], subject, where), number(j[1], subject, where),
              number(j[2], subject, where));
}

int index(const json& j, int n, const std::string& subject, const std::string& where) {
  if (!j.is_number_integer()) throw Error(subject, where + " must be an integer node index");
  // Compared as JSON stores it (ids beyond 2^63 are unsigned), never wrapped into range.
  const bool in_range = j.is_number_unsigned()
                            ? j.get<std::uint64_t>() < static_cast<std::uint64_t>(n)
                            : j.get<std::int64_t>() >= 0 && j.get<std::int64_t>() < n;
  if (!in_range)
    throw Error(subject,
                fmt::format("{} refers to node {}, but there are {} nodes", where, j.dump(), n));
  return static_cast<int>(j.get<std::int64_t>());
}

}  // namespace

bool is_model_json(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".json";
}

namespace {

/// "triangles": [[i, j, k]] or, without them, polygon "faces" split into fans.
std::vector<std::array<int, 3>> read_triangles(const json& j, int n, const std::string& s) {
  std::vector<std::array<int, 3>> tris;
  if (j.contains("triangles")) {
    if (!j["triangles"].is_array()) throw Error(s, "'triangles' must be a list");
    for (std::size_t f = 0; f < j["triangles"].size(); ++f) {
      const json& t = j["triangles"][f];
      const std::string w = fmt::format("triangles[{}]", f);
      if (!t.is_array() || t.size() != 3) throw Error(s, w + " must be [i, j, k]");
      tris.push_back({index(t[0], n, s, w), index(t[1], n, s, w), index(t[2], n, s, w)});
    }
  } else if (j.contains("faces") && j["faces"].is_array()) {
    for (std::size_t f = 0; f < j["faces"].size(); ++f) {
      const json& p = j["faces"][f];
      const std::string w = fmt::format("faces[{}]", f);
      if (!p.is_array() || p.size() < 3) throw Error(s, w + " must list at least 3 nodes");
      for (std::size_t k = 1; k + 1 < p.size(); ++k)
        tris.push_back({index(p[0], n, s, w), index(p[k], n, s, w), index(p[k + 1], n, s, w)});
    }
  }
  if (tris.empty()) throw Error(s, "a shell model needs 'triangles' (or polygon 'faces')");
  return tris;
}

/// "materials": {NAME: {"E", "nu"?, "density"?}}; the shell's one is "material" or the only one.
void read_material(const json& j, const std::string& s, fem::ShellModel& model) {
  const json& mats = j["materials"];
  if (!mats.is_object() || mats.empty()) throw Error(s, "'materials' must be a non-empty object");
  std::string name;
  if (j.contains("material") && j["material"].is_string()) {
    name = j["material"].get<std::string>();
    if (!mats.contains(name)) throw Error(s, "material '" + name + "' is not defined");
  } else if (mats.size() == 1) {
    name = mats.begin().key();
  } else {
    throw Error(s, "several materials: name the shell's one with \"material\": \"NAME\"");
  }
  const json& m = mats[name];
  const std::string w = "materials." + name;
  if (!m.contains("E")) throw Error(s, w + " has no E");
  model.material.E = number(m["E"], s, w + ".E");
  if (m.contains("nu")) model.material.nu = number(m["nu"], s, w + ".nu");
  if (m.contains("density")) model.material.density = number(m["density"], s, w + ".density");
  if (!(model.material.E > 0)) throw Error(s, w + ".E must be positive");
  if (!(model.material.nu > -1 && model.material.nu < 0.5))
    throw Error(s, w + ".nu must lie in (-1, 0.5)");
}

/// "supports": [{"node", "fix": "pinned" | "clamped" | "fixed" | [dof names]}] (pinned if absent).
void read_supports(const json& j, int n, const std::string& s, fem::ShellModel& model) {
  if (!j["supports"].is_array()) throw Error(s, "'supports' must be a list");
  static const char* names[6] = {"ux", "uy", "uz", "rx", "ry", "rz"};
  for (std::size_t k = 0; k < j["supports"].size(); ++k) {
    const json& sp = j["supports"][k];
    const std::string w = fmt::format("supports[{}]", k);
    if (!sp.is_object() || !sp.contains("node")) throw Error(s, w + " needs a 'node'");
    const int v = index(sp["node"], n, s, w);
    const json fix = sp.contains("fix") ? sp["fix"] : json("pinned");
    if (fix.is_string()) {
      const std::string kind = fix.get<std::string>();
      if (kind != "pinned" && kind != "clamped" && kind != "fixed")
        throw Error(s, w + ".fix must be a list of dofs, \"pinned\" or \"clamped\"");
      for (int d = 0; d < (kind == "pinned" ? 3 : 6); ++d) model.fixed[v][d] = true;
      continue;
    }
    if (!fix.is_array()) throw Error(s, w + ".fix must be a list of ux uy uz rx ry rz");
    for (const json& d : fix) {
      const auto it = d.is_string()
                          ? std::find(std::begin(names), std::end(names), d.get<std::string>())
                          : std::end(names);
      if (it == std::end(names))
        throw Error(s, w + ".fix: unknown dof " + d.dump() + " (use ux uy uz rx ry rz)");
      model.fixed[v][it - std::begin(names)] = true;
    }
  }
}

/// One entry of "loads": node, surface, projected, pressure or self_weight.
fem::ShellLoad read_load(const json& L, int n, const std::string& s, const std::string& w) {
  using Kind = fem::ShellLoad::Kind;
  if (!L.is_object()) throw Error(s, w + " must be an object");
  fem::ShellLoad load;
  const std::string type = L.contains("type") && L["type"].is_string()
                               ? L["type"].get<std::string>()
                               : std::string(L.contains("node") ? "node" : "");
  if (type == "node") {
    load.kind = Kind::kNode;
    // (const json::operator[] on a missing key is undefined behaviour: ask first)
    if (!L.contains("node")) throw Error(s, w + ": a nodal load needs 'node'");
    load.node = index(L["node"], n, s, w);
    if (L.contains("force")) load.force = vec3(L["force"], s, w + ".force");
    if (L.contains("moment")) load.moment = vec3(L["moment"], s, w + ".moment");
  } else if (type == "surface" || type == "projected") {
    load.kind = type == "surface" ? Kind::kSurface : Kind::kProjected;
    if (!L.contains("q")) throw Error(s, w + " needs q = [qx, qy, qz]");
    load.q = vec3(L["q"], s, w + ".q");
  } else if (type == "pressure") {
    load.kind = Kind::kPressure;
    if (!L.contains("p")) throw Error(s, w + " needs p");
    load.p = number(L["p"], s, w + ".p");
  } else if (type == "self_weight") {
    load.kind = Kind::kSelfWeight;
    if (L.contains("g")) load.g = number(L["g"], s, w + ".g");
  } else {
    throw Error(s, w + ": unknown load type '" + type +
                       "' (node, surface, projected, pressure, self_weight)");
  }
  return load;
}

}  // namespace

fem::ShellModel read_shell_model(const std::filesystem::path& path) {
  const std::string s = path.string();
  json j;
  try {
    j = parse_json(read_file(path), s);
  } catch (const json::exception& e) {
    throw Error(s, std::string("invalid JSON: ") + e.what());
  }
  if (!j.is_object()) throw Error(s, "a model must be a JSON object");
  fem::ShellModel model;

  if (!j.contains("nodes") || !j["nodes"].is_array() || j["nodes"].empty())
    throw Error(s, "missing or empty 'nodes'");
  const int n = static_cast<int>(j["nodes"].size());
  model.mesh.V.resize(n, 3);
  for (int i = 0; i < n; ++i)
    model.mesh.V.row(i) = vec3(j["nodes"][i], s, fmt::format("nodes[{}]", i)).transpose();

  const std::vector<std::array<int, 3>> tris = read_triangles(j, n, s);
  model.mesh.F.resize(static_cast<int>(tris.size()), 3);
  for (int f = 0; f < static_cast<int>(tris.size()); ++f) {
    model.mesh.F.row(f) << tris[f][0], tris[f][1], tris[f][2];
    if (tris[f][0] == tris[f][1] || tris[f][1] == tris[f][2] || tris[f][0] == tris[f][2])
      throw Error(s, fmt::format("triangles[{}] repeats a node", f));
  }

  if (j.contains("thickness")) {
    model.thickness = number(j["thickness"], s, "thickness");
    if (!(model.thickness > 0)) throw Error(s, "thickness must be positive");
  }
  if (j.contains("materials")) read_material(j, s, model);
  model.fixed.assign(n, {false, false, false, false, false, false});
  if (j.contains("supports")) read_supports(j, n, s, model);
  if (j.contains("loads")) {
    if (!j["loads"].is_array()) throw Error(s, "'loads' must be a list");
    for (std::size_t k = 0; k < j["loads"].size(); ++k)
      model.loads.push_back(read_load(j["loads"][k], n, s, fmt::format("loads[{}]", k)));
  }
  return model;
}

}  // namespace gridshell::io
