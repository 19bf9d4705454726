#pragma once
/// \file quad_aniso.h
/// `baseline --kind quad-aniso`: a quad-dominant grid-shell whose beams follow the field's two
/// directions (u and u⊥), with cells ∝ 1/d and stretched a-fold along u — the paper's second row
/// of Table 1 (a field-aligned quadrangulation, Panozzo et al. 2014).
///
/// Method (docs/quad_aniso.md). In the deformed surface M′ of metric/deform.h the field's metric
/// is Euclidean, so an isotropic quad mesh of M′ with spacing h, aligned with the image J u of
/// the field's direction, is — mapped back through the piecewise-linear map M′ → M — the
/// anisotropic, density-graded quad mesh wanted on M. On M′ (refined to edges ≤ h / resolution):
///   0. hierarchy: M′'s vertices paired with a neighbour level by level down to `coarsest`
///      vertices (Jakob et al. 2015); steps 1 and 2 solve on the coarsest level first and refine
///      level by level, each finer level starting from its parents' values;
///   1. orientation: per vertex a 4-direction (cross) field; the data is the 4-fold average of J u
///      over the incident triangles, weighted by area and by the field's anisotropy (where a = 1
///      the direction is no constraint; carried down the hierarchy), and every level
///      is smoothed by Gauss–Seidel sweeps with the data as a term weighted by its coherence
///      (strong where the field is, free where it cancels);
///   2. position: per vertex a lattice origin o_i in its tangent plane (spacing h × a factor
///      that follows the cross field's conformal scale within ±25 %, `integrable_scale`; axes of
///      the cross): on the coarsest level one lattice propagated breadth-first from a seeded random
///      offset; on every level Gauss–Seidel sweeps that average the neighbours' lattices brought
///      to the edge's middle (the 4 nearest lattice points of each side compared) and round the
///      result back to the lattice point nearest the vertex (the extrinsic smoothing of Jakob et
///      al. 2015, "Instant field-aligned meshes"; in vertex order: deterministic);
///   3. extraction: an edge whose ends carry the same lattice point is collapsed, one whose ends
///      differ by one lattice step along an axis becomes a beam; joints of degree ≤ 1 are pruned;
///      faces are walked with the beams ordered by angle around each joint, once on M′ and once
///      on M (each joint through the affine map of an incident triangle), and the walk whose
///      faces cover more of M is kept (M′ can be crushed where the metric changes fast, and its
///      order is then not the surface's); faces that are not simple, turn the wrong way or have
///      more than `max_face_sides` sides are left out; two faces of odd sides joined through ≤ 2
///      quads are re-split into quads (squarest quads, valences nearest 4, new beams nearest h),
///      remaining triangle pairs become quads;
///   4. mapping: each joint, carried to M as in step 3, is projected onto M, and joints on the
///      grid's outer boundary within `boundary_snap` × the local beam length of M's boundary are
///      moved onto it (so the boundary supports catch them); faces hanging on the grid by one
///      edge are peeled off and only the largest connected piece
///      is kept (mesh/topology.h: a flap or an island would be a near-mechanism in the analysis);
///      a face a third of whose sample points lie over a hole of M is left out (the extraction
///      walks loops around M′'s holes like any other face); last, where a beam of the grid's
///      boundary cuts off a corner of M (or a notch, `gap_joints`), the gap becomes a face whose
///      other side follows M's boundary, its corners new joints, so the grid reaches M's corners;
///      then step 3's pairing of odd faces once more on M, for odd faces inside whose partner is
///      a face of the rim (a row of cells that ends at the boundary); and faces that overlap
///      (mesh/overlaps.h: beams crossing, a joint inside a panel) are left out, thinner first.
/// Supports: transfer_supports (grids/supports.h), as the other baselines.
///
/// Cost: O(V · (orientation + position sweeps)) on M′ (the coarser levels add about as much again)
/// plus one sparse LDLᵀ of M′'s Laplacian (the spacing factor) and O(n log n) for the
/// extraction, times the lattice starts (`starts` per spacing, up to `max_starts` at the chosen
/// spacing of a small grid; the grid of the highest quality is kept; the starts of a spacing are
/// built in parallel, each with its own seed, so the result does not depend on the thread count);
/// the length fit repeats steps 2–4 (M′, the hierarchy and the cross field are computed once).
/// Step 4's gap filling locates each joint of the grid's boundary on M's boundary by a linear
/// scan: O(grid boundary joints × M's boundary edges) per grid, small beside the position field.

#include <cstdint>
#include <vector>

#include "gridshell/field/field.h"
#include "gridshell/grids/quad_grid.h"
#include "gridshell/mesh/mesh.h"
#include "gridshell/metric/deform.h"

namespace gridshell {

struct QuadAnisoOptions {
  double spacing = 0;  ///< h: quad size on M′ (m); ignored when `length` > 0
  double length = 0;   ///< total beam length wanted (m): h is fitted (secant on L ∝ 1/h)
  /// Relative: the fit stops at the first spacing whose best start is this close.
  double length_tolerance = 0.03;
  /// Relative: when no grid came within `length_tolerance`, the closest is kept if within this
  /// (±5 %), else Error. Among the grids within `length_tolerance` (every lattice
  /// start at every spacing tried) the one of the highest quality (`starts`) is kept.
  double length_limit = 0.05;
  int max_fits = 8;  ///< spacings tried by the fit (each with `starts` lattice starts)
  /// When no grid of the fit came within `length_limit` (a grid of a few dozen cells jumps by a
  /// row of cells between two spacings as close as the fit places them), up to this many more
  /// lattice starts are tried at the spacings of the closest grids above and below the target
  /// (with grids on one side only: there and at the fit's next spacing).
  int extra_starts = 16;
  double resolution = 2;  ///< M′ refined to edges ≤ h / resolution
  int orientation_iterations = 20;
  /// Gauss–Seidel sweeps of the position field on M′ and on each coarser level of the hierarchy
  /// (each level starts from its parents' lattices). Fewer sweeps are cheaper but not free: 20
  /// and 10 take 45 % of the CPU of 40 and 40 with about the same mean shares of valence-4 joints
  /// and quads, yet the runs that sit at the 85 % targets change sides (docs/quad_aniso.md).
  int position_iterations = 40;
  int coarse_position_iterations = 40;
  /// The hierarchy (Jakob et al. 2015) pairs neighbouring vertices of M′ level by level down to
  /// at most this many; both fields are solved on the coarsest level first, then refined level
  /// by level. 0: a single level (M′ only).
  int coarsest = 64;
  /// Smoothing length of the cross field, in units of h: the field's direction is followed at
  /// scales above about this fraction of a cell and smoothed below it (the data term's weight per
  /// neighbour is (e / 2ℓ)² × coherence × anisotropy weight, e the vertex's mean edge on M′, so
  /// the length does not depend on how finely M′ is meshed). A lattice cannot follow directions
  /// that turn within a cell: each turn it is made to follow costs dislocations, and their share
  /// per cell grows with h. A fixed weight of 4 per neighbour (ℓ ≈ e / 4 ≈ h / 15 on M′ refined
  /// to edges ≤ h / 2, mean edge ≈ 0.27 h) follows turns within a cell: docs/quad_aniso.md has
  /// the sweep.
  double direction_smoothing = 0.25;
  /// The field's direction is data for the cross field in proportion to its anisotropy: weight
  /// (a − 1) / (a_full − 1), capped at 1, with a_full this value or the field's largest a if
  /// smaller. Where the metric is isotropic any cross gives square cells, so following u there
  /// only adds singularities and lattice defects; weighting by a raised the mean shares of
  /// valence-4 joints and quads by 1.3 and 1.4 points over the 22 full-length anisotropic runs of
  /// docs/quad_aniso.md (a lower data weight without it: 0.3 at most). A field without
  /// anisotropy (A = 1) keeps full weight: its directions are then the only ones there are.
  /// ≤ 1: full weight everywhere (coherence only).
  double full_alignment_anisotropy = 3;
  /// The lattice's spacing on M′ is h × e^(κ s), κ this value: s is the conformal scale along
  /// which the cross field's turning needs no rows of cells to start (∇s = −J ∇θ; polar lines:
  /// cells ∝ r), so the lattice follows turning directions and M′'s curvature with fewer
  /// dislocations, at the price of cells departing from the size d asks for (bounded by
  /// `max_scale_change`). The field's own grading, log(d / √a), is taken out of s, so cells keep
  /// the sizes d asks for. 0: constant spacing. Against constant spacing, κ = 0.5 with a cap of
  /// 1.25 raised the runs of docs/quad_aniso.md's table that meet every target at full length
  /// from 31 to 33 of 33 (8 generated surfaces: 22 to 23 of 24) and the mean smaller share of
  /// valence-4 joints and quads of the 22 anisotropic full-length runs from 92.1 % to 93.7 %
  /// (docs/quad_aniso.md has the sweep of κ and the cap: κ = 1 at ±25 % and κ = 0.5 at ±50 % tie
  /// with this setting on the count).
  double integrable_scale = 0.5;
  /// The spacing factor stays within [1 / this, this] (≥ 1; 1: constant spacing).
  double max_scale_change = 1.25;
  int max_face_sides = 8;      ///< faces with more sides are left out (holes in the grid)
  double boundary_snap = 1.5;  ///< see step 4 (× the mean length of the joint's beams)
  /// Step 4's gaps between the grid's boundary and M's are filled where at most this many joints
  /// of the grid's boundary lie off M's boundary between two on it (and all of them have
  /// valence 4: they become interior joints). 0: only corners of M cut off by a single beam.
  /// Measured 3 against 0 (docs/quad_aniso.md): the same runs met every target
  /// (63 of 66 shared, 45 of 48 generated), 0.5 point more of M covered on the generated
  /// surfaces, the half-length runs' smaller share 0.2 points lower; 0 was kept.
  int gap_joints = 0;
  /// Faces of less than this fraction of the median face area are left out, after step 4's
  /// snapping and after its gap filling: slivers (all joints of a boundary cell snapped onto a
  /// straight piece of M's boundary) that no one would cut a panel for. 0: all kept.
  double min_face_area = 0.02;
  std::uint64_t seed = 1;
  /// Lattice starts tried per spacing by the length fit (seeds seed + 7919 k). Each grid's
  /// quality is quad_grid_quality (below). The fit follows
  /// the median length of the starts at each spacing; the result is the grid of the highest
  /// quality among all grids within `length_tolerance`. The seed alone moves these shares by
  /// several points (Shell at (3, 3): valence 4 from 81 % to 86 % over 4 seeds).
  int starts = 4;
  /// At the spacing of the grid chosen so far, more starts are tried, up to `start_cells` /
  /// (the grid's cells on M′) in all and at most `max_starts`: a grid of few cells is cheap to
  /// build again and its shares move most with the start (one defect among 40 joints is
  /// 2.5 points); a grid of 1000 cells or more gets none. The result is then chosen again.
  /// Because it is chosen by the figures docs/quad_aniso.md reports, those are the best of the
  /// starts, not those of one start.
  double start_cells = 4000;
  int max_starts = 32;
  DeformOptions deform;  ///< max_edge is set from h and `resolution`
};

struct QuadAnisoResult {
  GridShell grid;
  double spacing = 0;  ///< h on M′ of the result
  /// The lattice spacing on M′ is h × a factor per vertex (`integrable_scale`): its 10th and 90th
  /// percentiles over M′'s area (1 and 1 without it).
  double spacing_factor_p10 = 1, spacing_factor_p90 = 1;
  int fits = 0;  ///< spacings tried by the length fit
  /// Lattice starts at the spacing that got the extra ones (QuadAnisoOptions::start_cells; the
  /// result is chosen again after them and may come from another spacing).
  int starts = 0;
  int grids = 0;  ///< grids extracted (spacings × lattice starts, and any extra starts)
  int deformed_triangles = 0;
  int folded_edges = 0;  ///< of M′ (metric/deform.h)
};

/// Builds the grid on `surface` for `field` (per face of surface.mesh). Throws Error for bad
/// options, a field of the wrong size, an extraction without faces, or a length fit that does not
/// converge.
QuadAnisoResult quad_aniso(const Surface& surface, const Field& field,
                           const QuadAnisoOptions& options);

/// The quad mesh of a given M′ (same connectivity as `rest`, refined so its edges are well below
/// h) for the field per face of `rest`, spacing h on M′; joints on `rest` (not yet projected
/// onto another surface, no supports). Exposed for tests and the length fit.
PolyMesh quad_mesh_on_metric(const TriMesh& rest, const TriMesh& deformed, const Field& field,
                             double h, const QuadAnisoOptions& options);

/// The figures of docs/quad_aniso.md's acceptance, measured on a grid against the field of the
/// surface it was built on (field looked up at the nearest triangle centroid).
struct QuadMeshStats {
  int interior_joints = 0;
  double valence4_share = 0;  ///< interior joints with exactly 4 beams
  int interior_faces = 0;     ///< faces with no joint on the grid's boundary
  double quad_share = 0;      ///< of interior faces
  int non_simple_faces = 0;   ///< faces whose plan (best-fit plane) self-intersects
  /// Beams that cross and joints inside a panel not their own (mesh/overlaps.h): the grid covers
  /// part of the roof twice, and cannot be built.
  int overlaps = 0;
  double min_edge_ratio = 0;  ///< shortest beam / median beam
  /// Smallest face area / median face area: a sliver panel (joints of a boundary cell snapped
  /// onto a straight piece of M's boundary) shows here.
  double min_area_ratio = 0;
  /// Interior beams where the field's a ≥ `strong_a` (a at the beam's midpoint).
  int strong_beams = 0;
  double aligned_share = 0;  ///< of those, within `angle_deg` of u or u⊥
  /// Median quad aspect (mean length of its two edges nearer u / mean of the other two) over
  /// interior quads where a ≥ `aspect_a`; 0 when there are none.
  double median_aspect = 0;
  int aspect_quads = 0;
  double median_aspect_all = 0;  ///< max/min of the two mean opposite-edge lengths, all quads
  /// Area of the grid's faces / area of the surface: what the lattice's boundary cells leave
  /// uncovered (cells cut by M's boundary have no joints outside M; docs/quad_aniso.md).
  double coverage = 0;
};
struct QuadMeshStatsOptions {
  double strong_a = 2;
  double angle_deg = 15;
  double aspect_a = 2.5;
};
QuadMeshStats quad_mesh_stats(const PolyMesh& grid, const TriMesh& surface, const Field& field,
                              const QuadMeshStatsOptions& options = {});

/// How the lattice starts are ranked (higher is better), from four shares of QuadMeshStats:
/// interior joints of valence 4, interior faces with 4 sides, beams within 15° of u or u⊥ where
/// a ≥ 2 (1 when there are none: an isotropic field, or a grid too coarse to have interior beams
/// there), and the coverage of the surface (1 − |1 − coverage|: stacked faces would cover more
/// than the surface, as bad as less; remove_overlaps leaves them out before a grid is scored).
/// First by how many of them fall short of the bars of a good field-aligned quad grid (85 %
/// regular joints, 85 % quads, 70 % aligned beams, 90 % covered; docs/quad_aniso.md), then by
/// their sum: a grid fair in all beats one perfect in some and poor in another, which the sum
/// alone chose on grids of few cells, where one defect among 20 joints is 5 points (ranking by the bars first removed 4 of 8 such misses
/// of the generated surfaces). Coverage counts because a hole in the grid takes its joints and
/// faces out of the interior shares, so a start with a hole could otherwise rank first for it.
double quad_grid_quality(const QuadMeshStats& stats);

}  // namespace gridshell
