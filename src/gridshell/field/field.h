#pragma once
/// \file field.h
/// Stage 3 of the pipeline: from per-triangle principal stresses to the sizing field that drives
/// the anisotropic tessellation, as a triple per face (GUIDE.md stage 3, paper §3):
///
///   - u : unit tangent direction of the principal stress of largest magnitude (a line field:
///         u and −u mean the same),
///   - d : density, the largest principal stress magnitude, rescaled to [1, D],
///   - a : anisotropy, max/min of the two magnitudes (≥ 1, capped), rescaled to [1, A].
///
/// That is the paper's reading (FieldOptions' defaults). Its conventions are options, because
/// which reading makes the stronger grid-shell depends on the surface (docs/field.md):
/// `measure` (magnitude, tension only, compression only), `stretch` (cells long along u or
/// across it) and `density` (small cells where the stress is high, or where it is low).
///
/// Semantics (what the tessellation makes of it, through metric/deform.h): the linear size of a
/// cell is ∝ 1/d (with D = 4 the densest cells are 4× smaller across u than the sparsest), and
/// cells are elongated along u with aspect ratio ≈ a.
///
/// Processing, in order (make_field):
///   1. raw (u, d, a) from the stresses (u projected onto the triangle's plane),
///   2. u smoothed as a line field (smooth_line_field: one sparse Hermitian solve),
///   3. d and a clamped to their [low, high] percentiles (robust against FEM spikes),
///   4. d and a made Lipschitz by an upper saturation that keeps maxima (saturate_lipschitz),
///      a first (Euclidean distances), then
///   5. a blended towards isotropy where the smoothed direction is incoherent (|z| < 1) and
///      mapped onto [1, A]; d saturated in distances shrunk a-fold along u (the metric of M′
///      up to the scale d),
///   6. d and a mapped linearly onto exactly [1, D] and [1, A] (rescale_robust); a constant field
///      maps to 1.
/// (Clamping comes before saturation on purpose: saturating a raw spike would flood the surface
/// with a cone of near-maximal values.)
///
/// Everything is per face of the given mesh, deterministic, and free of global state.

#include <string>
#include <vector>

#include "gridshell/fem/principal_stress.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell {

/// Which stress drives the field (the field's conventions; docs/field.md "Conventions" has the
/// measurements behind each choice).
enum class StressMeasure {
  magnitude,    ///< |s1|, |s2|: u along the principal stress of largest magnitude (the paper)
  tension,      ///< max(s, 0): compression counts as no stress, u along the algebraically larger
                ///< principal stress s1 (the authors' later code, stressDrivenMesh)
  compression,  ///< max(−s, 0): tension counts as no stress, u along the more compressive s2
};
/// Which way the cells are elongated relative to the driving direction.
enum class StretchAxis {
  along,   ///< cells long along u (the paper's text)
  across,  ///< cells long across u (u turned by 90° in the tangent plane before smoothing)
};
/// How cell density follows the driving stress.
enum class DensityTrend {
  rising,   ///< small cells where the stress is high (the paper)
  falling,  ///< small cells where the stress is low
};

/// Knobs of make_field. Lengths in metres; all other values dimensionless.
struct FieldOptions {
  StressMeasure measure = StressMeasure::magnitude;
  StretchAxis stretch = StretchAxis::along;
  DensityTrend density = DensityTrend::rising;
  double D = 3;  ///< density ratio: d is rescaled to [1, D] (≥ 1; 1 = uniform cell size)
  double A = 3;  ///< anisotropy ratio: a is rescaled to [1, A] (≥ 1; 1 = isotropic cells)
  /// Smoothing length ℓ of the line field (m): the faithfulness weight is ω_f/ℓ² per unit area
  /// against a unit Dirichlet energy, so features shorter than ~ℓ are smoothed out.
  /// ≤ 0 = automatic: 5% of the bounding-box diagonal.
  double smoothing = 0;
  /// Lipschitz bound of d and a, relative: the slope allowed is
  /// lipschitz · (robust range of the signal) / (bounding-box diagonal), i.e. a signal may rise
  /// from its low to its high percentile over no less than 1/lipschitz of the diagonal.
  /// ≤ 0 disables the saturation.
  double lipschitz = 4;
  double low_percentile = 0.05;   ///< values below this quantile are clamped to it
  double high_percentile = 0.95;  ///< values above this quantile are clamped to it
  double anisotropy_cap = 10;     ///< raw anisotropy is capped here (> 1)
  /// Isotropy where the direction is incoherent: the saturated anisotropy's excess over its low
  /// level is multiplied by c^coherence_exponent, c = |z| ∈ [0, 1] the magnitude of the smoothed
  /// line field (1 where neighbouring directions agree, 0 at singularities and in strips where u
  /// turns by 90° within the smoothing length). Stretching cells along a direction that turns
  /// faster than the cells are long asks for a metric that no surface realises: M′ folds.
  /// 0 disables the blending.
  double coherence_exponent = 1;
};

/// The sizing field, per face of the mesh it was computed on.
struct Field {
  std::vector<Vec3> u;        ///< smoothed unit tangent direction (line field)
  std::vector<double> d;      ///< density in [1, D]
  std::vector<double> a;      ///< anisotropy in [1, A]
  std::vector<Vec3> u_raw;    ///< direction before smoothing
  std::vector<double> d_raw;  ///< the larger of the two measured stresses (stress units, ≥ 0)
  std::vector<double> a_raw;  ///< larger/smaller measured stress, in [1, anisotropy_cap]
  /// |z| of the smoothed line field in [0, 1] (see FieldOptions::coherence_exponent); may be
  /// empty (uniform or imported fields without smoothing).
  std::vector<double> coherence;

  int size() const { return static_cast<int>(u.size()); }
};

/// Whether two fields are the same bit for bit (every array, the raw values included): designs
/// made on them with the same seed and size are the same.
bool identical(const Field& a, const Field& b);

/// Per-face orthonormal tangent frame (t1, t2, n): t1 along the first edge, n the unit normal.
/// Throws Error("mesh", ...) for a degenerate triangle.
struct FaceFrames {
  std::vector<Vec3> t1, t2, n;
  std::vector<double> area;  ///< triangle areas (m²)
};
FaceFrames face_frames(const TriMesh& mesh);

/// The whole field stage: raw triple from `stress`, smoothing, saturation, rescaling.
/// `stress.size()` must equal the number of faces. Cost: one complex sparse Cholesky of size F plus
/// O(F log F). Throws Error for mismatched sizes, non-finite stresses or bad options.
Field make_field(const TriMesh& mesh, const StressField& stress, const FieldOptions& options);

/// Parses the option words of the conventions ("magnitude", "along", "rising", …); throws
/// Error(option, ...) naming the accepted words.
StressMeasure parse_stress_measure(const std::string& word);
StretchAxis parse_stretch_axis(const std::string& word);
DensityTrend parse_density_trend(const std::string& word);
const char* to_string(StressMeasure m);
const char* to_string(StretchAxis s);
const char* to_string(DensityTrend d);

/// The field of `--field uniform`: d = a = 1 everywhere, u = the first edge direction.
Field uniform_field(const TriMesh& mesh);

/// Options of the line-field smoothing.
struct LineFieldOptions {
  double smoothing = 0;  ///< smoothing length ℓ (m); ≤ 0 = 5% of the bounding-box diagonal
};

/// Smooths a line field (2-fold symmetric directions) per face. With z_f = e^{2iθ_f} in the face
/// frame, minimises  Σ_edges (l_e/h_e) |z_f − T_fg z_g|²  +  Σ_f (A_f ω_f / ℓ²) |z_f − z_f⁰|²
/// where T_fg is the discrete parallel transport across the shared edge (the edge keeps its
/// angle), l_e the edge length, h_e the distance between the two centroids, A_f the area and
/// ω_f ≥ 0 the faithfulness weight of face f (make_field uses 1 − 1/a_raw + 10⁻³). One sparse
/// Hermitian positive-definite solve of size F (complex LLᵀ, AMD ordering). Returns unit tangent
/// directions (the input direction where |z| vanishes). Directions are projected onto the face
/// planes first.
/// When `coherence` is given it receives |z_f| clamped to [0, 1]: 1 where the directions around
/// f agree, → 0 where they cancel (a singularity, or a strip where u turns by 90° within ~ℓ).
std::vector<Vec3> smooth_line_field(const TriMesh& mesh, const std::vector<Vec3>& directions,
                                    const std::vector<double>& weights,
                                    const LineFieldOptions& options = {},
                                    std::vector<double>* coherence = nullptr);

/// Upper saturation that keeps maxima: f'(p) = max_q ( f(q) − L · dist(p, q) ) with dist the
/// shortest path over the face graph (centroid to centroid through shared edges). Afterwards
/// f' ≥ f, max f' = max f, and |f'(p) − f'(q)| ≤ L · h_pq for adjacent faces. Dijkstra-like
/// sweep, O(F log F). L ≤ 0 returns f unchanged.
/// With `stretch` (per face: a unit tangent direction u and a factor a ≥ 1) the distances are
/// anisotropic: a step e from face f measures √((e·u_f / a_f)² + |e|² − (e·u_f)²), averaged over
/// the two faces of each pair, so along u the slope allowed per metre is L / a (for straight
/// paths; centroid paths on a triangle mesh zigzag across u, which dilutes this: 0.62 L instead
/// of L/3 for a = 3 on a chequerboard grid). make_field uses
/// this for d with the final (u, a): in M′ both directions then see the same bound (lengths along
/// u shrink by a there, which would otherwise steepen d's slope a-fold, and the metric's
/// curvature a²-fold: the cause of the folds of M′ on the barrel at D = A = 3).
struct SaturationStretch {
  const std::vector<Vec3>& u;
  const std::vector<double>& a;
};
std::vector<double> saturate_lipschitz(const TriMesh& mesh, const std::vector<double>& values,
                                       double L, const SaturationStretch* stretch = nullptr);

/// Clamps values to their [low, high] quantiles (nearest rank, so both bounds are values of the
/// input) and maps them linearly onto [1, top]: the result spans exactly [1, top]. When the
/// clamped range is empty (constant field) every value maps to 1.
std::vector<double> rescale_robust(const std::vector<double>& values, double top,
                                   double low_percentile = 0.05, double high_percentile = 0.95);

/// ParaView arrays per face: "u", "u_raw" (n×3), "d", "a", "d_raw", "a_raw", "coherence" (n×1).
io::Attributes field_attributes(const Field& field);

}  // namespace gridshell
