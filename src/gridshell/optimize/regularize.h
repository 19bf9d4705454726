#pragma once
/// \file regularize.h
/// The paper's finishing stage (§Regularization; GUIDE stage 10) and the ShapeUp planarity
/// projection it is compared with. Both alternate a per-face step (each face proposes target
/// positions for its vertices) and a per-vertex step, then bring the vertices back onto the
/// input surface M: free vertices onto M (closest point: a walk over M's triangles from the
/// last one, the AABB tree where the walk is unsure), boundary vertices onto M's boundary
/// polylines, fixed vertices (corners) never move. Topology never changes.
///
/// Per-face step, `regularize`: `regular_targets` (metrics.h) — PCA un-stretch, regular polygon
/// of equal perimeter, best rigid 2-D alignment, re-stretch (partly: `restretch`), then scaled
/// towards an anchored size (`size_anchor`, `size_evening`). `planarize`: `plane_targets` —
/// projection onto the best-fit plane (Bouaziz et al. 2012, "Shape-Up").
///
/// Per-vertex step:
/// - `Solver::global` (default) — the ShapeUp global step: minimise
///   Σ_f w_f |N_f x_f − N_f t_f|² + w Σ_v |x_v − x̄_v|² over the non-fixed vertices, where N_f
///   removes the face's mean (targets are translation-free, so the faces are not dragged back to
///   where they were), t_f are the face targets and x̄_v the current (on-surface) position. The
///   matrix depends only on the connectivity and is factorised once (CHOLMOD); each iteration is
///   one back-substitution with 3 right-hand sides. w = `closeness` keeps the step on the surface.
/// - `Solver::local` — the authors' scheme: each vertex moves to the damped average of its
///   targets, x ← x + damping (mean targets − x). Slow to converge; kept for comparison
///   (use damping ≤ 1 with it).
/// Then, before the projection, the planarity guard (`planarity_guard`) moves free vertices along
/// M's tangent planes where faces have become less planar than in the input.
/// Iterations stop when the largest vertex move is below `tolerance` × bbox diagonal, when the
/// energy stalls (`energy_tolerance`), or at `max_iterations`. The iterate with the lowest energy
/// is returned (the surface projection makes the alternation non-monotone; late iterations can
/// let faces drift, as the paper's stretch- and scale-invariant target has null directions).
///
/// Cost per iteration: O(Σ face sizes) for the targets and the guard (parallel, TBB), one sparse
/// triangular solve pair, and one short walk per vertex (parallel); 10 K polygons ≈ 14–17 ms on
/// two cores. Deterministic for any thread count.

#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

class SurfaceProjector;

/// How a vertex may move.
enum class VertexConstraint : unsigned char {
  free,      ///< stays on M
  boundary,  ///< slides along M's boundary polylines
  fixed      ///< never moves (corners, prescribed supports)
};

/// Constraints from the polygon mesh itself: vertices on its boundary slide along M's boundary;
/// boundary vertices where the mesh boundary turns by more than `corner_angle_deg`, and boundary
/// vertices used by a single face (valence 2), are fixed; all others are free.
std::vector<VertexConstraint> classify_vertices(const PolyMesh& mesh,
                                                double corner_angle_deg = 30.0);

/// Constraints from per-vertex flags of the tessellation: corner → fixed, on_boundary →
/// boundary, else free. Both vectors one entry per vertex (corner may be empty).
std::vector<VertexConstraint> constraints_from_flags(const std::vector<char>& on_boundary,
                                                     const std::vector<char>& corner);

struct RegularizeOptions {
  enum class Solver { global, local };
  Solver solver = Solver::global;
  /// hard: after each step every vertex is put back onto M (its boundary), so the result lies on
  /// M to rounding. soft (global solver only): the stay-close term pulls towards the closest
  /// point of M instead of the current position and nothing is projected — ShapeUp's
  /// closeness constraint; vertices end near M (see RegularizeStats::max_surface_distance).
  /// Planarity and exact on-surface vertices conflict (a planar panel's vertices must leave a
  /// curved M), so `planarize` defaults to soft; `regularize` uses hard.
  enum class Projection { hard, soft };
  Projection projection = Projection::hard;
  int max_iterations = 30;
  double tolerance = 1e-5;    ///< stop when the max vertex move < tolerance × bbox diagonal of M
  /// stop when the energy (RegularizeStats) fell by less than this fraction over 3 iterations
  double energy_tolerance = 1e-3;
  double closeness = 1.0;  ///< global: weight w of the stay-close term (per vertex)
  /// Fraction of the per-vertex step taken, (0, 2]: < 1 damps (the authors' scheme uses
  /// damping), > 1 over-relaxes. Default 1.5 for the global solver (measured: reaches in 30
  /// iterations 96–99% of the regularity gain of 100 damped-average iterations).
  double damping = 1.5;
  /// regularize: a face's target is never more stretched than the input face was (its PCA
  /// ratio σ1/σ2 × this factor). The paper's target is invariant to stretching a face, so
  /// without a cap faces drift towards slivers over many iterations. ∞ = uncapped.
  double stretch_growth = 1.0;
  /// regularize: exponent β in [0, 1] of the input face's stretch given back to its target, i.e.
  /// the target's stretch is at most (σ1/σ2 of the input face)^β × stretch_growth. 1 = the
  /// paper's re-stretch (the cells keep all the anisotropy the field asked for); 0 = isotropic
  /// regular polygons, which is what the authors' library does (VCGlib's SmoothPCA builds its
  /// templates with force_isotropy) and why it evens out beam lengths more. Default 0.7, measured
  /// with the size anchor and evening below on the six shared surfaces at D = A = 3 and on five
  /// built-ins (docs/regularization.md): rounder targets (smaller β) give flatter panels on domes
  /// (a regular polygon on a sphere is planar, a stretched one is not), more stretch flatter ones
  /// on Shell.ply; 0.7 keeps every shared surface within 1.10× raw planarity.
  double restretch = 0.7;
  /// regularize: how strongly each target is scaled to its face's anchored size: 0 = the target
  /// has the perimeter of the current (un-stretched) face, as in the paper (scale-invariant: a
  /// face's size is then free, and clipped cells at the boundary inflate); 1 = the target has
  /// the anchored size exactly (rms radius √(σ1σ2)); in between = geometric blend. Default 0.5.
  double size_anchor = 0.5;
  /// regularize: γ in [0, 1]. The anchored size of face f is g_f^(1−γ) G^γ, g_f its size in the
  /// input, G the geometric mean of all g_f: 0 keeps the sizes the density field asked for, 1
  /// pulls every cell towards the mean size. Default 0.8, measured on the six shared surfaces at
  /// D = A = 3 (docs/regularization.md): beam lengths are only made uniform (edge CV ≤ 0.75× raw)
  /// by evening out cell sizes — on Botanic the spread between the cells' mean edge lengths alone
  /// is 0.77× the raw CV — at the price of part of the density contrast (the spread of
  /// log(cell area) falls to 0.5–0.8× raw). The authors' library evens sizes too (a Laplacian
  /// term in VCGlib's SmoothPCA).
  double size_evening = 0.8;
  /// global: weight of the boundary fairing term w Σ_b |x_b − (x_p + x_n)/2|² over the sliding
  /// boundary vertices b (p, n: their neighbours along the boundary). 0 = off. Without it the
  /// clipped cells along the edge pull the boundary joints into uneven spacing.
  double boundary_fairing = 4.0;
  /// hard projection: weight w of the planarity guard (0 = off). After each per-vertex step, every
  /// face that has become less planar than it was in the input pulls its free vertices along
  /// M's tangent planes so that their heights over its plane shrink by the excess (a vertex
  /// takes half of argmin Σ_f (s_f h_f + a_f·u)² + |u|²/w; regularize.cpp, guard_planarity).
  /// Projecting onto M drops the normal part of every move, and with it any pull towards flat
  /// panels; on the saddle-shaped Shell.ply the panels then came out 1.10–1.13× less planar
  /// than raw. Default 33: Shell 1.07–1.10×, regularity gains 2% lower (docs/regularization.md).
  double planarity_guard = 33.0;
  /// global: the stay-close term pulls towards the input positions (true) or the current ones.
  bool anchor_to_input = false;
};

struct RegularizeStats {
  int iterations = 0;                ///< iterations run
  bool converged = false;            ///< max move or energy decrease fell below its tolerance
  double max_move = 0;               ///< last iteration's max vertex move / bbox diagonal
  double max_surface_distance = 0;   ///< max distance of a free/boundary vertex to M / diagonal
  std::vector<double> move_history;  ///< max move / diagonal per iteration
  /// Energy mean_f Σ_i |x_i − t_i|² / area_f at each iterate (index 0 = the input projected
  /// onto M); for `regularize` this is the regularity with the capped/anchored targets.
  std::vector<double> energy_history;
  double energy = 0;              ///< energy of the returned iterate (the lowest seen)
  int best_iteration = 0;         ///< which iterate is returned (0 = the input)
  double seconds = 0;             ///< wall time, setup (factorisation, trees) included
  double setup_seconds = 0;       ///< AABB trees + factorisation
  double targets_seconds = 0;     ///< per-face steps and energies, all iterations (wall)
  double solve_seconds = 0;       ///< per-vertex steps (wall)
  double projection_seconds = 0;  ///< reprojection onto M (wall)
};

/// Regularises `mesh` (lying on or near `surface`) towards stretched regular polygons.
/// `constraints` has one entry per vertex (empty = classify_vertices(mesh)).
/// Throws Error for a constraint list of the wrong size, bad faces, or invalid options.
PolyMesh regularize(const PolyMesh& mesh, const TriMesh& surface,
                    const std::vector<VertexConstraint>& constraints = {},
                    const RegularizeOptions& options = {}, RegularizeStats* stats = nullptr);

/// Same with a prebuilt projector for M (saves the AABB construction when called repeatedly).
PolyMesh regularize(const PolyMesh& mesh, const SurfaceProjector& surface,
                    const std::vector<VertexConstraint>& constraints,
                    const RegularizeOptions& options, RegularizeStats* stats = nullptr);

/// ShapeUp planarity projection: flatter panels, less regular faces. Same constraints, options
/// and stopping rule as `regularize`, except that `options.projection` is taken as soft
/// (stay-close term to M; use `planarize_options()` for the defaults used in tests).
/// Defaults for `planarize`: soft projection, closeness 0.1, up to 300 iterations.
RegularizeOptions planarize_options();

PolyMesh planarize(const PolyMesh& mesh, const TriMesh& surface,
                   const std::vector<VertexConstraint>& constraints = {},
                   const RegularizeOptions& options = {}, RegularizeStats* stats = nullptr);

}  // namespace gridshell
