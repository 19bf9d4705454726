#include "gridshell/pipeline/design.h"

#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>
#include <tuple>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "gridshell/core/error.h"
#include "gridshell/field/field_io.h"
#include "gridshell/field/transfer.h"
#include "gridshell/grids/plane_cut.h"
#include "gridshell/grids/supports.h"
#include "gridshell/mesh/coarsen.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/projector.h"
#include "gridshell/pipeline/once_map.h"
#include "gridshell/pipeline/structure.h"

namespace gridshell {

namespace {

using Clock = std::chrono::steady_clock;
/// Adds the seconds since `t` to `stage` and restarts `t`.
void lap(Timings& timings, const char* stage, Clock::time_point& t) {
  const auto now = Clock::now();
  timings.add(stage, std::chrono::duration<double>(now - t).count());
  t = now;
}

bool is_isotropic(const DesignOptions& o) {
  return o.field == FieldInput::uniform || (o.field_options.D == 1 && o.field_options.A == 1);
}

/// Field values of the faces of `sub`, a mesh whose faces come from `parent` faces of a mesh
/// carrying `field`.
Field restrict_field(const Field& field, const std::vector<int>& parent) {
  Field out;
  for (int p : parent) {
    out.u.push_back(field.u[p]);
    out.d.push_back(field.d[p]);
    out.a.push_back(field.a[p]);
    if (!field.u_raw.empty()) out.u_raw.push_back(field.u_raw[p]);
    if (!field.d_raw.empty()) out.d_raw.push_back(field.d_raw[p]);
    if (!field.a_raw.empty()) out.a_raw.push_back(field.a_raw[p]);
  }
  return out;
}

/// A first estimate of the cell radius R on M′ from the size request, so that M′ can be refined
/// to about R before tessellating (the engine refines further itself where needed).
double estimate_radius(const TessellationOptions& t, double area_rest, double area_deformed,
                       int sectors) {
  constexpr double kHexArea = 2.598076211353316;  // (3√3/2) R²
  if (t.radius > 0) return t.radius;
  if (t.length > 0) {
    // A hexagonal tiling has 3 R of beams per cell (six edges of length R, each shared by two
    // cells); lengths on M are about √(area_M / area_M′) of those on M′. (Not 1.5 R: that would
    // refine M′ to half the intended edge, 4–5× the triangles, for nothing.)
    return 3 * std::sqrt(area_deformed * area_rest) / (kHexArea * t.length / sectors);
  }
  const int cells = t.cells > 0 ? t.cells : t.default_cells;
  return std::sqrt(area_deformed / (kHexArea * std::max(1, cells / sectors)));
}

/// Area of M′ predicted from the field: each triangle scaled by d²/a.
double predicted_deformed_area(const TriMesh& mesh, const Field& field) {
  double area = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const double rest = triangle_area(mesh.vertex(mesh.F(f, 0)), mesh.vertex(mesh.F(f, 1)),
                                      mesh.vertex(mesh.F(f, 2)));
    area += rest * field.d[f] * field.d[f] / field.a[f];
  }
  return area;
}

// ---------------------------------------------------------------------------------------------
// The stages. Each takes what it needs and returns its value; `r` collects report details and
// timings.

/// Stage 0: the surface the stages before the finishing step run on — a coarsened copy of the
/// input when it is much finer than the cells need (DesignOptions::analysis_resolution), else
/// none (the input itself). `nearest_input_face` (optional): the copy's map to the input's
/// triangles, nearest_faces(input, copy), which the coarsening finds with its own tree.
std::optional<Surface> analysis_surface(const Surface& surface, const DesignOptions& o,
                                        DesignResult& r,
                                        std::vector<int>* nearest_input_face = nullptr) {
  if (o.analysis_resolution != AnalysisResolution::cells) return std::nullopt;
  auto t = Clock::now();
  const double area = surface_area(surface.mesh);
  const int faces = surface.mesh.num_faces();
  // The edge of an equilateral triangle of the input's mean triangle area.
  const double input_edge = std::sqrt(4 * area / (std::sqrt(3.0) * std::max(1, faces)));
  const double edge = estimate_radius(o.tessellation, area, area, 1) / o.analysis_edges_per_radius;
  if (!(edge > 2 * input_edge)) return std::nullopt;
  spdlog::info("[coarsen] {} triangles to edges of {:.3g} m for the analysis", faces, edge);
  CoarseSurface coarse = coarsen_surface(surface, {.edge_length = edge});
  r.details["analysis_surface"] = {{"resolution", "cells"},
                                   {"edge_length_m", edge},
                                   {"input_triangles", faces},
                                   {"triangles", coarse.surface.mesh.num_faces()},
                                   {"supports", coarse.surface.supports.size()}};
  lap(r.timings, "coarsen", t);
  if (coarse.surface.mesh.num_faces() == faces) return std::nullopt;  // refused (non-manifold)
  if (nearest_input_face) *nearest_input_face = std::move(coarse.nearest_input_face);
  return std::move(coarse.surface);
}

/// Stage 1: the stress that drives the field (empty for an isotropic design).
StressField design_stress(const Surface& surface, const DesignOptions& o, DesignResult& r) {
  if (is_isotropic(o)) return {};
  if (o.field == FieldInput::file) return read_field_file(o.field_file, surface.mesh);
  auto t = Clock::now();
  spdlog::info("[stress] shell analysis of {} triangles", surface.mesh.num_faces());
  fem::ShellResult shell = fem::analyze_surface_stress(surface, o.shell);
  r.details["stress"] = {{"max_displacement_m", shell.max_displacement},
                         {"max_displacement_vertex", shell.max_displacement_vertex},
                         {"dofs", shell.dofs}};
  lap(r.timings, "stress", t);
  return std::move(shell.stress);
}

/// Stage 2: the field on the whole surface at contrast (D, A); isotropic for D = A = 1.
Field design_field(const TriMesh& M, const StressField& stress, const DesignOptions& o, double D,
                   double A, bool given, DesignResult& r) {
  if (D == 1 && A == 1) {
    r.details["field"] = {
        {"kind", o.field == FieldInput::uniform ? "uniform" : "uniform (D = A = 1)"}};
    return uniform_field(M);
  }
  FieldOptions fo = o.field_options;
  fo.D = D, fo.A = A;
  spdlog::info("[field] direction, density (D = {}), anisotropy (A = {})", D, A);
  r.details["field"] = {{"kind", given                            ? "given"
                                 : o.field == FieldInput::stress ? "stress"
                                                                  : "file"},
                        {"D", D},
                        {"A", A},
                        {"stress_measure", to_string(fo.measure)},
                        {"stretch", to_string(fo.stretch)},
                        {"density", to_string(fo.density)}};
  return make_field(M, stress, fo);
}

/// The part of the surface that is tessellated: the whole of it, or one symmetric sector cut
/// along the mirror planes, with its field.
struct Sector {
  Surface surface;
  Field field;
};
Sector cut_sector(const Surface& surface, const Field& field, const std::vector<Plane>& planes) {
  if (planes.empty()) return {surface, field};
  CutMesh cut = make_cut_mesh(surface);
  const double snap = 1e-9 * bbox_diagonal(surface.mesh.V);
  for (const Plane& p : planes) {
    cut_along_plane(cut, p, snap);
    keep_side(cut, p);
  }
  Sector s;
  s.surface.mesh = cut.mesh;
  for (int v = 0; v < cut.mesh.num_vertices(); ++v)
    if (cut.support[v]) s.surface.supports.push_back(v);
  s.field = restrict_field(field, cut.parent_face);
  return s;
}

/// Stage 3: M′, the sector deformed so that the field's metric is Euclidean (M′ = M and the
/// field unchanged for an isotropic field).
struct Metric {
  TriMesh rest, deformed;      ///< refined M and M′, same connectivity
  Field rest_field;            ///< the field per triangle of `rest`
  std::vector<int> supports;   ///< support vertices of `rest`
};
Metric deform_sector(const Sector& sector, const DesignOptions& o, double length, int sectors,
                     bool isotropic, DesignResult& r) {
  if (isotropic) return {sector.surface.mesh, sector.surface.mesh, sector.field,
                         sector.surface.supports};
  const TriMesh& mesh = sector.surface.mesh;
  TessellationOptions whole = o.tessellation;  // the size asked of the whole surface
  whole.length = length;
  DeformOptions dopt = o.deform;
  dopt.max_edge = o.metric_edge * estimate_radius(whole, surface_area(mesh),
                                                  predicted_deformed_area(mesh, sector.field),
                                                  sectors);
  spdlog::info("[metric] deforming {} triangles (edges of M' ≤ {:.3g} m)", mesh.num_faces(),
               dopt.max_edge);
  Deformed def = deform_metric(mesh, sector.field, dopt);
  Metric m;
  m.supports = transfer_supports(def.rest.V, sector.surface, 1e-9 * bbox_diagonal(def.rest.V));
  m.rest = std::move(def.rest);
  m.deformed = std::move(def.deformed);
  m.rest_field = std::move(def.field);
  r.details["metric"] = {{"triangles", m.rest.num_faces()}, {"rounds", def.rounds},
                         {"iterations", def.iterations},     {"residual", def.residual},
                         {"max_edge", def.max_edge},         {"folded_edges", def.folded_edges}};
  if (def.folded_edges > 0)
    spdlog::warn("[metric] {} folded edges in M' (D or A large for this surface)",
                 def.folded_edges);
  return m;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// What designs of one surface share (DesignCache): each value is computed once, by the first
// design that asks, inside an isolated TBB region (a design waiting for a nested parallel loop
// must not pick up another design that waits for the same value); the others wait for it.

namespace {
/// A value with the report details its stage wrote.
template <class T>
struct Staged {
  T value;
  nlohmann::json details;
};
/// (D, A, measure, stretch, density) of a field.
using FieldKey = std::tuple<double, double, int, int, int>;
/// A field's key, the length target and the number of sectors of a metric.
using MetricKey = std::tuple<FieldKey, double, int>;
}  // namespace

struct DesignCache::Impl {
  OnceMap<int, Staged<std::optional<Surface>>> surface;
  OnceMap<int, Staged<StressField>> stress;
  OnceMap<FieldKey, Staged<Field>> field;
  OnceMap<MetricKey, Staged<Metric>> metric;
  // Of the input surface M, for the finishing stages (InputSurface below): its projector, its
  // symmetry, and the nearest-triangle maps between M and the analysis surface.
  OnceMap<int, std::optional<SurfaceProjector>> projector;
  OnceMap<int, SymmetryReport> symmetry;
  OnceMap<int, std::vector<int>> to_input, to_analysis;
};
DesignCache::DesignCache() : impl_(std::make_unique<Impl>()) {}
DesignCache::~DesignCache() = default;

namespace {
/// The details a cached stage wrote, added to `r`'s.
void add_details(DesignResult& r, const nlohmann::json& details) {
  for (const auto& [key, value] : details.items()) r.details[key] = value;
}

/// What the stages need of the input surface M beyond its mesh, each made when first asked:
/// shared through the cache when there is one (on a 250 K-triangle input the projector and the
/// maps cost a candidate of the objective search more than a second), else for this design
/// only. The values depend on M (and the analysis surface) alone, so a design gets the same
/// bits either way.
class InputSurface {
 public:
  InputSurface(const TriMesh& M, DesignCache::Impl* cache) : M_(M), cache_(cache) {}
  const TriMesh& mesh() const { return M_; }
  /// Closest points on M (the finishing step's projection).
  const SurfaceProjector& projector() {
    auto make = [&] { return std::optional<SurfaceProjector>(std::in_place, M_); };
    if (cache_) return *cache_->projector.get(0, make);
    if (!own_projector_) own_projector_ = make();
    return *own_projector_;
  }
  /// detect_symmetry of M.
  SymmetryReport symmetry() {
    auto make = [&] { return detect_symmetry(M_, 1e-6); };
    return cache_ ? cache_->symmetry.get(0, make) : make();
  }
  /// nearest_faces(analysis, M): per triangle of M, the nearest of the analysis surface.
  const std::vector<int>& to_input(const TriMesh& analysis) {
    return map(cache_ ? &cache_->to_input : nullptr, own_to_input_, analysis, M_);
  }
  /// nearest_faces(M, analysis): per triangle of the analysis surface, the nearest of M.
  const std::vector<int>& to_analysis(const TriMesh& analysis) {
    return map(cache_ ? &cache_->to_analysis : nullptr, own_to_analysis_, M_, analysis);
  }
  /// to_analysis's value found elsewhere, the same bits (the coarsening's tree over M; nothing
  /// when empty): a design with a stress per input triangle then does not build that tree again.
  void known_to_analysis(std::vector<int> map) {
    if (map.empty()) return;
    if (cache_)
      cache_->to_analysis.get(0, [&] { return std::move(map); });
    else if (own_to_analysis_.empty())
      own_to_analysis_ = std::move(map);
  }

 private:
  const std::vector<int>& map(OnceMap<int, std::vector<int>>* shared, std::vector<int>& own,
                              const TriMesh& from, const TriMesh& to) {
    auto make = [&] { return nearest_faces(from, to); };
    if (shared) return shared->get(0, make);
    if (own.empty()) own = make();
    return own;
  }
  const TriMesh& M_;
  DesignCache::Impl* cache_;
  std::optional<SurfaceProjector> own_projector_;
  std::vector<int> own_to_input_, own_to_analysis_;
};

/// The mirror planes of the requested symmetry (checked against the surface).
std::vector<Plane> mirror_planes(InputSurface& M, Symmetry symmetry, DesignResult& r) {
  if (symmetry == Symmetry::none) return {};
  const SymmetryReport report = M.symmetry();
  r.details["symmetry"] = {{"planes", to_string(symmetry)},
                           {"x_deviation", report.x_deviation},
                           {"y_deviation", report.y_deviation}};
  return symmetry_planes(report, symmetry);
}
FieldKey field_key(const DesignOptions& o, double D, double A) {
  return {D, A, static_cast<int>(o.field_options.measure),
          static_cast<int>(o.field_options.stretch), static_cast<int>(o.field_options.density)};
}

/// The tessellation options of one sector: the size split between the sectors, and the mirror
/// planes' edges left out of the length (they vanish when the sectors are welded).
TessellationOptions sector_tessellation(const TessellationOptions& whole, double length,
                                        const std::vector<Plane>& planes) {
  TessellationOptions t = whole;
  t.length = length;
  const int sectors = 1 << static_cast<int>(planes.size());
  if (sectors > 1) {
    if (t.cells > 0) t.cells = std::max(1, t.cells / sectors);
    if (t.length > 0) t.length /= sectors;
    for (const Plane& p : planes) t.length_excluded_planes.push_back(p);
  }
  return t;
}

/// The field at contrast (D, A) from `cache` (computed there when first asked).
const Staged<Field>& shared_field(DesignCache::Impl& cache, const TriMesh& S,
                                  const StressField& stress, const DesignOptions& o, double D,
                                  double A, bool given) {
  return cache.field.get(field_key(o, D, A), [&] {
    DesignResult scratch;
    Field field = design_field(S, stress, o, D, A, given, scratch);
    return Staged<Field>{std::move(field), std::move(scratch.details)};
  });
}

/// Stages 2–4 with the retries, in one place. Where the metric cannot be realised without
/// folds the engine may fail to extract valid cells (ExtractionError, nothing else): then
/// another seed, and failing that the field's contrast halved (reported in report.json), down
/// to the isotropic tessellation, which always exists.
struct Tessellated {
  Tessellation tess;
  Field rest_field;  ///< the field per triangle of the tessellated (refined) sector
};
Tessellated tessellate_with_retries(const Surface& surface, const StressField& stress,
                                    const DesignOptions& o, const std::vector<Plane>& planes,
                                    double length, bool given, DesignCache::Impl* cache,
                                    DesignResult& r) {
  const bool isotropic = is_isotropic(o);
  const int sectors = 1 << static_cast<int>(planes.size());
  const TessellationOptions topt = sector_tessellation(o.tessellation, length, planes);
  std::string last_error;
  for (double strength : isotropic ? std::vector<double>{0.0} : std::vector<double>{1.0, 0.5, 0.0}) {
    auto t = Clock::now();
    const double D = 1 + strength * (o.field_options.D - 1),
                 A = 1 + strength * (o.field_options.A - 1);
    if (cache) {  // the field and M′ do not depend on the seed: shared between designs
      const Staged<Field>& f = shared_field(*cache, surface.mesh, stress, o, D, A, given);
      r.field = f.value;
      add_details(r, f.details);
    } else {
      r.field = design_field(surface.mesh, stress, o, D, A, given, r);
    }
    if (strength != 1.0 && !isotropic)
      r.details["field"]["softened_from"] = {o.field_options.D, o.field_options.A};
    lap(r.timings, "field", t);
    Metric m;
    if (cache && strength != 0.0) {
      const Staged<Metric>& cached = cache->metric.get({field_key(o, D, A), length, sectors}, [&] {
        DesignResult scratch;
        const Sector sector = cut_sector(surface, r.field, planes);
        Metric metric = deform_sector(sector, o, length, sectors, false, scratch);
        return Staged<Metric>{std::move(metric), std::move(scratch.details)};
      });
      m = cached.value;
      add_details(r, cached.details);
    } else {
      const Sector sector = cut_sector(surface, r.field, planes);
      if (!planes.empty()) lap(r.timings, "sector", t);
      m = deform_sector(sector, o, length, sectors, strength == 0.0, r);
    }
    if (strength != 0.0) lap(r.timings, "metric", t);
    const int attempts = strength == 0.0 ? 3 : 2;
    for (int attempt = 0; attempt < attempts; ++attempt) {
      TessellationOptions seeded = topt;
      seeded.seed = o.tessellation.seed + 7919 * static_cast<std::uint64_t>(attempt);
      spdlog::info("[tessellation] {} triangles, {} supports", m.rest.num_faces(),
                   m.supports.size());
      try {
        Tessellated out{tessellate(m.rest, m.deformed, m.supports, seeded), std::move(m.rest_field)};
        if (attempt > 0) r.details["tessellation_seed_retries"] = attempt;
        lap(r.timings, "tessellation", t);
        return out;
      } catch (const ExtractionError& e) {
        last_error = e.message();
        spdlog::warn("[tessellation] failed ({}); retrying", last_error);
      }
    }
    lap(r.timings, "tessellation", t);
  }
  throw Error("tessellation", last_error);
}

/// The per-face targets d and a of the cells: the field at their joints (triangles of the
/// tessellated sector).
void cell_targets(const Tessellated& t, std::vector<double>& d, std::vector<double>& a) {
  const Tessellation& tess = t.tess;
  d.assign(tess.mesh.num_faces(), 1.0);
  a.assign(tess.mesh.num_faces(), 1.0);
  for (int f = 0; f < tess.mesh.num_faces(); ++f) {
    double sd = 0, sa = 0;
    for (int v : tess.mesh.faces[f]) {
      sd += t.rest_field.d[tess.vertex_triangle[v]];
      sa += t.rest_field.a[tess.vertex_triangle[v]];
    }
    d[f] = std::max(1.0, sd / tess.mesh.faces[f].size());
    a[f] = std::max(1.0, sa / tess.mesh.faces[f].size());
  }
}

/// Stage 5: the whole raw grid-shell (the sector reflected and welded when symmetric), its
/// supports, cell targets and the vertex constraints of the finishing step. Returns the mirror
/// map (empty without symmetry).
std::vector<std::vector<int>> assemble_raw(const Tessellated& t, const std::vector<Plane>& planes,
                                           DesignResult& r,
                                           std::vector<VertexConstraint>& constraints) {
  const Tessellation& tess = t.tess;
  std::vector<double> d_sector, a_sector;
  cell_targets(t, d_sector, a_sector);
  std::vector<std::vector<int>> mirror;
  r.supports.clear();
  if (planes.empty()) {
    r.raw = tess.mesh;
    r.supports = tess.supports;
    r.d_target = d_sector;
    r.a_target = a_sector;
    constraints = constraints_from_flags(tess.on_boundary, tess.corner);
  } else {
    ReflectedMesh rm = reflect_and_weld(tess.mesh, planes, 1e-6);
    r.raw = std::move(rm.mesh);
    mirror = std::move(rm.mirror);
    std::vector<char> sector_support(tess.mesh.num_vertices(), 0);
    for (int v : tess.supports) sector_support[v] = 1;
    for (int v = 0; v < r.raw.num_vertices(); ++v)
      if (sector_support[rm.source_vertex[v]]) r.supports.push_back(v);
    r.d_target.clear();
    r.a_target.clear();
    for (int f = 0; f < r.raw.num_faces(); ++f) {
      r.d_target.push_back(d_sector[rm.source_face[f]]);
      r.a_target.push_back(a_sector[rm.source_face[f]]);
    }
    constraints = classify_vertices(r.raw);
  }
  // Supports off the boundary (columns) never move.
  for (int v : r.supports)
    if (constraints[v] == VertexConstraint::free) constraints[v] = VertexConstraint::fixed;
  return mirror;
}

/// Stage 6: regularization (or planarization) of the raw grid-shell, symmetry restored.
void finish(InputSurface& M, const DesignOptions& o, const std::vector<Plane>& planes,
            const std::vector<std::vector<int>>& mirror,
            const std::vector<VertexConstraint>& constraints, DesignResult& r) {
  r.raw_metrics = mesh_metrics(r.raw);
  if (o.finish != Finish::raw) {
    RegularizeStats stats;
    spdlog::info("[{}] {} faces", o.finish == Finish::planarize ? "planarize" : "regularize",
                 r.raw.num_faces());
    r.mesh = o.finish == Finish::planarize
                 ? planarize(r.raw, M.mesh(), constraints, planarize_options(), &stats)
                 : regularize(r.raw, M.projector(), constraints, o.regularize_options, &stats);
    if (!planes.empty()) enforce_symmetry(r.mesh, planes, mirror);
    r.details["regularization"] = {
        {"kind", o.finish == Finish::planarize ? "planarize" : "regularize"},
        {"iterations", stats.iterations},
        {"converged", stats.converged},
        {"max_surface_distance", stats.max_surface_distance}};
  } else {
    r.mesh = r.raw;
  }
  r.metrics = mesh_metrics(r.mesh);
}

/// Stages 2–6 for one length target (0 = the size options decide): the grid-shell before
/// analysis, tessellated on `surface` (the analysis surface) and finished on `M` (the input).
/// `r` keeps what the earlier stages put there.
void build_grid(const Surface& surface, InputSurface& M, const StressField& stress,
                const DesignOptions& o, const std::vector<Plane>& planes, double length, bool given,
                DesignCache::Impl* cache, DesignResult& r) {
  Tessellated t = tessellate_with_retries(surface, stress, o, planes, length, given, cache, r);
  spdlog::info("[tessellation] {} cells, R = {:.4g} m, {} Lloyd iterations{}, hexagons {:.1f}%",
               t.tess.mesh.num_faces(), t.tess.radius, t.tess.iterations,
               t.tess.converged ? "" : " (not converged)",
               100 * t.tess.quality.hex_share_interior);
  auto clock = Clock::now();
  std::vector<VertexConstraint> constraints;
  const std::vector<std::vector<int>> mirror = assemble_raw(t, planes, r, constraints);
  if (!planes.empty()) lap(r.timings, "symmetry", clock);
  r.tessellation = std::move(t.tess);
  finish(M, o, planes, mirror, constraints, r);
  lap(r.timings, "regularization", clock);
}

/// After a design on the coarsened analysis surface `coarse`: the field carried over to the
/// input's triangles, and the joints onto the input surface `M` (the finishing step has put them
/// there already unless it is off).
void on_input_surface(const TriMesh& coarse, InputSurface& M, const DesignOptions& o,
                      DesignResult& r) {
  auto t = Clock::now();
  if (r.field.size() != coarse.num_faces())
    throw Error("field transfer", "the field does not match the analysis surface");
  if (o.field_on_input) {
    r.analysis_mesh = coarse;
    r.analysis_field = r.field;
    r.field = transfer_field(r.field, M.to_input(coarse), M.mesh());
  }
  if (o.finish == Finish::raw) {
    const SurfaceProjector& projector = M.projector();
    for (int v = 0; v < r.mesh.num_vertices(); ++v)
      r.mesh.V.row(v) = projector.closest_point(r.mesh.vertex(v)).transpose();
    r.metrics = mesh_metrics(r.mesh);
  }
  lap(r.timings, "coarsen", t);
}

/// Stage 6b (--panels flat): every panel exactly planar (optimize/flat_panels.h). When that fails
/// its post-check the free panels stay: a warning and design.flat_panels.failure say so.
void make_panels_flat(InputSurface& M, const DesignOptions& o, DesignResult& r) {
  auto t = Clock::now();
  FlatPanelAttempt a = attempt_flat_panels(r.mesh, r.supports, M.mesh(), M.projector(), o.flat);
  if (a.flat) {
    r.mesh = std::move(a.flat->mesh);
    r.supports = std::move(a.flat->supports);
    r.d_target = per_flat_panel(r.d_target, a.flat->source_face);
    r.a_target = per_flat_panel(r.a_target, a.flat->source_face);
    r.metrics = mesh_metrics(r.mesh);
  }
  r.details["flat_panels"] = std::move(a.info);
  lap(r.timings, "flat_panels", t);
}

}  // namespace

std::optional<Surface> design_analysis_surface(const Surface& surface, const DesignOptions& o) {
  DesignResult scratch;
  return analysis_surface(surface, o, scratch);
}

namespace {
/// Stages 0 and 1, shared through `cache` when there is one: the analysis surface (none: the
/// input) and the stress on it.
struct Prepared {
  std::optional<Surface> own_surface;
  StressField own_stress;
  const std::optional<Surface>* coarse = &own_surface;
  const StressField* stress = &own_stress;
};

/// A given stress on the analysis surface (the input itself when `coarse` is empty): its entries
/// at the input triangles nearest the copy's, carried onto the copy's triangles.
void given_stress(const std::optional<Surface>& coarse, const GivenStress& given, InputSurface& M,
                  Prepared& p, DesignResult& r) {
  if (!coarse) {
    if (!given.at.empty())
      throw Error("field",
                  "a stress sampled for a coarsened copy, but the design runs on the input");
    p.stress = &given.values;  // read in place: no copy of a fine input's stress
    return;
  }
  auto t = Clock::now();
  const std::vector<int>& to_analysis = M.to_analysis(coarse->mesh);
  if (given.at.empty()) {
    p.own_stress = transfer_stress(given.values, to_analysis, coarse->mesh);
  } else {
    if (given.at != to_analysis)
      throw Error("field", "the stress was sampled at other triangles than the design reads");
    std::vector<int> own(to_analysis.size());
    std::iota(own.begin(), own.end(), 0);
    p.own_stress = transfer_stress(given.values, own, coarse->mesh);
  }
  lap(r.timings, "coarsen", t);
}

/// The stress on the analysis surface `S`: design_stress there, or a stress per input triangle
/// read from a file carried over to the coarsened copy.
StressField analysis_stress(const Surface& input, const std::optional<Surface>& coarse,
                            const DesignOptions& o, InputSurface& M, DesignResult& r) {
  if (!coarse || is_isotropic(o)) return design_stress(coarse ? *coarse : input, o, r);
  if (o.field == FieldInput::stress) return design_stress(*coarse, o, r);
  const StressField on_input = design_stress(input, o, r);
  auto t = Clock::now();
  if (static_cast<int>(on_input.size()) != input.mesh.num_faces())
    throw Error("field transfer", "the stress does not match the source mesh");
  StressField out = transfer_stress(on_input, M.to_analysis(coarse->mesh), coarse->mesh);
  lap(r.timings, "coarsen", t);
  return out;
}

/// Stage 0 from `cache`: the analysis surface the cache's first design made (and its map to
/// the input, found by the coarsening, into M).
const Staged<std::optional<Surface>>& cached_surface(const Surface& surface, const DesignOptions& o,
                                                     DesignCache::Impl& cache, InputSurface& M) {
  return cache.surface.get(0, [&] {
    DesignResult scratch;
    std::vector<int> nearest_input_face;
    std::optional<Surface> coarse = analysis_surface(surface, o, scratch, &nearest_input_face);
    M.known_to_analysis(std::move(nearest_input_face));
    return Staged<std::optional<Surface>>{std::move(coarse), std::move(scratch.details)};
  });
}

void prepare(const Surface& surface, const DesignOptions& o, const GivenStress* given,
             DesignCache::Impl* cache, InputSurface& M, Prepared& p, DesignResult& r) {
  if (!cache) {
    std::vector<int> nearest_input_face;
    p.own_surface = analysis_surface(surface, o, r, &nearest_input_face);
    M.known_to_analysis(std::move(nearest_input_face));
  } else {
    auto t = Clock::now();
    const auto& s = cached_surface(surface, o, *cache, M);
    p.coarse = &s.value;
    add_details(r, s.details);
    if (*p.coarse) lap(r.timings, "coarsen", t);
  }
  if (is_isotropic(o)) return;                                 // no stress
  if (given) return given_stress(*p.coarse, *given, M, p, r);  // not shared
  if (!cache) {
    p.own_stress = analysis_stress(surface, p.own_surface, o, M, r);
    return;
  }
  auto t = Clock::now();
  const auto& stress = cache->stress.get(0, [&] {
    DesignResult scratch;
    StressField field = analysis_stress(surface, *p.coarse, o, M, scratch);
    return Staged<StressField>{std::move(field), std::move(scratch.details)};
  });
  p.stress = &stress.value;
  add_details(r, stress.details);
  lap(r.timings, "stress", t);
}

/// The analysis surface, the stress and the field at full contrast of a design with `o`, into
/// `cache`; the field, or null for an isotropic design.
const Field* warm_field(const Surface& surface, const DesignOptions& o, DesignCache::Impl* cache,
                        InputSurface& M, Prepared& prepared) {
  DesignResult scratch;
  prepare(surface, o, nullptr, cache, M, prepared, scratch);
  if (is_isotropic(o)) return nullptr;
  const std::optional<Surface>& coarse = *prepared.coarse;
  return &shared_field(*cache, coarse ? coarse->mesh : surface.mesh, *prepared.stress, o,
                       o.field_options.D, o.field_options.A, false)
              .value;
}

/// What prepare_design_cache computes (see design.h).
void warm_up(const Surface& surface, const DesignOptions& o, DesignCache::Impl* cache) {
  InputSurface M(surface.mesh, cache);
  if (o.finish == Finish::regularize) M.projector();  // needs only the input: first
  if (o.symmetry != Symmetry::none) M.symmetry();
  Prepared prepared;
  warm_field(surface, o, cache, M, prepared);
  const std::optional<Surface>& coarse = *prepared.coarse;
  if (coarse) {
    M.to_input(coarse->mesh);
    if (o.finish != Finish::planarize) M.projector();
  }
}

DesignResult design(const Surface& surface, const DesignOptions& o, const GivenStress* given,
                    DesignCache::Impl* cache) {
  check_design_options(o);
  DesignResult r;
  Prepared prepared;
  InputSurface M(surface.mesh, cache);  // the input's projector and maps: shared via the cache
  prepare(surface, o, given, cache, M, prepared, r);
  const std::optional<Surface>& coarse = *prepared.coarse;
  const Surface& S = coarse ? *coarse : surface;  // what the stages before finishing run on
  const StressField& stress = *prepared.stress;
  const std::vector<Plane> planes = mirror_planes(M, o.symmetry, r);
  const double L = o.tessellation.length;
  DesignCache::Impl* shared = given ? nullptr : cache;  // fields of a given stress: not shared
  build_grid(S, M, stress, o, planes, L, given != nullptr, shared, r);

  // Length control. --length is met on the raw tessellation (within 0.4 of the tolerance);
  // regularization shortens the beams by 0.5–3 %, planarization may lengthen them. When the
  // finishing step has moved the total by more than 0.9 of the tolerance, tessellate once more
  // with the target corrected by the measured change (stress and field do not depend on it):
  // the finishing step scaled the raw length R to F, so a raw length of L·R/F ends at L.
  const double tolerance = 0.9 * o.tessellation.length_tolerance;
  if (L > 0 && r.metrics.total_length > 0 && std::abs(r.metrics.total_length / L - 1) > tolerance) {
    spdlog::info("[length] {:.5g} m of beams for {:.5g} m: tessellating again",
                 r.metrics.total_length, L);
    const double first = r.metrics.total_length;
    const double target = L * r.raw_metrics.total_length / first;
    const double first_seconds = r.timings.sum();
    r.timings.clear();
    r.timings.add("length_first_pass", first_seconds);
    r.details.erase("tessellation_seed_retries");
    build_grid(S, M, stress, o, planes, target, given != nullptr, shared, r);
    r.details["length_retry"] = {{"first_length_m", first}, {"tessellation_target_m", target}};
  }
  if (coarse) on_input_surface(S.mesh, M, o, r);
  if (o.panels == PanelMode::flat) make_panels_flat(M, o, r);
  r.panels = panel_shape(r.mesh, &M.projector());

  // Stage 7: the steel frame.
  if (o.analyze != analysis::AnalysisLevel::none) {
    auto t = Clock::now();
    spdlog::info("[analysis] {} frame: {} joints", to_string(o.analyze), r.mesh.num_vertices());
    GridshellStructure s = analyze_structure(r.mesh, r.supports, o.frame, o.frame_analysis,
                                             {o.analyze, o.sizing, o.sizing_options});
    r.structure = std::move(s.result);
    r.sizing = std::move(s.sizing);
    const auto& st = *r.structure;
    auto num = [](const std::optional<double>& v) {
      return v ? fmt::format("{:.4g}", *v) : std::string("-");
    };
    spdlog::info(
        "[analysis] delta = {:.4g} m, lambda_LBA = {}, lambda_nonlinear = {} ({}), lambda at "
        "{:.3g} m = {}",
        st.delta_max_m, num(st.lambda_linear_buckling), num(st.lambda_nonlinear),
        fem::to_string(st.limit_type), st.displacement_limit_m, num(st.lambda_displacement_limit));
    lap(r.timings, "analysis", t);
  }
  return r;
}
}  // namespace

DesignResult run_design(const Surface& surface, const DesignOptions& o) {
  return design(surface, o, nullptr, nullptr);
}

DesignResult run_design(const Surface& surface, const DesignOptions& o, DesignCache& cache) {
  return design(surface, o, nullptr, &cache.impl());
}

void carry_field_to_input(const Surface& surface, DesignResult& r, DesignCache& cache) {
  if (r.field.size() == surface.mesh.num_faces()) return;
  auto t = Clock::now();
  const auto& coarse = cache.impl().surface.get(0, []() -> Staged<std::optional<Surface>> {
    throw Error("field transfer", "the design was not made from this cache");
  });
  if (!coarse.value) throw Error("field transfer", "the field does not match the input");
  InputSurface M(surface.mesh, &cache.impl());
  r.analysis_mesh = coarse.value->mesh;
  r.analysis_field = r.field;
  r.field = transfer_field(r.field, M.to_input(coarse.value->mesh), M.mesh());
  lap(r.timings, "coarsen", t);
}

void prepare_design_cache(const Surface& surface, const DesignOptions& o, DesignCache& cache) {
  check_design_options(o);
  warm_up(surface, o, &cache.impl());
}

const Field* shared_design_field(const Surface& surface, const DesignOptions& o,
                                 DesignCache& cache) {
  check_design_options(o);
  InputSurface M(surface.mesh, &cache.impl());
  Prepared prepared;
  return warm_field(surface, o, &cache.impl(), M, prepared);
}

namespace {
/// A given stress must have one tensor per triangle of the surface, or one per sampled one.
void check_stress_size(const Surface& surface, const GivenStress& stress) {
  const std::size_t n = stress.at.empty() ? surface.mesh.num_faces() : stress.at.size();
  if (stress.values.size() != n)
    throw Error("field", fmt::format("{} stresses for {} triangles", stress.values.size(), n));
}
}  // namespace

DesignResult run_design(const Surface& surface, const DesignOptions& o, const GivenStress& stress) {
  check_stress_size(surface, stress);
  return design(surface, o, &stress, nullptr);
}

DesignResult run_design(const Surface& surface, const DesignOptions& o, const GivenStress& stress,
                        DesignCache& cache) {
  check_stress_size(surface, stress);
  return design(surface, o, &stress, &cache.impl());
}

std::vector<int> given_stress_faces(const Surface& surface, const DesignOptions& o,
                                    DesignCache& cache) {
  check_design_options(o);
  InputSurface M(surface.mesh, &cache.impl());
  const std::optional<Surface>& coarse = cached_surface(surface, o, cache.impl(), M).value;
  return coarse ? M.to_analysis(coarse->mesh) : std::vector<int>{};
}

}  // namespace gridshell
