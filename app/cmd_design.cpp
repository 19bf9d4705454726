// gridshell design [SURFACE] [--field uniform] [--radius R | --cells N | --length L] -o DIR:
// the paper's pipeline (tessellation stage for now; stress field, regularization and analysis
// plug in as they land).

#include <chrono>
#include <filesystem>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common.h"
#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/pipeline/design.h"

namespace gridshell::app {

namespace {

struct DesignArgs {
  std::string surface = kDefaultSurface;
  SurfaceOptions surface_options;
  RunOptions run;
  DesignOptions design;
  bool no_regularize = false;
  std::string symmetry;
};

int run_design_cmd(const DesignArgs& a, const CLI::App* sub) {
  const auto guard = apply_run_options(a.run);
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  DesignOptions options = a.design;
  options.tessellation.seed = a.run.seed;
  options.regularize = !a.no_regularize;
  if (!a.symmetry.empty()) throw Error("--symmetry", "not available yet");
  auto t0 = clock::now();
  spdlog::info("design: loading {}", a.surface);
  const Surface surface = load_surface(a.surface, a.surface_options);
  const double t_load = std::chrono::duration<double>(clock::now() - t0).count();
  const DesignResult r = run_design(surface, options);

  t0 = clock::now();
  const std::filesystem::path dir(a.run.out_dir);
  io::ensure_directory(dir);
  io::write_obj(dir / "gridshell_raw.obj", r.raw.mesh, r.raw.supports);
  io::write_obj(dir / "gridshell.obj", r.mesh, r.supports);
  io::write_ply(dir / "gridshell.ply", r.mesh, r.supports);
  {
    const int nv = r.mesh.num_vertices(), nf = r.mesh.num_faces();
    Eigen::MatrixXd support = Eigen::MatrixXd::Zero(nv, 1), boundary(nv, 1), sides(nf, 1),
                    area(nf, 1);
    for (int v : r.supports) support(v, 0) = 1;
    for (int v = 0; v < nv; ++v) boundary(v, 0) = r.raw.on_boundary[v];
    for (int f = 0; f < nf; ++f) {
      sides(f, 0) = static_cast<double>(r.mesh.faces[f].size());
      area(f, 0) = polygon_area(r.mesh, f);
    }
    io::write_vtp(dir / "gridshell.vtp", r.mesh, {{"support", support}, {"boundary", boundary}},
                  {{"sides", sides}, {"area", area}});
  }
  std::string csv = "face,sides,area,d_target,a_target\n";
  for (int f = 0; f < r.mesh.num_faces(); ++f)
    csv += fmt::format("{},{},{},{},{}\n", f, r.mesh.faces[f].size(),
                       io::format_number(polygon_area(r.mesh, f)), io::format_number(r.d_target[f]),
                       io::format_number(r.a_target[f]));
  io::write_file_atomic(dir / "cells.csv", csv);

  const TessellationQuality& q = r.raw.quality;
  nlohmann::json sides = nlohmann::json::object();
  for (const auto& [n, c] : q.face_sides) sides[std::to_string(n)] = c;
  nlohmann::json report;
  report["surface"] = a.surface;
  report["mesh"] = {{"vertices", r.mesh.num_vertices()},
                    {"faces", r.mesh.num_faces()},
                    {"edges", q.edges},
                    {"total_length_m", q.total_length},
                    {"face_sides", sides},
                    {"planarity_mean", r.metrics.planarity_mean},
                    {"regularity_mean", r.metrics.regularity_mean},
                    {"hex_share_interior", q.hex_share_interior},
                    {"valence3_share_interior", q.valence3_share_interior},
                    {"edge_length_cv", q.edge_length_cv},
                    {"edge_length_mean_m", q.edge_length_mean},
                    {"edge_length_min_m", q.edge_length_min},
                    {"euler_characteristic", q.euler},
                    {"boundary_loops", q.boundary_loops},
                    {"radius_m", r.raw.radius},
                    {"lloyd_iterations", r.raw.iterations},
                    {"lloyd_converged", r.raw.converged},
                    {"support_mesh_vertices", r.raw.support_vertices},
                    {"length_runs", r.raw.length_runs},
                    {"supports", r.supports}};
  report["field"] = {{"kind", options.field}, {"D", options.D}, {"A", options.A}};
  report["regularized"] = false;
  report["analysis"] = options.analyze;
  if (options.tessellation.length > 0) {
    report["mesh"]["target_length_m"] = options.tessellation.length;
    report["mesh"]["length_error"] = q.total_length / options.tessellation.length - 1;
  }
  nlohmann::json timings = nlohmann::json::object();
  timings["load"] = t_load;
  for (const auto& [stage, s] : r.timings) timings[stage] = s;
  timings["write"] = std::chrono::duration<double>(clock::now() - t0).count();
  timings["total"] = std::chrono::duration<double>(clock::now() - start).count();
  report["timings_s"] = timings;
  write_config(a.run.out_dir, sub);
  write_report(a.run.out_dir, report);
  spdlog::info("design: wrote {}", dir.string());
  return 0;
}

}  // namespace

void register_design(CLI::App& app, Action& action) {
  auto a = std::make_shared<DesignArgs>();
  CLI::App* sub = app.add_subcommand(
      "design",
      "The grid-shell pipeline: a hex-dominant centroidal Voronoi tessellation of the surface "
      "(stress-driven field, regularization and analysis come with their stages)");
  sub->add_option("surface", a->surface,
                  "PLY/OBJ/OFF file or builtin:NAME (default builtin:funicular)")
      ->default_str(kDefaultSurface);
  sub->add_option("--field", a->design.field,
                  "cell-size field: uniform (isotropic cells). 'stress' (the contract's default) "
                  "comes with the stress-field stage")
      ->default_str("uniform");
  sub->add_option("-D", a->design.D, "density ratio D (only 1 until the stress field lands)")
      ->default_str("1");
  sub->add_option("-A", a->design.A, "anisotropy ratio A (only 1 until the stress field lands)")
      ->default_str("1");
  auto* radius = sub->add_option("--radius", a->design.tessellation.radius,
                                 "cell size R in metres (≈ beam length)");
  auto* cells = sub->add_option("--cells", a->design.tessellation.cells, "number of cells");
  auto* length = sub->add_option("--length", a->design.tessellation.length,
                                 "target total beam length in metres (held within 5%)");
  radius->excludes(cells)->excludes(length);
  cells->excludes(length);
  sub->add_option("--symmetry", a->symmetry, "x|y|xy (not available yet)");
  sub->add_flag("--no-regularize", a->no_regularize, "skip regularization (not implemented yet)");
  sub->add_option("--analyze", a->design.analyze, "none (linear|nonlinear come with analysis)")
      ->default_str("none");
  sub->footer(
      "Default size when none of --radius/--cells/--length is given: 300 cells.\n"
      "Writes gridshell_raw.obj, gridshell.obj, gridshell.ply, gridshell.vtp, cells.csv,\n"
      "report.json and config.json in the output folder.");
  add_surface_options(sub, a->surface_options);
  add_run_options(sub, a->run);
  sub->callback([a, sub, &action] { action = [a, sub] { return run_design_cmd(*a, sub); }; });
}

}  // namespace gridshell::app
