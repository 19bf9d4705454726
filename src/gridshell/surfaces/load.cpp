#include "gridshell/surfaces/load.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <set>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/io/json.h"
#include "gridshell/io/frame_model_json.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/repair.h"
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

/// The vertex ids of a JSON supports file; ids refer to the file's vertices (0 ≤ id < nv).
std::vector<int> supports_from_json(const std::string& path, int nv) {
  nlohmann::json j;
  try {
    j = io::parse_json(io::read_file(path), path);
  } catch (const nlohmann::json::exception& e) {
    throw Error(path, "not valid JSON (expected a list of vertex ids)");
  }
  if (j.is_object() && j.contains("supports")) j = j["supports"];
  if (!j.is_array()) throw Error(path, "expected a JSON list of vertex ids");
  std::vector<int> out;
  for (const auto& v : j) {
    if (!v.is_number_integer()) throw Error(path, "support ids must be integers");
    const bool in_range = v.is_number_unsigned()
                              ? v.get<std::uint64_t>() < static_cast<std::uint64_t>(nv)
                              : v.get<std::int64_t>() >= 0 && v.get<std::int64_t>() < nv;
    if (!in_range)
      throw Error(
          path, fmt::format("support vertex {} out of range (mesh has {} vertices)", v.dump(), nv));
    out.push_back(static_cast<int>(v.get<std::int64_t>()));
  }
  return out;
}

/// The vertex colours with their counts, rarest first (supports are the rare colour), e.g.
/// "(0,0,255) x4, (200,200,200) x77".
std::string colour_summary(const std::vector<std::array<std::uint8_t, 3>>& colours) {
  std::map<std::array<std::uint8_t, 3>, int> count;
  for (const auto& c : colours) ++count[c];
  std::vector<std::pair<int, std::array<std::uint8_t, 3>>> byfreq;
  for (const auto& [c, n] : count) byfreq.emplace_back(n, c);
  std::sort(byfreq.begin(), byfreq.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second < b.second;  // rarest first
  });
  std::string out;
  for (std::size_t i = 0; i < byfreq.size() && i < 3; ++i) {
    const auto& [n, c] = byfreq[i];
    out += fmt::format("{}({},{},{}) x{}", i ? ", " : "", c[0], c[1], c[2], n);
  }
  if (byfreq.size() > 3) out += ", ...";
  return out;
}

/// File vertex ids → ids after the repair (`new_id` empty: unchanged); dropped ones are left
/// out and counted in `dropped`. Sorted, without repeats.
std::vector<int> remap(const std::vector<int>& ids, const std::vector<int>& new_id, int& dropped) {
  std::vector<int> out;
  dropped = 0;
  for (int v : ids) {
    const int w = new_id.empty() ? v : new_id[v];
    if (w < 0) {
      ++dropped;
    } else {
      out.push_back(w);
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// The supports by the rules of SurfaceOptions::supports. `file` (when the surface comes from a
/// file) gives the colours and `new_id` maps its vertex ids onto `mesh` (see mesh/repair.h);
/// what the caller should hear about is appended to `notes`.
std::vector<int> resolve_supports(const SurfaceOptions& o, const PolyMesh& mesh,
                                  const io::MeshFile* file, const std::vector<int>& new_id,
                                  const std::vector<int>* builtin,
                                  std::vector<std::string>& notes) {
  std::vector<int> red_in_file;
  int near_red = 0;
  if (file)
    for (std::size_t v = 0; v < file->vertex_colors.size(); ++v)
      if (is_support_colour(file->vertex_colors[v])) {
        red_in_file.push_back(static_cast<int>(v));
        const auto& c = file->vertex_colors[v];
        near_red += !(c[0] == 255 && c[1] == 0 && c[2] == 0);
      }
  int red_dropped = 0;
  std::vector<int> red = remap(red_in_file, new_id, red_dropped);
  const bool use_red = o.supports == "red" || (o.supports == "auto" && !red.empty());
  if (use_red) {
    if (red.empty())
      throw Error("--supports", red_dropped > 0 ? "'red' asked for, but the only red vertices "
                                                  "are unreferenced (no face uses them)"
                                                : "'red' asked for, but the surface has no red "
                                                  "vertices (red >= 128, green and blue at "
                                                  "most a quarter of it)");
    if (near_red > 0)
      notes.push_back(fmt::format("{} of the {} red support vertices {} not pure (255,0,0)",
                                  near_red, red_in_file.size(), near_red == 1 ? "is" : "are"));
    if (red_dropped > 0)
      notes.push_back(fmt::format("{} of the dropped vertices {} red (not supports)", red_dropped,
                                  red_dropped == 1 ? "was" : "were"));
    return red;
  }
  if (o.supports == "auto") {
    if (builtin) return *builtin;
    if (file && !file->vertex_colors.empty()) {
      std::set<std::array<std::uint8_t, 3>> distinct(file->vertex_colors.begin(),
                                                     file->vertex_colors.end());
      if (red_dropped > 0)
        notes.push_back("the only red vertices are unreferenced: supports are the whole boundary");
      else if (distinct.size() > 1)
        notes.push_back(
            fmt::format("no red vertices among the colours {}: supports are the "
                        "whole boundary (--supports FILE.json names others)",
                        colour_summary(file->vertex_colors)));
    }
    return boundary_vertices(build_topology(mesh));
  }
  if (o.supports == "boundary") return boundary_vertices(build_topology(mesh));
  const int nv_file = new_id.empty() ? mesh.num_vertices() : static_cast<int>(new_id.size());
  int listed_dropped = 0;
  std::vector<int> listed = remap(supports_from_json(o.supports, nv_file), new_id, listed_dropped);
  if (listed_dropped > 0)
    notes.push_back(fmt::format("{} of the listed supports {} unreferenced (dropped)",
                                listed_dropped, listed_dropped == 1 ? "was" : "were"));
  return listed;
}

/// Repairs a file's mesh (mesh/repair.h), noting what was done; Error when no face is left.
RepairReport repaired(io::MeshFile& file, const std::string& subject,
                      std::vector<std::string>& notes) {
  const RepairReport repair = repair_mesh(file.mesh);
  if (file.mesh.num_faces() == 0)
    throw Error(subject, "no face has an area (every face uses a vertex twice)");
  if (const std::string what = repair.describe(); !what.empty()) notes.push_back(what);
  return repair;
}

/// Error when pieces of the repaired mesh touch at a single corner (mesh/topology.h
/// pinched_vertices): no stage can walk such a vertex's neighbourhood. Names the first one by
/// its number in the file (`new_id`: file → repaired) and its coordinates there.
void refuse_pinched(const std::string& subject, const PolyMesh& mesh,
                    const std::vector<int>& new_id) {
  const std::vector<int> pinched = pinched_vertices(mesh);
  if (pinched.empty()) return;
  const int v = pinched.front();
  int in_file = v;
  for (std::size_t i = 0; i < new_id.size(); ++i)
    if (new_id[i] == v) {
      in_file = static_cast<int>(i);
      break;
    }
  const Vec3 p = mesh.V.row(v).transpose();
  throw Error(
      subject,
      fmt::format("{} where pieces of the surface touch at a single corner (the first at "
                  "{:.6g} {:.6g} {:.6g}, vertex {} counting from 0): the surface must be a "
                  "manifold; join the pieces along an edge or design each from its own "
                  "file",
                  pinched.size() == 1 ? "1 vertex" : fmt::format("{} vertices", pinched.size()),
                  p.x(), p.y(), p.z(), in_file));
}

void warn(const std::string& subject, const std::vector<std::string>& notes) {
  if (notes.empty()) return;
  std::string line;
  for (const auto& n : notes) line += (line.empty() ? "" : "; ") + n;
  spdlog::warn("{}: {}", subject, line);
}

}  // namespace

namespace {

bool obj_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".obj";
}

}  // namespace

PolySurface load_gridshell(const std::string& path, const SurfaceOptions& o) {
  if (path.rfind("builtin:", 0) == 0) return load_poly_surface(path, o);
  PolySurface s;
  std::vector<std::string> notes;
  io::MeshFile file = io::read_mesh(path);
  std::vector<int> comment;
  if (o.supports == "auto" && obj_file(path)) {
    comment = io::read_obj_supports_comment(path);
    for (int v : comment)
      if (v >= file.mesh.num_vertices())
        throw Error(path,
                    fmt::format("'# supports' lists vertex {} of {}", v, file.mesh.num_vertices()));
  }
  const RepairReport repair = repaired(file, path, notes);
  if (comment.empty()) {
    s.supports = resolve_supports(o, file.mesh, &file, repair.new_id, nullptr, notes);
  } else {
    int dropped = 0;
    s.supports = remap(comment, repair.new_id, dropped);
    if (dropped > 0)
      notes.push_back(fmt::format("{} of the '# supports' joints {} unused (dropped)", dropped,
                                  dropped == 1 ? "was" : "were"));
  }
  s.mesh = std::move(file.mesh);
  reorient(s.mesh.V, o.up, o.scale);
  warn(path, notes);
  return s;
}

bool is_support_colour(const std::array<std::uint8_t, 3>& rgb) {
  const int r = rgb[0], g = rgb[1], b = rgb[2];
  return r >= 128 && 4 * g <= r && 4 * b <= r;
}

Surface load_surface(const std::string& spec, const SurfaceOptions& o) {
  Surface s;
  std::vector<std::string> notes;
  if (spec.rfind("builtin:", 0) == 0) {
    Surface b = make_builtin(spec.substr(8));
    // "auto" takes the built-in's own supports: no polygon copy of a mesh of up to 2 M triangles.
    s.supports = o.supports == "auto"
                     ? b.supports
                     : resolve_supports(o, to_poly(b.mesh), nullptr, {}, &b.supports, notes);
    s.mesh = std::move(b.mesh);
  } else {
    io::MeshFile file = io::read_mesh(spec);
    const RepairReport repair = repaired(file, spec, notes);
    if (repair.non_manifold_edges > 0)
      throw Error(spec,
                  fmt::format("{} {} of three or more faces (a fin, or roofs meeting in a T): "
                              "the surface must be a manifold; delete the extra faces or "
                              "design each roof from its own file",
                              repair.non_manifold_edges,
                              repair.non_manifold_edges == 1 ? "edge" : "edges"));
    refuse_pinched(spec, file.mesh, repair.new_id);
    s.mesh = triangulate(file.mesh);
    s.supports = resolve_supports(o, file.mesh, &file, repair.new_id, nullptr, notes);
    if (const int slivers = count_slivers(s.mesh); slivers > 0)
      notes.push_back(fmt::format("kept {} sliver {} (an angle below 1 degree)", slivers,
                                  slivers == 1 ? "triangle" : "triangles"));
  }
  reorient(s.mesh.V, o.up, o.scale);
  if (s.supports.empty()) {
    const bool listed = o.supports != "auto" && o.supports != "red" && o.supports != "boundary";
    throw Error(spec, listed ? "no supports: the --supports list names no vertex of the surface"
                             : "no supports: the surface has no boundary and no red vertices "
                               "(mark the supports red, or name them with --supports FILE.json)");
  }
  if (const double size = bbox_diagonal(s.mesh.V); size > kLargestRoof)
    notes.push_back(fmt::format(
        "the surface is {:.0f} m across (its bounding box's diagonal): if its coordinates are in "
        "millimetres, pass --scale 0.001",
        size));
  if (s.mesh.num_vertices() > 0) {
    const Vec3 extent = (s.mesh.V.colwise().maxCoeff() - s.mesh.V.colwise().minCoeff()).transpose();
    const double narrow = std::min(extent.x(), extent.y());
    if (extent.z() > kTallerThanWide * narrow)
      notes.push_back(fmt::format(
          "the surface is {:.3g} m tall and {:.3g} m wide: if its up axis is not z, pass --up y "
          "(or -y)",
          extent.z(), narrow));
  }
  warn(spec, notes);
  return s;
}

PolySurface load_poly_surface(const std::string& path, const SurfaceOptions& o) {
  PolySurface s;
  std::vector<std::string> notes;
  if (path.rfind("builtin:", 0) == 0) {
    Surface b = make_builtin(path.substr(8));
    s.mesh = to_poly(b.mesh);
    s.supports = resolve_supports(o, s.mesh, nullptr, {}, &b.supports, notes);
  } else {
    io::MeshFile file = io::read_mesh(path);
    s.mesh = file.mesh;
    s.supports = resolve_supports(o, file.mesh, &file, {}, nullptr, notes);
  }
  reorient(s.mesh.V, o.up, o.scale);
  warn(path, notes);
  return s;
}

}  // namespace gridshell
