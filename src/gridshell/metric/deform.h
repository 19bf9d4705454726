#pragma once
/// \file deform.h
/// Stage 4 of the pipeline: turning the anisotropic sizing metric of a Field into a Euclidean one
/// by deforming the surface (Panozzo et al. 2014, "Frame fields: anisotropic and non-orthogonal
/// cross fields"; GUIDE.md stage 4, paper §4.1).
///
/// Per triangle t of M the target linear map M → M′ is, in the frame (u, u⊥) of the face,
///     S_t = diag(d/a, d):
/// lengths along u are scaled by d/a, lengths across u by d. An isotropic cell of size R on M′
/// therefore comes back to M with size R/d across u and R·a/d along u: cells ∝ 1/d, stretched
/// along u with aspect ratio a.
///
/// Normalisation: none beyond the field itself. d ≥ 1 and a ≥ 1 are used as given, so where
/// d = a = 1 (the sparsest, isotropic region) M′ has the size of M; everywhere else M′ is locally
/// d× larger across u. A radius R measured on M′ is the cell size on M in the sparsest region.
/// Area of M′ ≈ Σ_t area_t · d_t² / a_t.
///
/// Method: minimise Σ_t area_t ‖J_t − R_t S_t‖²_F (J_t the 3×2 Jacobian of the piecewise-linear
/// map from the face's (u, u⊥) coordinates, R_t a 3×2 orthonormal frame) plus a bending
/// regulariser μ Σ_v |Δ(x′ − x_ref)_v|²/area_v that stops the iterations from crumpling M′, by
/// local/global iterations: local = per-triangle polar decomposition (closed-form 2×2 eigen
/// solve, SVD fallback, TBB-parallel), global = one sparse SPD system (cotangent Laplacian of M
/// plus the bending matrix) with one vertex per connected component fixed, factorised once per
/// refinement level (CHOLMOD supernodal LLᵀ, converted to a simplicial factor for the solves) and
/// re-solved with three right-hand sides per iteration. Initial guess (and bending reference x_ref): the membrane-only Poisson solve with
/// R_t = (u, u⊥), i.e. the target Jacobians integrated in place; on refined levels x_ref is the
/// warm start.
///
/// Refinement: edges of M′ longer than max_edge (q = R/5) are split at their midpoint in both M
/// and M′ (red-green: 1, 2 or 3 split edges per triangle give 2, 3 or 4 children), the field is
/// copied from parent to children (so targets are unchanged: refinement only adds resolution),
/// a few iterations are re-run, and this repeats until no edge of M′ exceeds q.

#include <vector>

#include "gridshell/field/field.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct DeformOptions {
  /// q: maximum edge length of the final M′ (m in M′ units), normally R/5. ≤ 0 or infinite =
  /// no refinement.
  double max_edge = 0;
  /// Once some edge of M′ exceeds q, every edge longer than split_ratio·q is split (in (0, 1]):
  /// a margin below 1 saves refinement rounds (edges just under q tend to grow past it when
  /// the finer mesh is re-solved) at the price of a few more triangles.
  double split_ratio = 0.85;
  /// Weight of the bending regulariser μ Σ_v |Δ(x′ − x_ref)_v|²/area_v (interior vertices, Δ the
  /// cotangent Laplacian of M, x_ref the initial M′ of the level) with μ = bending · h², h the
  /// mean edge length of the input mesh, the same on every refinement level (the regulariser
  /// must not fade as the mesh is refined, else M′ creases on the fine levels). Without it the
  /// local/global iterations crumple M′ (folded triangles) where the metric is not realisable. 0 =
  /// pure membrane energy.
  double bending = 1;
  /// A refinement round that splits fewer than this fraction of the edges is not followed by a
  /// re-solve: midpoint splits leave M′ the same piecewise-linear map (children carry the
  /// parent's target), so only the new factorisation would be paid for. 0 = always re-solve.
  double resolve_fraction = 0.02;
  int iterations = 30;  ///< local/global iterations on the input mesh (≥ 0)
  /// The first of those iterations run without the bending term; their result is the bending
  /// reference. The initial guess (the targets integrated in place) can have folds, which a
  /// regulariser against it would keep (Aquadom at D = A = 3: 3 folded edges that the bending
  /// iterations kept; 5 membrane iterations remove them).
  int membrane_iterations = 5;
  int refine_iterations = 8;  ///< local/global iterations after each refinement round
  int max_rounds = 16;        ///< refinement rounds before giving up (Error)
  int max_faces = 4'000'000;  ///< refined size limit (Error beyond)
};

struct Deformed {
  TriMesh rest;                  ///< refined M (on the input surface's triangles)
  TriMesh deformed;              ///< M′, same connectivity as rest
  Field field;                   ///< the field per refined face (copied from the parent face)
  std::vector<int> parent_face;  ///< refined face → face of the input mesh
  int rounds = 0;                ///< refinement rounds performed
  int iterations = 0;            ///< local/global iterations performed in total
  /// Relative residual Σ area ‖J − R S‖² / Σ area ‖S‖² at the end (0 = metric met exactly).
  double residual = 0;
  double max_edge = 0;  ///< longest edge of M′ at the end
  /// Interior edges of M′ whose two triangles face opposite ways (dihedral fold > 90°): 0 for a
  /// healthy deformation; it grows when D or A are pushed much beyond ~4.
  int folded_edges = 0;
};

/// Deforms `mesh` so that the field's metric becomes Euclidean on M′, refining until every edge
/// of M′ is ≤ options.max_edge. `field` must have one entry per face with u tangent (it is
/// re-projected) and d, a > 0. Cost per iteration O(F) plus one triangular solve with 3
/// right-hand sides; one sparse Cholesky per refinement round. Throws Error for mismatched sizes,
/// degenerate triangles, non-finite values, or when the limits (rounds, faces) are reached.
Deformed deform_metric(const TriMesh& mesh, const Field& field, const DeformOptions& options);

/// Measured stretch of the map rest → deformed per face: |J u| (along u) and |J u⊥| (across u),
/// to compare with the targets d/a and d. Same connectivity required.
struct Stretch {
  std::vector<double> along, across;
};
Stretch measure_stretch(const TriMesh& rest, const TriMesh& deformed, const Field& field);

/// Splits every edge of `deformed` longer than `max_edge` at its midpoint in both meshes (same
/// connectivity), red-green style; appends to `parent` (child → parent face index in the input
/// of this call). Returns the number of edges split. Exposed for tests.
int split_long_edges(TriMesh& rest, TriMesh& deformed, double max_edge, std::vector<int>& parent);

}  // namespace gridshell
