#include "gridshell/analysis/gridshell_frame.h"

#include "gridshell/core/error.h"
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

fem::FrameModel gridshell_frame(const PolyMesh& mesh, const std::vector<int>& supports,
                                const GridshellFrameOptions& o) {
  if (!(o.diameter > 0)) throw Error("--diameter", "must be > 0");
  if (o.elements < 1) throw Error("--elements", "must be >= 1");
  if (!(o.area_load_kN_m2 >= 0) && !(o.area_load_kN_m2 < 0))
    throw Error("--area-load", "is not a number");
  const Topology topo = build_topology(mesh);
  fem::FrameModel m;
  m.nodes = mesh.V;
  m.faces = mesh.faces;
  m.sections = {fem::circle_section(o.diameter, "bar")};
  m.materials = {{"steel", o.E, o.nu, o.density}};
  for (const auto& e : topo.edges) {
    fem::FrameMember mb;
    mb.i = e[0];
    mb.j = e[1];
    mb.elements = o.elements;
    m.members.push_back(mb);
  }
  for (int s : supports) {
    if (s < 0 || s >= mesh.num_vertices()) throw Error("supports", "a support id is out of range");
    m.supports.push_back({s, {true, true, true, false, false, false}});
  }
  const int n = mesh.num_vertices();
  std::vector<double> fz(n, 0.0);
  const double A = m.sections[0].A;
  const double weight = o.self_weight ? o.density * o.g * A * fem::total_length(m) : 0.0;
  const std::vector<double> trib = tributary_areas(mesh);
  double area = 0;
  for (double t : trib) area += t;
  if (o.self_weight) {
    if (o.self_weight_at_bars || !(area > 0)) {
      for (int k = 0; k < static_cast<int>(m.members.size()); ++k) {
        const double w = o.density * o.g * A * fem::member_length(m, k);
        fz[m.members[k].i] -= 0.5 * w;
        fz[m.members[k].j] -= 0.5 * w;
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
