#pragma once
/// \file tessellation.h
/// The tessellation engine (GUIDE stages 5–9): a centroidal Voronoi tessellation of a surface
/// under a general metric, extracted as a hex-dominant polygon mesh.
///
/// Input: the rest surface M (where the output lives) and a deformed surface M' with the same
/// connectivity (the metric: distances, areas and centroids are measured on M'; M' = M gives the
/// uniform, isotropic tessellation). Method:
///  1. support mesh: M and M' refined together until every edge of M' is ≤ `support_edge`·R;
///  2. seeds: sharp boundary corners (fixed), evenly spaced seeds along every boundary loop
///     between corners (the fixed point of 1-D Lloyd along the loop, in M' arc length), 2-D
///     Poisson-disk sampling of the interior constrained by those (seeded `Rng`);
///  3. CVT optimisation: the restricted Voronoi diagram (Euclidean in M') is computed exactly
///     on the support mesh (every vertex labelled with its nearest seed, every triangle with
///     several labels clipped by the bisector planes of the seeds around it), giving the CVT
///     energy and its gradient 2 m_i (s_i − c_i); L-BFGS (LBFGS++) minimises it with the seeds
///     kept on the surface (projected onto their region's triangles, gradient in the tangent
///     plane; seeds are surface points: triangle + barycentrics, no snapping) until the RMS
///     Lloyd move is below `tolerance`·R (plain over-relaxed Lloyd with `quasi_newton` = false);
///  4. extraction: the support mesh is refined to `extraction_base`·R, the edges crossing cell
///     borders further; Voronoi vertices are placed at the exact equidistant points in 3-label
///     triangles and on boundary edges, plus boundary corners; borders are traced into polygon
///     edges; every region is checked to be a disk bounded by one cycle and the output to be a
///     manifold with the input's Euler characteristic and boundary loops (repaired by local
///     refinement, else Error); a cell whose Euclidean region falls into several pieces keeps
///     its largest piece, the others join the neighbour they share most border with;
///  5. output positions mapped back onto M through (triangle, barycentrics).
///
/// Cost: O(support triangles) per diagram (≈ 6 R⁻² · area triangles at support_edge 0.6), about
/// 50–170 diagrams; see docs/voronoi.md for measured times.

#include <cstdint>
#include <map>
#include <vector>

#include "gridshell/core/error.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct TessellationOptions {
  /// Cell size R on M' in metres: the circumradius of a regular hexagonal cell (≈ its edge
  /// length, i.e. the beam length). At most one of radius / cells / length may be set;
  /// none set = `default_cells` cells.
  double radius = 0;
  int cells = 0;      ///< cells (faces) wanted; exact unless below boundary seeds + 1
  double length = 0;  ///< total edge length on M wanted (m), held within `length_tolerance`
  /// The one tolerance of `--length` (a share of the target): the tessellation aims at 0.4 of
  /// it and warns beyond it; `design` tessellates once more when its finishing step moves the
  /// total by more than 0.9 of it (pipeline/design.cpp, length control).
  double length_tolerance = 0.05;
  /// Edges with both ends on one of these planes (within 1e-6 of the bounding-box diagonal) do
  /// not count towards `length`. A symmetric design tessellates a sector cut along its mirror
  /// planes; the cells on a plane merge with their mirror images there, so those edges are not
  /// beams of the final grid-shell.
  std::vector<Plane> length_excluded_planes;
  int default_cells = 300;
  std::uint64_t seed = 1;    ///< seeds the Poisson sampling
  int max_iterations = 300;  ///< CVT diagrams (L-BFGS evaluations or Lloyd steps) at most
  /// Stop when the seeds' RMS distance to their region's centroid (the Lloyd move) is below
  /// tolerance·R.
  double tolerance = 5e-4;
  /// Support-mesh edges ≤ support_edge·R on M' while the CVT is optimised. The diagram is clipped
  /// exactly on the planar triangles, so this only needs to be fine enough for every cell meeting
  /// a triangle to label one of its corners or its neighbours' opposite corners; the borders are
  /// refined to extraction_edge·R before extraction.
  double support_edge = 0.6;
  /// Optional first level on a coarser support mesh (edges ≤ coarse_edge·R) until seeds move
  /// less than coarse_tolerance·R, then ≤ fine_iterations Lloyd steps on the support_edge mesh.
  /// coarse_edge ≤ support_edge: one level (the default).
  double coarse_edge = 0;
  double coarse_tolerance = 1e-3;
  int fine_iterations = 30;      ///< at most this many iterations on the fine level
  double over_relaxation = 1.7;  ///< Lloyd step factor ω (1 = plain Lloyd, < 2)
  /// Optimise by L-BFGS on the CVT energy (Liu et al. 2009) instead of Lloyd steps.
  bool quasi_newton = true;
  int lbfgs_history = 7;  ///< L-BFGS correction pairs kept
  /// Before extraction the whole support mesh is refined to edges ≤ extraction_base·R (0 = not),
  /// then the edges crossing cell borders to ≤ extraction_edge·R.
  double extraction_base = 0.3;
  double extraction_edge = 0.05;  ///< border-crossing edges refined to ≤ this·R before extraction
  int extraction_passes = 3;      ///< refinement passes at most for that
  double corner_angle_deg = 30;   ///< boundary turning angle above which a vertex is a corner
  double boundary_spacing = 1.0;  ///< boundary seed spacing in units of √3·R (hex seed spacing)
  /// Boundary edges of the output (chords between consecutive boundary joints, ≈ √3·R long
  /// between boundary seeds) are divided along the input boundary into round(chord /
  /// (boundary_split·R)) pieces; the extra joints have valence 2. 0 = keep them whole.
  double boundary_split = 1.0;
  /// Output edges shorter than stub_length·R with an end on the boundary are collapsed into
  /// that end (a corner is never moved). 0 = keep them.
  double stub_length = 0.2;
};

/// Quality figures of a polygon mesh (the tessellation's acceptance figures).
struct TessellationQuality {
  int vertices = 0, faces = 0, edges = 0;
  int interior_vertices = 0;           ///< vertices not on the boundary
  int interior_faces = 0;              ///< faces with no vertex on the boundary
  double valence3_share_interior = 0;  ///< share of interior vertices of valence 3
  double hex_share_interior = 0;       ///< share of interior faces with 6 sides
  double edge_length_mean = 0;         ///< m
  double edge_length_cv = 0;           ///< standard deviation / mean of all edge lengths
  double edge_length_min = 0;          ///< m
  double total_length = 0;             ///< sum of edge lengths, m
  std::map<int, int> face_sides;       ///< number of sides → number of faces
  int euler = 0;                       ///< V − E + F
  int boundary_loops = 0;
  bool manifold = false;  ///< check_mesh found no problem
};

TessellationQuality measure_quality(const PolyMesh& mesh);

struct Tessellation {
  PolyMesh mesh;                     ///< on the rest surface M; one face per seed
  std::vector<int> supports;         ///< output vertices that are supports, sorted
  std::vector<char> on_boundary;     ///< per output vertex
  std::vector<char> corner;          ///< per output vertex: a sharp corner of the input
  std::vector<int> vertex_triangle;  ///< per output vertex: triangle of the ORIGINAL M
  std::vector<Vec3> vertex_bary;     ///< per output vertex: barycentrics in that triangle
  std::vector<Vec3> seeds;           ///< per face: its seed, on M
  double radius = 0;                 ///< R used (m, on M')
  int iterations = 0;                ///< CVT diagrams computed (final run): L-BFGS or Lloyd steps
  bool converged = false;            ///< the CVT met `tolerance` before `max_iterations`
  int support_vertices = 0;          ///< support-mesh size used for Lloyd
  int length_runs = 1;               ///< tessellations computed to meet `length`
  int repairs = 0;                   ///< extraction repairs (local refinements) needed
  /// Support vertices moved at extraction from a detached piece of a cell's Euclidean region
  /// (M′ bending back within a cell size) to the neighbouring cell (final attempt).
  int orphan_vertices = 0;
  TessellationQuality quality;
  double seconds_setup = 0;       ///< support mesh and seeding (final run)
  double seconds_lloyd = 0;       ///< Lloyd relaxation (final run)
  double seconds_extraction = 0;  ///< refinement, extraction, checks, supports (final run)
};

/// Tessellates `rest` under the metric of `deformed` (same connectivity). `rest_supports`:
/// supported vertex ids of `rest`. A boundary output vertex is a support when the input boundary
/// edge it lies on has both ends supported, or its nearest end supported; a supported corner
/// stays supported; every supported input vertex off the boundary makes its nearest output
/// vertex a support. Deterministic for `options.seed`. Throws Error for bad input (non-manifold
/// surface, mismatched meshes, bad options) or when no valid mesh can be extracted.
/// The one tessellation failure that another seed or a softer field may cure: no valid polygon
/// mesh could be extracted (a cell not a disk after the repairs). Everything else is an Error
/// of the input or the options.
class ExtractionError : public Error {
 public:
  using Error::Error;
};

/// Throws Error for size options that can never work (several of radius/cells/length, negative
/// values, non-positive tolerances): called by tessellate, and by callers before other work.
void check_tessellation_options(const TessellationOptions& options);

Tessellation tessellate(const TriMesh& rest, const TriMesh& deformed,
                        const std::vector<int>& rest_supports, const TessellationOptions& options);

/// Lower-level access for benchmarks: one Lloyd iteration on a given support mesh.
struct LloydBenchmark {
  int support_vertices = 0, seeds = 0;
  double seconds = 0;   ///< wall time of one iteration (labelling + clipping + centroids)
  double max_move = 0;  ///< largest seed move in that iteration (m)
};
/// Builds the support mesh of `surface` for about `cells` seeds with support edges ≤
/// `support_edge`·R, seeds it, runs `warmup` iterations, then times one more.
LloydBenchmark benchmark_lloyd(const TriMesh& surface, int cells, double support_edge, int warmup,
                               std::uint64_t seed = 1);

}  // namespace gridshell
