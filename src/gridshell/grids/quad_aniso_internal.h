#pragma once
/// \file quad_aniso_internal.h
/// Internal to src/gridshell/grids/: what the stages of `quad_aniso` (quad_aniso.h, the API and
/// the method) share, and which file does which stage. Nothing here is used outside this folder.
///
/// | file                          | stage                                                     |
/// |-------------------------------|-----------------------------------------------------------|
/// | quad_aniso_cross_field.cpp    | steps 0–1 and the spacing factor, once per M′: hierarchy, |
/// |                               | cross field per level, matched neighbour frames,          |
/// |                               | `integrable_scale` (`metric_frames`)                      |
/// | quad_aniso_position_field.cpp | step 2: the lattice origin per vertex (`position_field`)  |
/// | quad_aniso_extraction.cpp     | step 3: joints, beams, faces traced on M′ and on M; the   |
/// |                               | joints carried to M (`quad_mesh_from_frames`)             |
/// | quad_aniso_odd_faces.cpp      | the quad-dominant clean-up of faces of an odd number of   |
/// |                               | sides (`pair_odd_faces`), on M′ and again on M            |
/// | quad_aniso_cleanup.cpp        | step 4 on M: boundary snap, slivers, hanging faces, gaps  |
/// |                               | to M's boundary, pairing with the rim, overlaps, the      |
/// |                               | largest part per piece of M (`clean_up_on_surface`)       |
/// | quad_aniso_length_fit.cpp     | the lattice starts and the secant fit of the spacing to   |
/// |                               | --length; the choice of the result (`CandidatePool`)      |
/// | quad_aniso.cpp                | `quad_aniso`: options, M′, the steps above in order       |
///
/// Every stage is deterministic for a seed: the lattice starts of a spacing are built in
/// parallel, each with its own seed, and kept in the order of their starts.

#include <array>
#include <cstdint>
#include <functional>
#include <set>
#include <utility>
#include <vector>

#include "gridshell/field/field.h"
#include "gridshell/grids/quad_aniso.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/mesh.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/projector.h"

namespace gridshell::quad_aniso_internal {

// ---------------------------------------------------------------------------------------------
// Frames on M′ (quad_aniso_cross_field.cpp)

/// A cross field on M′'s vertices: normal n, the cross's first arm q and t = n × q.
struct CrossField {
  std::vector<Vec3> n, q, t;
};

/// One level of the multiresolution hierarchy on M′ (level 0: M′'s vertices; each coarser level
/// pairs neighbouring vertices of the finer one, as Jakob et al. 2015 do): position, normal,
/// area, neighbours, and per vertex its parent on the next coarser level.
struct Level {
  std::vector<Vec3> p, n;
  std::vector<double> area;
  std::vector<std::vector<int>> nbr;
  std::vector<int> parent;
  int size() const { return static_cast<int>(p.size()); }
};

/// Per vertex of a level, per neighbour (in `nbr` order, flattened from `offset[v]`): the
/// neighbour's cross arms matched to the vertex's. The cross field does not change while the
/// position field is smoothed, so this is computed once per level and M′.
struct MatchedFrames {
  std::vector<int> offset;
  std::vector<Vec3> q, t;
};

/// What does not depend on the spacing or the lattice's start, computed once per M′: topology,
/// hierarchy, cross field per level and the matched neighbour frames of each level.
struct MetricFrames {
  Topology topo;
  std::vector<Vec3> pos;
  std::vector<Level> levels;
  std::vector<CrossField> cfs;
  std::vector<MatchedFrames> matched;
  std::vector<std::vector<double>> scale;  ///< per level and vertex: the lattice spacing / h
  std::vector<Vec3> rest_normal;           ///< per vertex of M (refined as M′): unit normal
  double scale_p10 = 1, scale_p90 = 1;     ///< of scale[0], weighted by M′'s vertex areas
};

/// Everything of M′ that steps 2–4 reuse for every spacing and lattice start: M′'s topology and
/// vertices, the hierarchy (down to `o.coarsest` vertices), the cross field of each level, the
/// spacing factor (`o.integrable_scale`) and M's vertex normals. `h` is the spacing M′ was
/// refined for (it scales the cross field's smoothing). Throws Error when M, M′ and the field do
/// not match.
MetricFrames metric_frames(const TriMesh& rest, const TriMesh& def, const Field& field, double h,
                           const QuadAnisoOptions& o);

/// A unit vector perpendicular to n (deterministic).
Vec3 any_perpendicular(const Vec3& n);

/// The one of ±q, ±n×q closest to `target`: q's cross brought to agree with target's.
Vec3 match_cross(const Vec3& q, const Vec3& n, const Vec3& target);

// ---------------------------------------------------------------------------------------------
// Position field (quad_aniso_position_field.cpp)

/// The two lattice points, one of each side's lattice, nearest each other near the middle of
/// the edge v0 v1 (the 4 corners of the cell around the middle compared on each side).
std::pair<Vec3, Vec3> compat_position(const Vec3& v0, const Vec3& q0, const Vec3& t0,
                                      const Vec3& o0, double h0, const Vec3& v1, const Vec3& q1,
                                      const Vec3& t1, const Vec3& o1, double h1);

/// Step 2: the position field (a lattice origin per vertex): on the coarsest level one lattice
/// propagated breadth-first from a seeded random origin, then smoothing; each finer level starts
/// from its parents' origins (brought into its tangent plane, rounded) and is smoothed again.
/// Returns level 0's origins.
std::vector<Vec3> position_field(const std::vector<Level>& levels,
                                 const std::vector<CrossField>& cfs,
                                 const std::vector<MatchedFrames>& matched,
                                 const std::vector<std::vector<double>>& scale, double h,
                                 const QuadAnisoOptions& o);

// ---------------------------------------------------------------------------------------------
// Extraction (quad_aniso_extraction.cpp)

/// The joints: vertices of M′ collapsed to their lattice points (cluster per vertex, mean
/// position and normal, vertex count), and the edges of M′ that cross one lattice step.
struct LatticeJoints {
  int count = 0;
  std::vector<int> cluster;
  std::vector<Vec3> pos, normal;
  std::vector<int> vertices;
  std::vector<std::array<int, 2>> steps;
};

/// Steps 2–4 for one spacing `h` and one lattice start (o.seed): the position field, the joints
/// and faces (traced on M′ and on M, the better kept), the odd faces paired, and the joints on
/// `rest` (projected onto it, not yet onto the input surface). Throws Error for a spacing that is
/// not positive or an extraction without faces.
PolyMesh quad_mesh_from_frames(const MetricFrames& m, const TriMesh& rest, const TriMesh& def,
                               double h, const QuadAnisoOptions& o);

// ---------------------------------------------------------------------------------------------
// Faces of an odd number of sides (quad_aniso_odd_faces.cpp)

/// Two triangles sharing an edge are a quad cut by a diagonal (a lattice step taken across a
/// seam of the position field): the edge is removed, longest shared edges first.
void merge_triangle_pairs(std::vector<std::vector<int>>& faces, const std::vector<Vec3>& p);

/// A triangle left among quads is a lattice defect with two joints of valence ≥ 5 on one of its
/// edges: that edge (the longest such one with a quad on its other side) is removed, leaving a
/// pentagon and two joints of valence 4 (the share of quads is unchanged but for one face).
void absorb_lone_triangles(std::vector<std::vector<int>>& faces, const std::vector<Vec3>& p);

/// Quad-dominant clean-up on M′. Where the position field has a seam (a row of cells that starts
/// or ends, a half-step shift between two lattices) the extraction leaves faces of an odd number
/// of sides: two triangles (a quad cut by its diagonal), a triangle and a pentagon (a
/// T-junction), a wedge-shaped triangle where a row of cells begins. Two odd faces joined by a
/// path of at most `max_quads_between` quads (sharing one beam each step) make a polygon of an
/// even number of sides (≤ 10); it is re-split into quads by diagonals chosen for the squarest
/// quads and valences nearest 4 (faces of 6 or 8 sides alone likewise). Cheapest first, each
/// face used once; a split whose quads are far from square (badness > 4 × 0.4² per quad: a
/// corner outside about 50°–130°) is not made.
///
/// `h` is the length a new beam should have; h = 0 takes each polygon's mean side instead (on M,
/// where cells vary in size and shape). With `on_rim` (one flag per face) non-empty, only pairs
/// with a face on the rim are made (and faces of 6 or 8 sides on the rim alone).
void pair_odd_faces(std::vector<std::vector<int>>& faces, const std::vector<Vec3>& p,
                    const std::vector<Vec3>& normal, double h, int max_quads_between = 2,
                    const std::vector<char>& on_rim = {});

// ---------------------------------------------------------------------------------------------
// Clean-up on M (quad_aniso_cleanup.cpp)

/// The connected pieces of M (two roofs in one file): per triangle the id of its piece, and
/// whether there is more than one.
struct SurfacePieces {
  std::vector<int> of_triangle;
  bool several = false;
};
SurfacePieces surface_pieces(const TriMesh& mesh);

/// Step 4 on M for a grid of quad_mesh_from_frames: its joints projected onto M (`mesh`, whose
/// projector is `proj`), then moved onto M's boundary where near it (`o.boundary_snap`), slivers
/// (`o.min_face_area`) and hanging faces left out, gaps to M's boundary filled (`o.gap_joints`),
/// odd faces paired with the rim's, overlapping faces left out; after each of the steps that can
/// cut the grid apart only its largest connected part on each piece of M is kept (a flap or an
/// island would be a mechanism, or nearly, in the analysis).
PolyMesh clean_up_on_surface(PolyMesh grid, const TriMesh& mesh, const SurfaceProjector& proj,
                             const SurfacePieces& pieces, const QuadAnisoOptions& o);

// ---------------------------------------------------------------------------------------------
// Lattice starts and the length fit (quad_aniso_length_fit.cpp)

/// One lattice start at one spacing: the grid on M, cleaned up, its total length, its relative
/// error against --length (0 without one) and its quality (quad_grid_quality).
struct Candidate {
  PolyMesh grid;
  double spacing = 0, length = 0, error = 0, score = 0;
};

/// Every grid built, in the order built; the result is chosen from it at the end.
class CandidatePool {
 public:
  /// Builds the grid of lattice start `start` at spacing `spacing` (called in parallel).
  using Builder = std::function<Candidate(double spacing, int start)>;
  explicit CandidatePool(Builder build) : build_(std::move(build)) {}

  /// Builds the (spacing, start) pairs not built yet (each pair once), in parallel: every start
  /// has its own seed, so the grids and their order in the pool do not depend on threads.
  void add(const std::vector<std::pair<double, int>>& jobs);
  /// Whether a grid's length is within `limit` (relative) of the target.
  bool within(double limit) const;
  /// The grid of the highest quality within `tolerance` of the target length (the first on a
  /// tie); failing that, the closest. Null while the pool is empty.
  const Candidate* choose(double tolerance) const;

  const std::vector<Candidate>& grids() const { return grids_; }
  int size() const { return static_cast<int>(grids_.size()); }

 private:
  Builder build_;
  std::vector<Candidate> grids_;
  std::set<std::pair<double, int>> built_;  ///< (spacing, start) of every grid in the pool
};

/// What the secant fit of the spacing did: spacings tried, and the one it would try next.
struct SpacingFit {
  int fits = 0;
  double next_spacing = 0;
};

/// The secant fit of the spacing on M′ to the target length `o.length` (one spacing, `h`, without
/// one): `starts` lattice starts per spacing, the secant on L ∝ 1/h following their median
/// length, until the best start is within `o.length_tolerance` or `o.max_fits` spacings were
/// tried; bracketed steps that leave the bracket are replaced by its geometric middle.
SpacingFit fit_spacing(CandidatePool& pool, double h, int starts, const QuadAnisoOptions& o);

/// When no grid is within max(length_tolerance, length_limit) of the target: up to
/// `o.extra_starts` more starts at the spacings of the closest grids above and below it (or, with
/// one side only, there and at the fit's `next_spacing`). A grid of a few dozen cells can jump
/// across the band between two spacings as close as the fit places them; other starts land
/// elsewhere on the step function.
void starts_across_target(CandidatePool& pool, double next_spacing, int starts,
                          const QuadAnisoOptions& o);

/// More starts at the spacing of the grid chosen so far, up to `o.start_cells` / its cells on M′
/// (`area_def` / h²) and `o.max_starts`: a grid of few cells is cheap to build again, and its
/// shares move most with the start. Returns the starts at that spacing.
int starts_at_chosen(CandidatePool& pool, double area_def, int starts, const QuadAnisoOptions& o);

}  // namespace gridshell::quad_aniso_internal
