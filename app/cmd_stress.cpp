// gridshell stress SURFACE|MODEL.json -o DIR: linear static analysis of the continuous thin shell
// (flat facet OPT + DKT triangles). Writes displacements.csv, stress.csv, shell.vtp, report.json,
// config.json.

#include <cmath>
#include <filesystem>
#include <limits>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common.h"
#include "gridshell/core/error.h"
#include "gridshell/core/timings.h"
#include "gridshell/fem/shell_solver.h"
#include "gridshell/io/files.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/io/shell_model_json.h"

namespace gridshell::app {

namespace {

struct StressArgs {
  std::string input;
  SurfaceOptions surface_options;
  RunOptions run;
  fem::ShellDefaults defaults;
  double load_kn = 1.0;                                            // kN/m² of plan area
  double support_below = std::numeric_limits<double>::infinity();  // keep supports with z < this
  CLI::Option* opt_thickness = nullptr;
  CLI::Option* opt_E = nullptr;
  CLI::Option* opt_nu = nullptr;
  CLI::Option* opt_density = nullptr;
};

std::string num(double x) {
  return io::format_number(x);
}

int run_stress(const StressArgs& a, const CLI::App* sub) {
  const auto guard = apply_run_options(a.run);
  const Stopwatch total;
  Stopwatch clock;
  if (!(a.load_kn >= 0) || !std::isfinite(a.load_kn))
    throw Error("--load", "must be a finite load ≥ 0 (kN/m² of plan area)");
  if (!(a.defaults.thickness > 0)) throw Error("--thickness", "must be positive");
  if (!(a.defaults.material.E > 0)) throw Error("--E", "must be positive");
  if (!(a.defaults.material.nu > -1 && a.defaults.material.nu < 0.5))
    throw Error("--nu", "must lie in (-1, 0.5)");

  fem::ShellModel model;
  std::string source;
  if (a.input.rfind("builtin:", 0) != 0 && io::is_model_json(a.input)) {
    model = io::read_shell_model(a.input);
    // Explicit command-line values override the model's.
    if (a.opt_thickness->count()) model.thickness = a.defaults.thickness;
    if (a.opt_E->count()) model.material.E = a.defaults.material.E;
    if (a.opt_nu->count()) model.material.nu = a.defaults.material.nu;
    if (a.opt_density->count()) model.material.density = a.defaults.material.density;
    source = "model";
  } else {
    Surface surface = load_surface(a.input, a.surface_options);
    if (std::isfinite(a.support_below)) {
      std::vector<int> kept;
      for (int v : surface.supports)
        if (surface.mesh.V(v, 2) < a.support_below) kept.push_back(v);
      surface.supports = kept;
    }
    if (surface.supports.empty())
      throw Error(a.input, "the surface has no supports (use --supports)");
    fem::ShellDefaults d = a.defaults;
    d.projected_load = a.load_kn * 1e3;
    model = fem::surface_shell_model(surface, d);
    source = "surface";
  }
  Timings timings{{"read", clock.lap()}};
  io::ensure_directory(a.run.out_dir);

  fem::ShellResult r;
  try {
    r = fem::solve_shell(model);
  } catch (const Error& e) {
    throw Error(a.input, e.what());  // name the input file, not the internal "model"
  }

  // The solver's phases; its ordering ran beside the assembly, so its seconds are not added.
  for (const auto& [stage, seconds] : r.timings)
    if (stage != "order") timings.add(stage, seconds);
  clock.lap();
  const std::filesystem::path dir(a.run.out_dir);
  const int n = model.mesh.num_vertices(), nf = model.mesh.num_faces();
  std::string csv = "vertex,ux,uy,uz,rx,ry,rz\n";
  csv.reserve(static_cast<std::size_t>(n) * 140);
  for (int v = 0; v < n; ++v) {
    csv += std::to_string(v);
    for (int k = 0; k < 6; ++k) csv += "," + num(r.displacement(v, k));
    csv += "\n";
  }
  io::write_file_atomic(dir / "displacements.csv", csv);
  csv = "face,s1,s2,d1x,d1y,d1z,d2x,d2y,d2z\n";
  csv.reserve(static_cast<std::size_t>(nf) * 180);
  Eigen::MatrixXd s1(nf, 1), s2(nf, 1), d1(nf, 3), d2(nf, 3);
  double s1max = -std::numeric_limits<double>::infinity(), s2min = -s1max;
  for (int f = 0; f < nf; ++f) {
    const PrincipalStress& p = r.stress[f];
    csv += fmt::format("{},{},{},{},{},{},{},{},{}\n", f, num(p.s1), num(p.s2), num(p.d1.x()),
                       num(p.d1.y()), num(p.d1.z()), num(p.d2.x()), num(p.d2.y()), num(p.d2.z()));
    s1(f) = p.s1, s2(f) = p.s2;
    d1.row(f) = p.d1.transpose(), d2.row(f) = p.d2.transpose();
    s1max = std::max(s1max, p.s1), s2min = std::min(s2min, p.s2);
  }
  io::write_file_atomic(dir / "stress.csv", csv);
  io::Attributes point_data, cell_data;
  point_data["displacement"] = r.displacement.leftCols(3);
  point_data["rotation"] = r.displacement.rightCols(3);
  point_data["reaction"] = r.reaction.leftCols(3);
  cell_data["s1"] = s1;
  cell_data["s2"] = s2;
  cell_data["d1"] = d1;
  cell_data["d2"] = d2;
  io::write_vtp(dir / "shell.vtp", to_poly(model.mesh), point_data, cell_data);
  timings.add("write", clock.lap());

  nlohmann::json rep;
  rep["input"] = a.input;
  rep["input_kind"] = source;
  rep["shell"] = {
      {"max_displacement_m", r.max_displacement},
      {"max_displacement_vertex", r.max_displacement_vertex},
      {"vertices", n},
      {"triangles", nf},
      {"dofs", r.dofs},
      {"free_dofs", r.free_dofs},
      {"element", "flat facet: Felippa OPT membrane with drilling dof + Batoz DKT bending"},
      {"thickness_m", model.thickness},
      {"E_Pa", model.material.E},
      {"nu", model.material.nu},
      {"density_kg_m3", model.material.density},
      {"s1_max_Pa", s1max},
      {"s2_min_Pa", s2min},
      {"applied_force_N", {r.applied_force.x(), r.applied_force.y(), r.applied_force.z()}},
      {"reaction_force_N", {r.reaction_force.x(), r.reaction_force.y(), r.reaction_force.z()}}};
  timings.add("total", total.seconds());
  rep["timings_s"] = timings;
  write_config(a.run.out_dir, sub);
  write_report(a.run.out_dir, rep);
  spdlog::info("stress: max displacement {:.4g} m at vertex {}; results in {}", r.max_displacement,
               r.max_displacement_vertex, a.run.out_dir);
  return 0;
}

}  // namespace

void register_stress(CLI::App& app, Action& action) {
  auto a = std::make_shared<StressArgs>();
  CLI::App* sub = app.add_subcommand(
      "stress",
      "Linear static analysis of the continuous thin shell: principal membrane stresses and "
      "displacements (flat facet OPT membrane + DKT bending triangles, CHOLMOD)");
  sub->add_option("input", a->input,
                  "surface (PLY/OBJ/OFF file or builtin:NAME) or a shell MODEL.json")
      ->required();
  add_surface_options(sub, a->surface_options);
  add_run_options(sub, a->run);
  a->opt_thickness = sub->add_option("--thickness", a->defaults.thickness, "shell thickness (m)")
                         ->default_str("0.1");
  a->opt_E = sub->add_option("-E,--E", a->defaults.material.E, "Young's modulus (Pa)")
                 ->default_str("3e10");
  a->opt_nu =
      sub->add_option("--nu", a->defaults.material.nu, "Poisson's ratio")->default_str("0.2");
  // (design's --density is the field's trend word, also spelt --density-trend there)
  a->opt_density = sub->add_option("--density,--material-density", a->defaults.material.density,
                                   "the shell's mass density (kg/m³); --material-density: the "
                                   "same option")
                       ->default_str("2400");
  sub->add_option("--load", a->load_kn,
                  "surface input: uniform load per unit plan area, downward (kN/m²)")
      ->default_str("1");
  sub->add_option("--support-below", a->support_below,
                  "surface input: keep only the supports with z below this height (m), e.g. the "
                  "ground edges of a vault whose free arches are also boundary");
  sub->add_flag("--self-weight", a->defaults.self_weight,
                "surface input: add the shell's own weight (density · 9.81 · thickness)");
  sub->add_flag("--clamped", a->defaults.clamped,
                "surface input: supports also fix rotations (default: pinned)");
  sub->callback([a, sub, &action] { action = [a, sub] { return run_stress(*a, sub); }; });
}

}  // namespace gridshell::app
