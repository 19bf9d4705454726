// gridshell info SURFACE [--json]: counts, extent, area, Euler characteristic, overlaps, validity.

#include <iostream>

#include <fmt/format.h>

#include "common.h"
#include "gridshell/mesh/overlaps.h"
#include "gridshell/mesh/topology.h"

namespace gridshell::app {

namespace {

struct InfoArgs {
  std::string surface;
  SurfaceOptions surface_options;
  bool json = false;
};

int run_info(const InfoArgs& a) {
  PolySurface s = load_poly_surface(a.surface, a.surface_options);
  const Topology topo = build_topology(s.mesh);
  const MeshProblems problems = check_mesh(s.mesh);
  double area = 0;
  for (int f = 0; f < s.mesh.num_faces(); ++f) area += polygon_area(s.mesh, f);
  const Eigen::RowVector3d lo = s.mesh.V.colwise().minCoeff(), hi = s.mesh.V.colwise().maxCoeff();
  std::map<std::string, int> sides;
  for (const auto& f : s.mesh.faces) ++sides[std::to_string(f.size())];
  const int euler = euler_characteristic(s.mesh, topo);
  const int overlaps = find_overlaps(s.mesh, topo).count();
  if (a.json) {
    nlohmann::json j;
    j["file"] = a.surface;
    j["vertices"] = s.mesh.num_vertices();
    j["faces"] = s.mesh.num_faces();
    j["edges"] = topo.num_edges();
    j["boundary_loops"] = topo.boundary_loops.size();
    j["supports"] = s.supports.size();
    j["support_vertices"] = s.supports;
    j["bbox"] = {{"min", {lo(0), lo(1), lo(2)}}, {"max", {hi(0), hi(1), hi(2)}}};
    j["extent"] = {hi(0) - lo(0), hi(1) - lo(1), hi(2) - lo(2)};
    j["area"] = area;
    j["euler_characteristic"] = euler;
    j["face_sides"] = sides;
    j["overlaps"] = overlaps;
    j["problems"] = problems.describe();
    j["valid"] = problems.ok();
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << fmt::format("{}\n", a.surface);
    std::cout << fmt::format("  vertices        {}\n  faces           {}\n  edges           {}\n",
                             s.mesh.num_vertices(), s.mesh.num_faces(), topo.num_edges());
    std::cout << fmt::format("  boundary loops  {}\n  supports        {}\n",
                             topo.boundary_loops.size(), s.supports.size());
    std::cout << fmt::format(
        "  bbox            [{:.4g}, {:.4g}, {:.4g}] – [{:.4g}, {:.4g}, {:.4g}]\n", lo(0), lo(1),
        lo(2), hi(0), hi(1), hi(2));
    std::cout << fmt::format("  extent          {:.4g} x {:.4g} x {:.4g}\n", hi(0) - lo(0),
                             hi(1) - lo(1), hi(2) - lo(2));
    std::cout << fmt::format("  area            {:.6g}\n  Euler char.     {}\n", area, euler);
    std::string fs;
    for (const auto& [k, v] : sides) fs += fmt::format(" {}-gons: {}", k, v);
    std::cout << "  faces by sides " << fs << "\n";
    std::cout << fmt::format("  overlaps        {} (beams that cross, joints inside a face)\n",
                             overlaps);
    if (problems.ok()) {
      std::cout << "  validity        no problems found\n";
    } else {
      for (const auto& p : problems.describe()) std::cout << "  problem         " << p << "\n";
    }
  }
  return 0;
}

}  // namespace

void register_info(CLI::App& app, Action& action) {
  auto a = std::make_shared<InfoArgs>();
  CLI::App* sub = app.add_subcommand(
      "info", "Counts, extent, area, Euler characteristic and validity problems of a surface");
  sub->add_option("surface", a->surface, "PLY/OBJ/OFF file or builtin:NAME")->required();
  sub->add_flag("--json", a->json, "print JSON instead of text");
  add_surface_options(sub, a->surface_options);
  sub->callback([a, &action] { action = [a] { return run_info(*a); }; });
}

}  // namespace gridshell::app
