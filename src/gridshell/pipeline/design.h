#pragma once
/// \file design.h
/// `gridshell design`: the paper's pipeline, stage by stage, each timed.
///
///   coarsen  (a fine input) a copy at the resolution the cells need, on which
///            the stages up to the tessellation run (analysis_resolution)  mesh/coarsen.h
///   stress   shell FEM of the surface (uniform plan load, pinned supports)  fem/shell_solver.h
///   field    direction u, density d ∈ [1, D], anisotropy a ∈ [1, A]        field/field.h
///   sector   (with --symmetry) the surface cut to one symmetric sector       grids/plane_cut.h
///   metric   deformed surface M′ in which the field's metric is Euclidean  metric/deform.h
///   tessellation  centroidal Voronoi tessellation on M′, mapped back to M   voronoi/tessellation.h
///   symmetry reflect the sector's cells and weld them                       optimize/symmetry.h
///   regularization  stretched-regular faces (or --planarize)                 optimize/regularize.h
///   flat_panels (--panels flat) every panel exactly planar                  optimize/flat_panels.h
///   analysis δ, λ_LBA, λ_nonlinear of the steel frame                       analysis/
///
/// With D = A = 1 (or `--field uniform`) the stress analysis is skipped and M′ = M.

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/core/timings.h"
#include "gridshell/fem/shell_solver.h"
#include "gridshell/field/field.h"
#include "gridshell/metric/deform.h"
#include "gridshell/optimize/flat_panels.h"
#include "gridshell/optimize/metrics.h"
#include "gridshell/optimize/regularize.h"
#include "gridshell/optimize/symmetry.h"
#include "gridshell/sizing/sizing.h"
#include "gridshell/voronoi/tessellation.h"

namespace gridshell {

/// Where the stress that drives the field comes from.
enum class FieldInput {
  stress,   ///< a shell analysis of the surface (the paper)
  uniform,  ///< none: isotropic cells of one size
  file,     ///< a BLK or CSV file (field/field_io.h), DesignOptions::field_file
};
/// "stress", "uniform", or anything else = a file (with `file` set to the word).
FieldInput parse_field_input(const std::string& word, std::string* file);

/// Which mesh the stress, field, metric and tessellation stages run on (docs/shell.md
/// "Analysis resolution"). The grid-shell lies on the input surface either way.
enum class AnalysisResolution {
  cells,  ///< a coarsened copy (mesh/coarsen.h) when the input is much finer than the cells need
  input,  ///< the input mesh as it is
};
AnalysisResolution parse_analysis_resolution(const std::string& word);
const char* to_string(AnalysisResolution resolution);

/// The finishing step after the tessellation (optimize/regularize.h).
enum class Finish {
  raw,         ///< none: the tessellation as it is (`--no-regularize`)
  regularize,  ///< stretched-regular faces (the paper; the default)
  planarize,   ///< ShapeUp planarity projection instead (`--planarize`)
};
/// (Its words and the command line's flags: pipeline/design_settings.h.)

struct DesignOptions {
  FieldInput field = FieldInput::stress;
  std::string field_file;  ///< with FieldInput::file
  analysis::AnalysisLevel analyze = analysis::AnalysisLevel::nonlinear;
  Finish finish = Finish::regularize;
  Symmetry symmetry = Symmetry::none;
  TessellationOptions tessellation;
  /// The field's conventions and its ratios, stored here only: D (density ratio: the densest
  /// cells D× smaller across than the sparsest, default 3) and A (anisotropy ratio: cells up to
  /// A× longer along u than across, default 3).
  FieldOptions field_options;
  fem::ShellDefaults shell;
  DeformOptions deform;  ///< max_edge is set from the cell size (metric_edge × R)
  /// Edges of M′ are refined to metric_edge × R by the deformation; the tessellation engine then
  /// refines M and M′ together to its support-mesh size (≤ R/5 on M′) where the diagram needs it.
  /// Deforming the coarser mesh is much cheaper and the field has the input's resolution anyway.
  double metric_edge = 1.0;
  /// With AnalysisResolution::cells the stages before the finishing step run on a copy of the
  /// surface coarsened to edges of R / analysis_edges_per_radius (R: the cell radius the size
  /// request gives, as for metric_edge), when the input's edges are shorter than half of that
  /// (≥ 4× the triangles needed); the field is then carried back to the input's triangles and the
  /// joints are projected onto the input. Not with a given stress or a field file (per input
  /// triangle). Measured in docs/shell.md "Analysis resolution".
  AnalysisResolution analysis_resolution = AnalysisResolution::cells;
  double analysis_edges_per_radius = 3;
  /// false: a design on a coarsened analysis surface keeps `DesignResult::field` on that
  /// surface's triangles instead of carrying it to the input's (the objective search's
  /// candidates: only the chosen one's field is written, and on a 2 M-triangle input each
  /// carried field is 2 M triangles of memory); carry_field_to_input does it later, the same bits.
  bool field_on_input = true;
  RegularizeOptions regularize_options;
  /// flat: after the finishing step every panel is made exactly planar (optimize/flat_panels.h;
  /// docs/panels.md); when that fails its post-check the free panels stay, with a warning and
  /// report.json `design.flat_panels.failure`.
  PanelMode panels = PanelMode::free;
  FlatPanelOptions flat;
  analysis::GridshellFrameOptions frame;
  analysis::FrameAnalysisOptions frame_analysis;  ///< linear/buckling/nonlinear set from analyze
  /// `sized`: every member sized to the code (sizing/sizing.h) in the analysis stage.
  sizing::MemberSizing sizing = sizing::MemberSizing::given;
  sizing::SizingOptions sizing_options;
};

struct DesignResult {
  PolyMesh raw;                  ///< tessellation before regularization
  PolyMesh mesh;                 ///< final grid-shell
  std::vector<int> supports;     ///< support joints (same for raw and mesh: topology kept)
  std::vector<double> d_target;  ///< per face: rescaled density asked for (≥ 1)
  std::vector<double> a_target;  ///< per face: rescaled anisotropy asked for (≥ 1)
  MeshMetrics metrics, raw_metrics;
  Tessellation tessellation;  ///< engine output (of the sector when symmetric)
  Field field;                ///< on the input surface, per triangle
  /// When the stages before the finishing step ran on a coarsened copy of the input
  /// (AnalysisResolution::cells): that copy and the field on its triangles, where the field was
  /// computed (`field` is its copy on the input's triangles, each taking its nearest triangle's
  /// values). Empty otherwise. The field figure draws these: the same picture, from the
  /// analysis surface's triangles instead of every input triangle.
  TriMesh analysis_mesh;
  Field analysis_field;
  std::optional<analysis::FrameResult> structure;
  /// With DesignOptions::sizing = sized: the sizing, its members' sections and its final
  /// analysis of every combination (`structure` is its primary combination's).
  std::optional<sizing::SizingResult> sizing;
  PanelShape panels;  ///< out-of-plane, convexity, angles, joints to the input surface (mesh)
  nlohmann::json details;                               ///< per-stage figures for report.json
  Timings timings;  ///< stage → seconds, in the order they ran (core/timings.h)
};

/// Throws Error for options that can never work (D < 1, a negative size, …), before any work.
void check_design_options(const DesignOptions& options);

/// Stage 0 of run_design on its own: the coarsened copy of `surface` the stages before the
/// finishing step run on (`analysis_resolution`, for the size that `options.tessellation`
/// requests), or nothing when the input is not much finer than the cells need. For baselines
/// that follow the design's field (pipeline/baseline_field.h).
std::optional<Surface> design_analysis_surface(const Surface& surface, const DesignOptions& options);

/// Runs the pipeline on `surface`. Throws Error for bad options or input.
DesignResult run_design(const Surface& surface, const DesignOptions& options);

/// A stress that replaces the design's stress stage (e.g. a frame response,
/// field/frame_response.h): one entry per triangle of the input surface, or only at the input
/// triangles the design reads — `at` = given_stress_faces(...) of the design's cache, entry k
/// at input triangle at[k]. On a coarsened input (DesignOptions::analysis_resolution) the design
/// reads the input triangle nearest each triangle of its analysis surface, so the two give the
/// same design bit for bit; the second is ~250× less work on a 2 M-triangle input.
struct GivenStress {
  StressField values;
  std::vector<int> at;  ///< empty: `values` has one entry per input triangle
};
/// run_design with a given stress; `options.field` is then not read (except `uniform`, which
/// still means isotropic cells). Throws Error when `stress` has the wrong size, or was sampled
/// (`at`) at other triangles than the design reads.
DesignResult run_design(const Surface& surface, const DesignOptions& options,
                        const GivenStress& stress);

/// What designs of one surface share when they differ only in D, A, the field's conventions
/// (measure, stretch, density) and the seed — a sweep, the objective search: the analysis
/// surface, the shell stress, and per (D, A, conventions) the field and per length target the
/// deformed surface M′ (neither depends on the seed); and of the input surface what the finishing
/// step needs (its projector, its symmetry, the nearest-triangle maps to and from the analysis
/// surface: on a 250 K-triangle input these cost a design over a second). One cache per surface
/// and per set of the other options. Thread-safe: designs running in parallel share it, and each
/// value is computed once (a design that needs a value being computed waits for it). A design
/// from a cache equals the same design without one.
class DesignCache {
 public:
  DesignCache();
  ~DesignCache();
  DesignCache(const DesignCache&) = delete;
  DesignCache& operator=(const DesignCache&) = delete;
  struct Impl;
  Impl& impl() { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};
/// run_design(surface, options) with what `cache` holds from earlier designs of `surface`.
DesignResult run_design(const Surface& surface, const DesignOptions& options, DesignCache& cache);
/// The same with a given stress (shares only the analysis surface and its maps: fields of a
/// given stress are not kept).
DesignResult run_design(const Surface& surface, const DesignOptions& options,
                        const GivenStress& stress, DesignCache& cache);
/// The input triangles a design of `surface` with `options` from `cache` reads a given stress
/// at (GivenStress::at): per triangle of its coarsened analysis surface, the input triangle
/// nearest the centroid (the analysis surface is made now when `cache` has none yet). Empty
/// when the design runs on the input itself, which reads every triangle.
std::vector<int> given_stress_faces(const Surface& surface, const DesignOptions& options,
                                    DesignCache& cache);
/// For a design made from `cache` with DesignOptions::field_on_input = false on a coarsened
/// analysis surface: carries its field to the input's triangles, as run_design would have
/// (nothing when it is there already). The seconds are added to the design's `coarsen` timing.
void carry_field_to_input(const Surface& surface, DesignResult& result, DesignCache& cache);
/// Computes into `cache` now what designs of `surface` with `options` take from it before their
/// metric: the analysis surface, the stress and the field (for a stress or file field), and of
/// the input surface the projector of the finishing step, its symmetry and the map from the
/// analysis surface. A caller runs it beside other work so that the designs it starts later
/// find them ready (the objective search: beside its isotropic reference, which needs no
/// stress); designs never depend on who computed a value. Throws what the designs would.
void prepare_design_cache(const Surface& surface, const DesignOptions& options, DesignCache& cache);
/// The field a design of `surface` with `options` is made on at its full contrast (per triangle
/// of the analysis surface), from `cache`: computed there when first asked, the value the design
/// itself then takes. Null for an isotropic design. Throws what the design would.
const Field* shared_design_field(const Surface& surface, const DesignOptions& options,
                                 DesignCache& cache);

/// The flat-panel stage with its fallback (docs/panels.md): `flat` holds the flat mesh when it
/// passes the stage's post-check, else nothing (the free panels stay, with a warning); `info` is
/// report.json's `flat_panels` block either way (`panels`, the stage's figures or `failure`).
/// Used by design (after the finishing step) and by baseline.
struct FlatPanelAttempt {
  std::optional<FlatPanelResult> flat;
  nlohmann::json info;
};
FlatPanelAttempt attempt_flat_panels(const PolyMesh& mesh, const std::vector<int>& supports,
                                     const TriMesh& surface, const SurfaceProjector& projector,
                                     const FlatPanelOptions& options = {});
/// Per panel of a flat result, `values` given per panel of the design it was made from
/// (`source_face`: FlatPanelResult::source_face; a panel glazed as triangles gives each its
/// value). Empty stays empty.
std::vector<double> per_flat_panel(const std::vector<double>& values,
                                   const std::vector<int>& source_face);

/// The frame options the design was analysed with: `options.frame`, with a sized design's
/// member sections.
analysis::GridshellFrameOptions analysed_frame(const DesignOptions& options,
                                              const DesignResult& result);

/// Analyses a grid-shell as the paper's steel frame at `level` (linear | buckling | nonlinear).
analysis::FrameResult analyze_gridshell(const PolyMesh& mesh, const std::vector<int>& supports,
                                        analysis::AnalysisLevel level,
                                        const analysis::GridshellFrameOptions& frame = {},
                                        const analysis::FrameAnalysisOptions& options = {});

/// The report.json `structure` block of a frame analysis (CONTRACT keys plus details).
nlohmann::json structure_block(const analysis::FrameResult& r);
/// The member checks, serviceability and stability keys of `structure` (docs/checks.md):
/// span_m, delta_limit_m, delta_pass, utilisation_max, utilisation_beam,
/// buckling_utilisation_max/_beam, lambda_lba, lambda_perfect, lambda_imperfect,
/// imperfection_sensitivity (λ_imperfect / λ_perfect), imperfection_amplitude_m, lambda_y,
/// lambda_y_path, lambda_y_linear (1 / utilisation_max). Called by structure_block.
void add_checks_block(nlohmann::json& st, const analysis::FrameResult& r);

/// One combination's block of `structure.combinations`: gamma_G, gamma_Q, δ and its limit and
/// pass/fail, the member checks and the stability figures of `r` (add_checks_block's keys).
nlohmann::json combination_block(const analysis::FrameResult& r, double gamma_g, double gamma_q);

/// report.json's `structure.combinations`: one block per load combination with δ, its limit and
/// pass/fail, the member checks and the stability figures (add_checks_block's keys that apply).
/// paper load: {"paper": from `primary`}; eurocode: every combination of
/// analysis::eurocode_combinations: "ULS" from `primary` (analysed with frame.combination =
/// ULS), the other ULS combinations analysed here linearly with LBA (when `primary` has one),
/// the SLS ones linearly; the ULS combinations whose λ_LBA is within 15 % of the lowest also
/// get the non-linear paths (when `primary` has them: `nonlinear_followed`). Each ULS block has
/// `lambda` (the smaller of λ_imperfect and λ_perfect, else λ_LBA: `lambda_source`), `leading`,
/// `factors`, `imperfection`.
/// `done`: the combinations already analysed (a sized design's final analysis,
/// sizing::SizingResult::final, in the order of eurocode_combinations): reported, not analysed
/// again.
nlohmann::json combinations_block(const PolyMesh& mesh, const std::vector<int>& supports,
                                  const analysis::GridshellFrameOptions& frame,
                                  const analysis::FrameAnalysisOptions& options,
                                  const analysis::FrameResult& primary,
                                  const analysis::CombinationRunsResult* done = nullptr);
/// report.json's `structure.governing` from `structure.combinations`: {"utilisation": the ULS
/// combination with the largest utilisation_max, "lambda": the ULS one with the smallest
/// `lambda` (else lambda_imperfect, else lambda_lba), "delta": the SLS one with the largest
/// δ (the only combination when there is one), and their values; the verdicts over all
/// combinations: "utilisation_pass" (≤ 1), "lambda_pass" (≥ 1: λ multiplies the ULS loads),
/// "delta_pass" (the governing δ within its combination's delta_limit_m) and "pass" (all that
/// were computed)}. `structure`'s own keys (delta_pass, utilisation_max, …) are the primary
/// combination's.
nlohmann::json governing_block(const nlohmann::json& combinations);

}  // namespace gridshell
