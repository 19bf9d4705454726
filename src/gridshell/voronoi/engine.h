#pragma once
/// \file engine.h
/// Internal to src/gridshell/voronoi/: the state the stages of one tessellation run share, and
/// what each stage file provides. The library's API is tessellation.h; nothing here is used
/// outside this folder.
///
/// One run (tessellation.cpp `run_once`, for one cell size R) goes through the files in order:
///
/// | file                   | stage                                                           |
/// |------------------------|-----------------------------------------------------------------|
/// | seeding.cpp            | support mesh at the optimisation's resolution; boundary seeds   |
/// |                        | (corners, even spacing along the loops), Poisson interior seeds |
/// | restricted_voronoi.cpp | the diagram: nearest-seed labels of the support vertices,       |
/// |                        | clipping, per-cell area / moment / CVT energy; seed placement   |
/// | cvt.cpp                | the optimisation: L-BFGS on the CVT energy or Lloyd steps, and  |
/// |                        | the optional fine level                                         |
/// | extraction.cpp         | border refinement, Voronoi vertices and border tracing, checks, |
/// |                        | repair by local refinement, output mesh, flags and supports     |
/// | tessellation.cpp       | `tessellate`: options, cell size from --cells / --radius, the   |
/// |                        | secant search for --length; quality figures                     |
///
/// Every stage is deterministic for a seed: parallel loops write disjoint outputs or are summed
/// in a fixed order (see integrate).

#include <cmath>
#include <vector>

#include "gridshell/core/rng.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/mesh.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/voronoi/support_mesh.h"
#include "gridshell/voronoi/tessellation.h"

namespace gridshell::voronoi {

constexpr double kHexArea = 2.598076211353316;  ///< area of a regular hexagon of circumradius 1
inline const double kSqrt3 = std::sqrt(3.0);

// ---------------------------------------------------------------------------------------------
// The state

enum SeedKind : int { kInterior = 0, kBoundary = 1, kCorner = 2 };

/// A seed is a surface point: a support-mesh triangle and barycentrics in it (never snapped to a
/// vertex), and the position they give on M′. Only interior seeds move.
struct Seed {
  int kind = kInterior;
  int tri = 0;  ///< support-mesh triangle
  Vec3 bary{1, 0, 0};
  Vec3 pos{0, 0, 0};  ///< on M'
};

/// One clipped piece of a triangle, as integrate() collects them (per block of triangles).
struct Piece {
  int cell, tri;
  double area, energy;
  Vec3 moment;
};

/// Everything one run works on: the support mesh with its adjacency, the seeds, the labels of
/// the support vertices and the integrals of the last diagram.
struct Engine {
  SupportMesh S;
  TriangleAdjacency adj;            ///< of S (rebuilt after every refinement that needs it)
  std::vector<char> corner_vertex;  ///< per support vertex (original corners keep their ids)
  std::vector<Seed> seeds;          ///< boundary and corner seeds first, then interior ones
  std::vector<int> label;           ///< per support vertex: its nearest seed
  /// Per seed, its nearest other seed at the last labelling: where the next one starts looking.
  std::vector<int> nearest_seed;
  Vec3 lo, hi;                      ///< bounding box of M′
  double R = 1;                     ///< cell size (m on M′)
  double boundary_split = 0;        ///< see TessellationOptions

  // Restricted Voronoi diagram integrals (filled by integrate()).
  std::vector<double> area;                ///< per seed: area of its region on M'
  std::vector<Vec3> moment;                ///< per seed: first moment ∫ x dA of its region
  double energy = 0;                       ///< CVT energy Σ_i ∫_{V_i} |x − s_i|² dA
  std::vector<int> cell_start, cell_tris;  ///< per seed: the triangles its region meets
  std::vector<std::vector<Piece>> chunk_pieces;  ///< per block of triangles, reused
  /// Per support triangle on M′: its area and first moment (area · centroid) as integrate() adds
  /// a whole triangle to a cell, and a ball around it (centroid, largest corner distance) that
  /// lets place_on_region() skip triangles that cannot hold the closest point. Refinement only
  /// adds triangles, so a cache whose size is not the triangle count is stale and is filled again.
  std::vector<double> tri_area;
  std::vector<Vec3> tri_moment;
  std::vector<Vec3> tri_center;
  std::vector<double> tri_radius;

  /// The point (support triangle t, barycentrics b) on M′ and on M.
  Vec3 point(int t, const Vec3& b) const {
    const auto& M = S.deformed;
    return barycentric_point(b, M.vertex(M.F(t, 0)), M.vertex(M.F(t, 1)), M.vertex(M.F(t, 2)));
  }
  Vec3 rest_point(int t, const Vec3& b) const {
    const auto& M = S.rest;
    return barycentric_point(b, M.vertex(M.F(t, 0)), M.vertex(M.F(t, 1)), M.vertex(M.F(t, 2)));
  }
  std::vector<Vec3> seed_positions() const {
    std::vector<Vec3> p(seeds.size());
    for (std::size_t i = 0; i < seeds.size(); ++i) p[i] = seeds[i].pos;
    return p;
  }
};

/// The input as every run sees it, checked and measured once by `tessellate`.
struct Input {
  const TriMesh& rest;
  const TriMesh& deformed;
  std::vector<char> supported;  ///< per rest vertex
  std::vector<char> corners;    ///< per rest vertex: a sharp boundary corner
  std::vector<std::vector<int>> boundary_loops;  ///< of rest (TriangleAdjacency's)
  int euler = 0;                                 ///< V − E + F of rest
};

// ---------------------------------------------------------------------------------------------
// seeding.cpp

/// The support mesh of (rest, deformed) refined to edges ≤ `max_edge` on M′, with its adjacency,
/// corner flags (`corners`: per rest vertex), bounding box and cell size R.
void set_up_support(Engine& E, const TriMesh& rest, const TriMesh& deformed,
                    const std::vector<char>& corners, double R, double max_edge);

/// All seeds of a run (Rng seeded with o.seed): boundary seeds spaced boundary_spacing·√3 R, then
/// interior ones at Poisson radius 0.8·√3 R — `cells` minus the boundary seeds, or with
/// cells = 0 as many as M′'s `area` holds at R (area / (2.598 R²) less half a cell per boundary
/// seed) — at least one.
void place_seeds(Engine& E, double area, int cells, const TessellationOptions& o);

/// Boundary seeds: corners (fixed) and evenly spaced seeds between them along each loop (the
/// converged 1-D Lloyd sampling in M' arc length). Loops without corners get ≥ 3 seeds with a
/// random phase.
void seed_boundary(Engine& E, double spacing, Rng& rng);

/// 2-D Poisson-disk sampling of `count` interior seeds on M', constrained by the seeds present.
void seed_interior(Engine& E, int count, double radius, Rng& rng);

// ---------------------------------------------------------------------------------------------
// restricted_voronoi.cpp

/// Labels every support vertex from `first` on with its nearest seed (exact, uniform grid).
/// Vertices below `labelled` keep their label as a hint (seeds move little between two
/// diagrams, so the search box around the old seed is small); the result does not depend on it.
void compute_labels(Engine& E, int first = 0, int labelled = 0);

/// Integrates the restricted Voronoi diagram of the current seeds (labels must be current) into
/// E.area, E.moment, E.energy and the triangles of each region.
void integrate(Engine& E);

/// Moves seed i to the closest point to `c` on the triangles its region meets (integrate() must
/// be current). Returns the squared distance moved.
double place_on_region(Engine& E, int i, const Vec3& c);

/// After a refinement with per-new-triangle `source`: moves every seed's (triangle,
/// barycentrics) to the refined triangle that holds its (unchanged) position.
void relocate_seeds(Engine& E, const std::vector<int>& source, int old_faces);

// ---------------------------------------------------------------------------------------------
// cvt.cpp

/// One Lloyd step (labels must be current), the move over-relaxed by `omega`. Returns the
/// root-mean-square move of the interior seeds divided by omega.
double lloyd_step(Engine& E, double omega = 1.0);

/// What the optimisation did.
struct CvtResult {
  int iterations = 0;      ///< diagrams computed
  bool converged = false;  ///< the last level met its tolerance
};

/// The CVT optimisation of one run: L-BFGS (or over-relaxed Lloyd steps) on the support mesh
/// until the seeds' RMS Lloyd move is below the tolerance; with a coarse first level, then a
/// refinement to `support_edge` and at most `fine_iterations` Lloyd steps. Labels and integrals
/// are not current afterwards.
CvtResult optimize_cvt(Engine& E, const TessellationOptions& o);

// ---------------------------------------------------------------------------------------------
// extraction.cpp

/// Extracts the polygon mesh of the optimised seeds into T (mesh, quality, per-vertex flags and
/// mapping to M, supports, seeds, repairs, orphan vertices, seconds_extraction): refines the
/// support mesh across the cell borders, traces the borders, checks the result, and repairs by
/// refining around the offending cells (at most 4 times). Throws ExtractionError when that
/// does not give a valid mesh.
void extract_cells(Engine& E, const Input& in, const TessellationOptions& o, Tessellation& T);

}  // namespace gridshell::voronoi
