// gridshell baseline SURFACE --kind quad|tri|voronoi-iso --length L -o DIR: the comparison
// grid-shells of the paper at equal total length, with the same outputs as design.

#include <chrono>
#include <filesystem>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common.h"
#include "gridshell/core/error.h"
#include "gridshell/grids/quad_grid.h"
#include "gridshell/io/files.h"
#include "gridshell/pipeline/gridshell_output.h"

namespace gridshell::app {

namespace {

struct BaselineArgs {
  std::string surface = kDefaultSurface;
  std::string kind = "quad";
  double length = 0, spacing = 0, angle_deg = 0;
  std::string analyze = "none";
  SurfaceOptions surface_options;
  RunOptions run;
};

int run_baseline(const BaselineArgs& a, const CLI::App* sub) {
  auto guard = apply_run_options(a.run);
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  nlohmann::json timings;
  auto lap = [&](const char* stage, clock::time_point since) {
    timings[stage] = std::chrono::duration<double>(clock::now() - since).count();
  };
  if (a.analyze != "none")
    throw Error("--analyze", "structural analysis of baselines arrives with the analysis stage; use none");
  Surface surface = load_surface(a.surface, a.surface_options);
  lap("load", t0);
  GridShellOutput out;
  const auto t1 = clock::now();
  if (a.kind == "quad") {
    QuadGridOptions qo;
    qo.angle = a.angle_deg * 3.14159265358979323846 / 180;
    GridShell g;
    if (a.length > 0) {
      spdlog::info("[baseline] quad grid at total length {} m", a.length);
      g = quad_grid_for_length(surface, a.length, qo);
    } else {
      if (!(a.spacing > 0)) throw Error("--length", "give --length L (m) or --spacing S (m)");
      qo.spacing = a.spacing;
      g = quad_grid(surface, qo);
    }
    out.mesh = std::move(g.mesh);
    out.supports = std::move(g.supports);
  } else if (a.kind == "tri" || a.kind == "voronoi-iso") {
    throw Error("--kind", fmt::format("'{}' needs the tessellation engine (not built yet)", a.kind));
  } else {
    throw Error("--kind", fmt::format("'{}' is not one of quad, tri, voronoi-iso", a.kind));
  }
  lap("grid", t1);
  out.raw = out.mesh;
  io::ensure_directory(a.run.out_dir);
  write_gridshell_files(a.run.out_dir, out);
  nlohmann::json report;
  report["kind"] = a.kind;
  report["surface"] = a.surface;
  report["mesh"] = mesh_block(out);
  timings["total"] = std::chrono::duration<double>(clock::now() - t0).count();
  report["timings_s"] = timings;
  write_config(a.run.out_dir, sub);
  write_report(a.run.out_dir, report);
  spdlog::info("[baseline] {} joints, {} panels, {:.1f} m of beams -> {}", out.mesh.num_vertices(),
               out.mesh.num_faces(), report["mesh"]["total_length_m"].get<double>(), a.run.out_dir);
  return 0;
}

}  // namespace

void register_baseline(CLI::App& app, Action& action) {
  auto a = std::make_shared<BaselineArgs>();
  CLI::App* sub = app.add_subcommand(
      "baseline", "Comparison grid-shells of the paper (quad, tri, voronoi-iso) at equal length");
  sub->add_option("surface", a->surface, "PLY/OBJ/OFF file or builtin:NAME")->default_str(kDefaultSurface);
  sub->add_option("--kind", a->kind, "quad | tri | voronoi-iso")->default_str("quad");
  sub->add_option("--length", a->length, "target total beam length (m), held within 5%");
  sub->add_option("--spacing", a->spacing, "quad: grid spacing in plan (m) instead of --length");
  sub->add_option("--angle", a->angle_deg, "quad: rotation of the grid in plan (degrees)")->default_str("0");
  sub->add_option("--analyze", a->analyze, "none (structural analysis: coming with the analysis stage)")
      ->default_str("none");
  add_surface_options(sub, a->surface_options);
  add_run_options(sub, a->run);
  sub->callback([a, sub, &action] { action = [a, sub] { return run_baseline(*a, sub); }; });
}

}  // namespace gridshell::app
