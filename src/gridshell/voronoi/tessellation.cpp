#include "gridshell/voronoi/tessellation.h"

// The entry points: `tessellate` (options, the cell size for --cells / --radius, the secant search
// for --length, one run per cell size tried), the quality figures, the Lloyd benchmark. The
// stages of a run are in the files listed in engine.h.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <spdlog/spdlog.h>

#include "gridshell/core/error.h"
#include "gridshell/core/rng.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/voronoi/engine.h"
#include "gridshell/voronoi/support_mesh.h"

namespace gridshell {

namespace {

using namespace voronoi;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// V − E + F of a triangle mesh, every vertex counted.
int euler_of(const TriMesh& m) {
  const Topology t = build_topology(m);
  return m.num_vertices() - t.num_edges() + m.num_faces();
}

/// Total length of the boundary loops on `m`.
double boundary_length(const TriMesh& m, const std::vector<std::vector<int>>& loops) {
  double perimeter = 0;
  for (const auto& loop : loops)
    for (std::size_t k = 0; k < loop.size(); ++k)
      perimeter += (m.vertex(loop[k]) - m.vertex(loop[(k + 1) % loop.size()])).norm();
  return perimeter;
}

/// The cell size R that gives `cells` cells on a surface of `area` and boundary `perimeter`
/// (M′), boundary seeds spaced bs·√3 R.
double radius_for_cells(double area, double perimeter, int cells, double bs) {
  // cells ≈ area / (kHexArea R²) + (boundary seeds) / 2, boundary seeds ≈ perimeter / (bs √3 R).
  const double a = area / kHexArea, b = perimeter / (2 * bs * kSqrt3);
  const double x = (-b + std::sqrt(b * b + 4 * a * cells)) / (2 * a);
  return 1.0 / x;
}

/// R itself, or Error(subject, …) when it is no cell size or asks for over 200 000 cells.
double checked_radius(double R, double area, const char* subject) {
  if (!(R > 0) || !std::isfinite(R)) throw Error(subject, "gives no valid cell size");
  const double cells_est = area / (kHexArea * R * R);
  if (cells_est > 2e5) throw Error(subject, "asks for too many cells (more than 200000)");
  return R;
}

/// Total length of the edges lying on one of `o.length_excluded_planes`.
double length_on_planes(const PolyMesh& mesh, const TessellationOptions& o) {
  if (o.length_excluded_planes.empty() || mesh.num_vertices() == 0) return 0.0;
  const double tol = 1e-6 * bbox_diagonal(mesh.V);
  double sum = 0;
  for (const auto& e : build_topology(mesh).edges) {
    const Vec3 a = mesh.vertex(e[0]), b = mesh.vertex(e[1]);
    for (const Plane& plane : o.length_excluded_planes)
      if (std::abs(plane.signed_distance(a)) <= tol && std::abs(plane.signed_distance(b)) <= tol) {
        sum += (a - b).norm();
        break;
      }
  }
  return sum;
}

/// The closed-form length of a tessellation of cell size R (to meet --length in one run):
/// a hexagonal tiling of M′ has 3/(kHexArea R) metres of edges per square metre of M′ and the
/// boundary seeds sit on a lattice row, so cutting the tiling along the boundary adds the
/// boundary itself: ℓ′ = 3 A′/(kHexArea R) + P′. The output lives on M: an edge of M′ with
/// direction w comes back with length |F w| (F the map M′ → M of its triangle), and over the
/// edge directions of a hexagonal cell that averages to the perimeter of the ellipse F(unit
/// circle) over 2π. So ℓ(R) = 3/(kHexArea R) · Σ_t A′_t m_t + P, m_t that mean stretch and P
/// the boundary length on M (edges on an excluded plane left out, as in the count).
struct LengthModel {
  double interior = 0;  ///< Σ_t A′_t m_t (m²)
  double boundary = 0;  ///< P (m)
  double length(double R) const { return 3 * interior / (kHexArea * R) + boundary; }
  /// The R with length(R) = L; 0 when the boundary alone is as long as L.
  double radius(double L) const {
    return L > boundary ? 3 * interior / (kHexArea * (L - boundary)) : 0.0;
  }
};

/// Mean of |F w| over unit directions w for a 2×2 map with singular values s1, s2: the perimeter
/// of the ellipse with those half-axes over 2π (Ramanujan's second approximation, 1e-5 relative
/// up to an aspect ratio of 5).
double mean_stretch(double s1, double s2) {
  const double sum = s1 + s2;
  if (!(sum > 0)) return 0.0;
  const double h = (s1 - s2) * (s1 - s2) / (sum * sum);
  return 0.5 * sum * (1 + 3 * h / (10 + std::sqrt(4 - 3 * h)));
}

LengthModel length_model(const Input& in, const TessellationOptions& o) {
  LengthModel m;
  const TriMesh &M = in.rest, &D = in.deformed;
  for (int f = 0; f < M.num_faces(); ++f) {
    const Vec3 a = M.vertex(M.F(f, 1)) - M.vertex(M.F(f, 0)),
               b = M.vertex(M.F(f, 2)) - M.vertex(M.F(f, 0));
    const Vec3 ad = D.vertex(D.F(f, 1)) - D.vertex(D.F(f, 0)),
               bd = D.vertex(D.F(f, 2)) - D.vertex(D.F(f, 0));
    Eigen::Matrix2d g, gd;  // Gram matrices of the edges on M and on M′
    g << a.dot(a), a.dot(b), a.dot(b), b.dot(b);
    gd << ad.dot(ad), ad.dot(bd), ad.dot(bd), bd.dot(bd);
    const double area_d = 0.5 * std::sqrt(std::max(0.0, gd.determinant()));
    if (!(area_d > 0)) continue;
    // FᵀF is similar to g gd⁻¹: its eigenvalues are the squared singular values of F.
    const Eigen::Matrix2d c = g * gd.inverse();
    const double tr = c.trace(), det = std::max(0.0, c.determinant());
    const double disc = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
    const double l1 = std::max(0.0, 0.5 * tr + disc), l2 = std::max(0.0, 0.5 * tr - disc);
    m.interior += area_d * mean_stretch(std::sqrt(l1), std::sqrt(l2));
  }
  const double tol = 1e-6 * bbox_diagonal(M.V);
  auto on_plane = [&](const Vec3& p, const Vec3& q) {
    for (const Plane& plane : o.length_excluded_planes)
      if (std::abs(plane.signed_distance(p)) <= tol && std::abs(plane.signed_distance(q)) <= tol)
        return true;
    return false;
  };
  for (const auto& loop : in.boundary_loops)
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Vec3 p = M.vertex(loop[k]), q = M.vertex(loop[(k + 1) % loop.size()]);
      if (!on_plane(p, q)) m.boundary += (p - q).norm();
    }
  return m;
}

/// One tessellation at cell size R (and exactly `cells` cells when > 0): the stages of engine.h
/// in order.
Tessellation run_once(const Input& in, double R, int cells, const TessellationOptions& o) {
  const auto t_setup = Clock::now();
  Engine E;
  E.boundary_split = o.boundary_split;
  const bool two_level = o.coarse_edge > o.support_edge;
  set_up_support(E, in.rest, in.deformed, in.corners, R,
                 (two_level ? o.coarse_edge : o.support_edge) * R);
  place_seeds(E, surface_area(in.deformed), cells, o);
  Tessellation T;
  T.radius = R;
  T.seconds_setup = seconds_since(t_setup);
  const auto t_lloyd = Clock::now();
  const CvtResult cvt = optimize_cvt(E, o);
  T.converged = cvt.converged;
  T.iterations = cvt.iterations;
  T.support_vertices = E.S.deformed.num_vertices();
  T.seconds_lloyd = seconds_since(t_lloyd);
  extract_cells(E, in, o, T);
  return T;
}

/// --length: R from the closed-form length model (LengthModel), then, when the run misses by
/// more than 0.4 of the tolerance, a secant in log R / log ℓ (first slope from the model); at most
/// 8 runs, the best kept.
Tessellation tessellate_to_length(const Input& in, double area, const TessellationOptions& o) {
  const LengthModel model = length_model(in, o);
  double R = model.radius(o.length);
  if (!(R > 0)) R = 3 * area / (kHexArea * o.length);  // boundary longer than L: tiny cells
  R = checked_radius(R, area, "--length");
  Tessellation best;
  double best_err = std::numeric_limits<double>::infinity();
  double lr_prev = 0, ll_prev = 0;
  bool have_prev = false;
  int runs = 0;
  constexpr int kMaxRuns = 8;
  for (; runs < kMaxRuns; ++runs) {
    Tessellation t = run_once(in, checked_radius(R, area, "--length"), 0, o);
    const double len = t.quality.total_length - length_on_planes(t.mesh, o);
    const double err = std::abs(len / o.length - 1);
    spdlog::info("tessellation: R = {:.4g} m gives total length {:.5g} m (target {:.5g}, model "
                 "{:.5g})",
                 R, len, o.length, model.length(R));
    if (err < best_err) {
      best_err = err;
      best = std::move(t);
    }
    if (err <= 0.4 * o.length_tolerance) break;
    const double lr = std::log(R), ll = std::log(len);
    // d log ℓ / d log R of the model: the interior term's share, negated.
    double slope = -std::clamp(1 - model.boundary / model.length(R), 0.3, 1.0);
    if (have_prev && std::abs(lr - lr_prev) > 1e-9) {
      slope = (ll - ll_prev) / (lr - lr_prev);
      if (!(slope < -0.3 && slope > -3)) slope = -1;
    }
    lr_prev = lr;
    ll_prev = ll;
    have_prev = true;
    R = std::exp(lr + (std::log(o.length) - ll) / slope);
  }
  best.length_runs = std::min(runs + 1, kMaxRuns);  // runs made
  // Said at info level: the design's own length (after welding a symmetric sector's copies and
  // the finishing) is what a command warns about (app/common.h, warn_if_length_missed).
  if (best_err > o.length_tolerance)
    spdlog::info("tessellation: total length off target by {:.1f}% (the best of {} runs)",
                 100 * best_err, best.length_runs);
  return best;
}

}  // namespace

TessellationQuality measure_quality(const PolyMesh& mesh) {
  TessellationQuality q;
  q.vertices = mesh.num_vertices();
  q.faces = mesh.num_faces();
  const MeshProblems problems = check_mesh(mesh);
  q.manifold = problems.ok();
  const Topology topo = build_topology(mesh);
  q.edges = topo.num_edges();
  q.euler = euler_characteristic(mesh, topo);
  q.boundary_loops = static_cast<int>(topo.boundary_loops.size());
  for (const auto& f : mesh.faces) ++q.face_sides[static_cast<int>(f.size())];
  int v3 = 0;
  for (int v = 0; v < q.vertices; ++v) {
    if (topo.on_boundary[v]) continue;
    ++q.interior_vertices;
    if (topo.vertex_neighbors[v].size() == 3) ++v3;
  }
  q.valence3_share_interior = q.interior_vertices ? double(v3) / q.interior_vertices : 1.0;
  int hex = 0;
  for (const auto& f : mesh.faces) {
    bool interior = true;
    for (int v : f) interior = interior && !topo.on_boundary[v];
    if (!interior) continue;
    ++q.interior_faces;
    if (f.size() == 6) ++hex;
  }
  q.hex_share_interior = q.interior_faces ? double(hex) / q.interior_faces : 0.0;
  double sum = 0, sum2 = 0, mn = std::numeric_limits<double>::infinity();
  for (const auto& e : topo.edges) {
    const double l = (mesh.vertex(e[0]) - mesh.vertex(e[1])).norm();
    sum += l;
    sum2 += l * l;
    mn = std::min(mn, l);
  }
  if (q.edges > 0) {
    q.total_length = sum;
    q.edge_length_mean = sum / q.edges;
    const double var = std::max(0.0, sum2 / q.edges - q.edge_length_mean * q.edge_length_mean);
    q.edge_length_cv = q.edge_length_mean > 0 ? std::sqrt(var) / q.edge_length_mean : 0.0;
    q.edge_length_min = mn;
  }
  return q;
}

void check_tessellation_options(const TessellationOptions& o) {
  const int given = (o.radius > 0) + (o.cells > 0) + (o.length > 0);
  if (given > 1) throw Error("--radius/--cells/--length", "give at most one of them");
  if (o.radius < 0 || !std::isfinite(o.radius)) throw Error("--radius", "must be positive");
  if (o.cells < 0) throw Error("--cells", "must be positive");
  if (o.length < 0 || !std::isfinite(o.length)) throw Error("--length", "must be positive");
  if (o.max_iterations < 0) throw Error("tessellation", "max_iterations must be ≥ 0");
  if (!(o.support_edge > 0) || !(o.extraction_edge > 0) || !(o.tolerance > 0))
    throw Error("tessellation", "support_edge, extraction_edge and tolerance must be positive");
  if (!(o.length_tolerance > 0 && o.length_tolerance < 1))
    throw Error("tessellation", "length_tolerance must be in (0, 1)");
}

Tessellation tessellate(const TriMesh& rest, const TriMesh& deformed,
                        const std::vector<int>& rest_supports, const TessellationOptions& o) {
  check_tessellation_options(o);
  (void)make_support_mesh(rest, deformed);  // validates
  // Also the manifold check of the input (throws Error("surface", …)).
  const TriangleAdjacency adj = build_triangle_adjacency(rest.F, rest.num_vertices());
  Input in{rest, deformed, std::vector<char>(rest.num_vertices(), 0), {}, {}, 0};
  for (int v : rest_supports) {
    if (v < 0 || v >= rest.num_vertices()) throw Error("supports", "vertex id out of range");
    in.supported[v] = 1;
  }
  in.corners = boundary_corners(rest.V, adj.boundary_loops, o.corner_angle_deg);
  in.euler = euler_of(rest);
  in.boundary_loops = adj.boundary_loops;
  const double area = surface_area(deformed);
  const double perimeter = boundary_length(deformed, adj.boundary_loops);
  if (!(area > 0)) throw Error("surface", "zero area");
  if (o.length > 0) return tessellate_to_length(in, area, o);
  double R = o.radius;
  int cells = o.cells;
  if (R <= 0) {
    if (cells <= 0) cells = o.default_cells;
    R = radius_for_cells(area, perimeter, cells, o.boundary_spacing);
  }
  checked_radius(R, area, o.radius > 0 ? "--radius" : "--cells");
  return run_once(in, R, cells, o);
}

LloydBenchmark benchmark_lloyd(const TriMesh& surface, int cells, double support_edge, int warmup,
                               std::uint64_t seed) {
  Engine E;
  const double area = surface_area(surface);
  const TriangleAdjacency adj0 = build_triangle_adjacency(surface.F, surface.num_vertices());
  const double R = radius_for_cells(area, boundary_length(surface, adj0.boundary_loops), cells, 1.0);
  const std::vector<char> corners = boundary_corners(surface.V, adj0.boundary_loops, 30);
  set_up_support(E, surface, surface, corners, R, support_edge * R);
  Rng rng(seed);
  seed_boundary(E, kSqrt3 * E.R, rng);
  const int nb = static_cast<int>(E.seeds.size());
  seed_interior(E, std::max(1, cells - nb), 0.8 * kSqrt3 * E.R, rng);
  for (int i = 0; i < warmup; ++i) {
    compute_labels(E);
    lloyd_step(E);
  }
  LloydBenchmark b;
  b.support_vertices = E.S.deformed.num_vertices();
  b.seeds = static_cast<int>(E.seeds.size());
  const auto t0 = Clock::now();
  compute_labels(E);
  b.max_move = lloyd_step(E);
  b.seconds = seconds_since(t0);
  return b;
}

}  // namespace gridshell
