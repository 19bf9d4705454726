#include "gridshell/surfaces/load.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/surfaces/builtin.h"

namespace gridshell {

namespace {

void reorient(Points& V, const std::string& up, double scale) {
  if (!(std::isfinite(scale) && scale > 0))
    throw Error("--scale", fmt::format("must be a positive number, got {}", scale));
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const double x = V(i, 0), y = V(i, 1), z = V(i, 2);
    if (up == "z") {
    } else if (up == "y") {  // rotate +y onto +z
      V.row(i) << x, -z, y;
    } else if (up == "-y") {  // rotate −y onto +z
      V.row(i) << x, z, -y;
    } else {
      throw Error("--up", fmt::format("'{}' is not one of z, y, -y", up));
    }
  }
  V *= scale;
}

std::vector<int> supports_from_json(const std::string& path, int nv) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(io::read_file(path));
  } catch (const nlohmann::json::exception& e) {
    throw Error(path, "not valid JSON (expected a list of vertex ids)");
  }
  if (j.is_object() && j.contains("supports")) j = j["supports"];
  if (!j.is_array()) throw Error(path, "expected a JSON list of vertex ids");
  std::vector<int> out;
  for (const auto& v : j) {
    if (!v.is_number_integer()) throw Error(path, "support ids must be integers");
    const long long id = v.get<long long>();
    if (id < 0 || id >= nv)
      throw Error(path,
                  fmt::format("support vertex {} out of range (mesh has {} vertices)", id, nv));
    out.push_back(static_cast<int>(id));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<int> boundary_of(const PolyMesh& mesh) {
  Topology t = build_topology(mesh);
  std::vector<int> out;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (t.on_boundary[v]) out.push_back(v);
  return out;
}

std::vector<int> resolve_supports(const SurfaceOptions& o, const PolyMesh& mesh,
                                  const io::MeshFile* file, const std::vector<int>* builtin) {
  std::vector<int> red;
  if (file)
    for (std::size_t v = 0; v < file->vertex_colors.size(); ++v) {
      const auto& c = file->vertex_colors[v];
      if (c[0] == 255 && c[1] == 0 && c[2] == 0) red.push_back(static_cast<int>(v));
    }
  if (o.supports == "auto") {
    if (!red.empty()) return red;
    if (builtin) return *builtin;
    return boundary_of(mesh);
  }
  if (o.supports == "red") {
    if (red.empty())
      throw Error("--supports",
                  "'red' asked for, but the surface has no pure red (255,0,0) vertices");
    return red;
  }
  if (o.supports == "boundary") return boundary_of(mesh);
  return supports_from_json(o.supports, mesh.num_vertices());
}

}  // namespace

Surface load_surface(const std::string& spec, const SurfaceOptions& o) {
  Surface s;
  if (spec.rfind("builtin:", 0) == 0) {
    Surface b = make_builtin(spec.substr(8));
    s.mesh = b.mesh;
    s.supports = resolve_supports(o, to_poly(b.mesh), nullptr, &b.supports);
  } else {
    io::MeshFile file = io::read_mesh(spec);
    s.mesh = triangulate(file.mesh);
    s.supports = resolve_supports(o, file.mesh, &file, nullptr);
  }
  reorient(s.mesh.V, o.up, o.scale);
  return s;
}

PolySurface load_poly_surface(const std::string& path, const SurfaceOptions& o) {
  PolySurface s;
  if (path.rfind("builtin:", 0) == 0) {
    Surface b = make_builtin(path.substr(8));
    s.mesh = to_poly(b.mesh);
    s.supports = resolve_supports(o, s.mesh, nullptr, &b.supports);
  } else {
    io::MeshFile file = io::read_mesh(path);
    s.mesh = file.mesh;
    s.supports = resolve_supports(o, file.mesh, &file, nullptr);
  }
  reorient(s.mesh.V, o.up, o.scale);
  return s;
}

}  // namespace gridshell
