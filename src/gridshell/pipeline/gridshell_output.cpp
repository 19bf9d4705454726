#include "gridshell/pipeline/gridshell_output.h"

#include <cmath>

#include <fmt/format.h>

#include "gridshell/io/files.h"
#include "gridshell/mesh/overlaps.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

PolyStats poly_stats(const PolyMesh& mesh) {
  PolyStats s;
  const Topology t = build_topology(mesh);
  s.vertices = mesh.num_vertices();
  s.faces = mesh.num_faces();
  s.edges = t.num_edges();
  s.boundary_loops = static_cast<int>(t.boundary_loops.size());
  s.euler = euler_characteristic(mesh, t);
  s.overlaps = find_overlaps(mesh, t).count();
  double sum = 0, sum2 = 0;
  s.min_edge = 1e300;
  for (const auto& e : t.edges) {
    const double l = (mesh.vertex(e[0]) - mesh.vertex(e[1])).norm();
    sum += l, sum2 += l * l;
    s.min_edge = std::min(s.min_edge, l), s.max_edge = std::max(s.max_edge, l);
  }
  const double n = std::max(1, s.edges);
  s.total_length = sum;
  const double mean = sum / n;
  s.edge_length_cv = mean > 0 ? std::sqrt(std::max(0.0, sum2 / n - mean * mean)) / mean : 0;
  if (s.edges == 0) s.min_edge = 0;
  int interior_faces = 0, hexes = 0;
  for (const auto& f : mesh.faces) {
    ++s.face_sides[static_cast<int>(f.size())];
    bool inner = true;
    for (int v : f) inner &= !t.on_boundary[v];
    if (inner) ++interior_faces, hexes += f.size() == 6;
  }
  int interior_vertices = 0, val3 = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (t.on_boundary[v] || t.vertex_faces[v].empty()) continue;
    ++interior_vertices;
    val3 += t.vertex_neighbors[v].size() == 3;
  }
  s.hex_share_interior = interior_faces ? static_cast<double>(hexes) / interior_faces : 0;
  s.valence3_share_interior = interior_vertices ? static_cast<double>(val3) / interior_vertices : 0;
  return s;
}

namespace {
double mean_of(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / v.size();
}
}  // namespace

nlohmann::json mesh_block(const GridShellOutput& out) {
  const PolyStats s = poly_stats(out.mesh);
  nlohmann::json j;
  j["vertices"] = s.vertices;
  j["faces"] = s.faces;
  j["edges"] = s.edges;
  j["total_length_m"] = s.total_length;
  nlohmann::json sides = nlohmann::json::object();
  for (const auto& [k, v] : s.face_sides) sides[std::to_string(k)] = v;
  j["face_sides"] = sides;
  j["edge_length_cv"] = s.edge_length_cv;
  j["edge_length_min_m"] = s.min_edge;
  j["edge_length_max_m"] = s.max_edge;
  j["hex_share_interior"] = s.hex_share_interior;
  j["valence3_share_interior"] = s.valence3_share_interior;
  j["boundary_loops"] = s.boundary_loops;
  j["euler_characteristic"] = s.euler;
  j["overlaps"] = s.overlaps;
  j["supports"] = out.supports.size();
  j["support_joints"] = out.supports;
  if (!out.planarity.empty()) j["planarity_mean"] = mean_of(out.planarity);
  if (!out.regularity.empty()) j["regularity_mean"] = mean_of(out.regularity);
  return j;
}

void write_gridshell_files(const std::filesystem::path& dir, const GridShellOutput& out) {
  io::write_obj(dir / "gridshell.obj", out.mesh, out.supports);
  io::write_obj(dir / "gridshell_raw.obj", out.raw.num_faces() ? out.raw : out.mesh, out.supports);
  io::write_ply(dir / "gridshell.ply", out.mesh, out.supports, false);
  const int nf = out.mesh.num_faces();
  auto per_face = [&](const std::vector<double>& v, std::size_t f) {
    return v.size() == static_cast<std::size_t>(nf) ? v[f] : 1.0;
  };
  std::string csv = "face,sides,area,d_target,a_target";
  const bool metrics = out.planarity.size() == static_cast<std::size_t>(nf) &&
                       out.regularity.size() == static_cast<std::size_t>(nf);
  if (metrics) csv += ",planarity,regularity";
  csv += "\n";
  for (int f = 0; f < nf; ++f) {
    csv += fmt::format(
        "{},{},{},{},{}", f, out.mesh.faces[f].size(), io::format_number(polygon_area(out.mesh, f)),
        io::format_number(per_face(out.d_target, f)), io::format_number(per_face(out.a_target, f)));
    if (metrics)
      csv += fmt::format(",{},{}", io::format_number(out.planarity[f]),
                         io::format_number(out.regularity[f]));
    csv += "\n";
  }
  io::write_file_atomic(dir / "cells.csv", csv);
  write_gridshell_vtp(dir, out);
}

void add_structure(GridShellOutput& out, const analysis::FrameResult& structure) {
  out.beam_axial_force = structure.axial_force;
  out.joint_displacement = structure.displacement.topRows(
      std::min<Eigen::Index>(structure.displacement.rows(), out.mesh.num_vertices()));
}

void write_gridshell_vtp(const std::filesystem::path& dir, const GridShellOutput& out) {
  const int nf = out.mesh.num_faces(), nv = out.mesh.num_vertices();
  auto per_face = [&](const std::vector<double>& v, int f) {
    return v.size() == static_cast<std::size_t>(nf) ? v[f] : 1.0;
  };
  io::Attributes panels = out.extra_cell_data, points = out.extra_point_data, beams;
  Eigen::MatrixXd id(nf, 1), sides(nf, 1), area(nf, 1), d(nf, 1), a(nf, 1);
  for (int f = 0; f < nf; ++f) {
    id(f, 0) = f;
    sides(f, 0) = static_cast<double>(out.mesh.faces[f].size());
    area(f, 0) = polygon_area(out.mesh, f);
    d(f, 0) = per_face(out.d_target, f);
    a(f, 0) = per_face(out.a_target, f);
  }
  panels["panel_id"] = id;
  panels["sides"] = sides;
  panels["area"] = area;
  panels["d_target"] = d;
  panels["a_target"] = a;
  if (out.planarity.size() == static_cast<std::size_t>(nf) &&
      out.regularity.size() == static_cast<std::size_t>(nf)) {
    panels["planarity"] = Eigen::Map<const Eigen::VectorXd>(out.planarity.data(), nf);
    panels["regularity"] = Eigen::Map<const Eigen::VectorXd>(out.regularity.data(), nf);
  }
  const Topology t = build_topology(out.mesh);
  const int ne = t.num_edges();
  Eigen::MatrixXd beam_id(ne, 1), length(ne, 1);
  for (int e = 0; e < ne; ++e) {
    beam_id(e, 0) = e;
    length(e, 0) = (out.mesh.vertex(t.edges[e][0]) - out.mesh.vertex(t.edges[e][1])).norm();
  }
  beams["beam_id"] = beam_id;
  beams["length"] = length;
  if (out.beam_axial_force.size() == static_cast<std::size_t>(ne))
    beams["axial_force"] = Eigen::Map<const Eigen::VectorXd>(out.beam_axial_force.data(), ne);
  Eigen::MatrixXd joint_id(nv, 1), support = Eigen::MatrixXd::Zero(nv, 1);
  for (int v = 0; v < nv; ++v) joint_id(v, 0) = v;
  for (int v : out.supports) support(v, 0) = 1;
  points["joint_id"] = joint_id;
  points["support"] = support;
  if (out.joint_displacement.rows() == nv) points["displacement"] = out.joint_displacement;
  io::write_vtp_beams_and_panels(dir / "gridshell.vtp", out.mesh, t.edges, points, beams, panels);
}

}  // namespace gridshell
