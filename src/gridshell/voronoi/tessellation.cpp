#include "gridshell/voronoi/tessellation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <tuple>
#include <unordered_map>

#include <LBFGS.h>
#include <spdlog/spdlog.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "gridshell/core/error.h"
#include "gridshell/core/rng.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/voronoi/support_mesh.h"

namespace gridshell {

namespace {

constexpr double kHexArea = 2.598076211353316;  // area of a regular hexagon of circumradius 1
const double kSqrt3 = std::sqrt(3.0);

// ---------------------------------------------------------------------------------------------
// A uniform grid over the seeds for exact nearest-seed queries.

class SeedGrid {
 public:
  SeedGrid(const std::vector<Vec3>& pts, const Vec3& lo, const Vec3& hi, double cell)
      : pts_(pts), lo_(lo) {
    const Vec3 ext = (hi - lo).cwiseMax(1e-12);
    cell_ = std::max(cell, 1e-12);
    for (;;) {
      for (int d = 0; d < 3; ++d) n_[d] = std::max(1, static_cast<int>(ext(d) / cell_) + 1);
      if (static_cast<double>(n_[0]) * n_[1] * n_[2] <= 4e6) break;
      cell_ *= 1.5;
    }
    start_.assign(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2] + 1, 0);
    std::vector<int> key(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      key[i] = cell_of(pts[i]);
      ++start_[key[i] + 1];
    }
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    items_.resize(pts.size());
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < pts.size(); ++i) items_[fill[key[i]]++] = static_cast<int>(i);
  }

  /// Index of the seed nearest to p (ties: lowest index), knowing a seed `hint`: only the cells
  /// meeting the box of half-width |p − hint| around p can hold a nearer (or tied) seed.
  int nearest(const Vec3& p, int hint) const {
    double bd = (pts_[hint] - p).squaredNorm();
    int best = hint;
    const double r = std::sqrt(bd);
    int c0[3], c1[3];
    coords(p - Vec3::Constant(r), c0);
    coords(p + Vec3::Constant(r), c1);
    for (int k = c0[2]; k <= c1[2]; ++k)
      for (int j = c0[1]; j <= c1[1]; ++j)
        for (int i = c0[0]; i <= c1[0]; ++i) scan((k * n_[1] + j) * n_[0] + i, p, bd, best);
    return best;
  }

  /// Index of the seed nearest to p (ties: lowest index).
  int nearest(const Vec3& p) const {
    int c[3];
    coords(p, c);
    int best = -1;
    double bd = std::numeric_limits<double>::infinity();
    const int maxr = std::max({n_[0], n_[1], n_[2]});
    for (int r = 0; r <= maxr; ++r) {
      for (int i = c[0] - r; i <= c[0] + r; ++i) {
        if (i < 0 || i >= n_[0]) continue;
        for (int j = c[1] - r; j <= c[1] + r; ++j) {
          if (j < 0 || j >= n_[1]) continue;
          const bool face_ij = (i == c[0] - r || i == c[0] + r || j == c[1] - r || j == c[1] + r);
          for (int k = c[2] - r; k <= c[2] + r; ++k) {
            if (k < 0 || k >= n_[2]) continue;
            if (!face_ij && k != c[2] - r && k != c[2] + r) continue;  // only the shell of ring r
            scan((k * n_[1] + j) * n_[0] + i, p, bd, best);
          }
        }
      }
      // Points outside the searched cube are at least r·cell away.
      if (best >= 0 && std::sqrt(bd) <= r * cell_) break;
    }
    return best;
  }

 private:
  /// Updates (bd, best) with the seeds of grid cell cc: squared distance, ties to the lowest index.
  void scan(int cc, const Vec3& p, double& bd, int& best) const {
    for (int s = start_[cc]; s < start_[cc + 1]; ++s) {
      const int q = items_[s];
      const double d = (pts_[q] - p).squaredNorm();
      if (d < bd || (d == bd && q < best)) {
        bd = d;
        best = q;
      }
    }
  }
  void coords(const Vec3& p, int c[3]) const {
    for (int d = 0; d < 3; ++d)
      c[d] = std::clamp(static_cast<int>(std::floor((p(d) - lo_(d)) / cell_)), 0, n_[d] - 1);
  }
  int cell_of(const Vec3& p) const {
    int c[3];
    coords(p, c);
    return (c[2] * n_[1] + c[1]) * n_[0] + c[0];
  }
  const std::vector<Vec3>& pts_;
  Vec3 lo_;
  double cell_;
  int n_[3];
  std::vector<int> start_, items_;
};

// ---------------------------------------------------------------------------------------------
// Convex polygon clipping by bisector half-spaces.

struct Poly {
  int n = 0;
  Vec3 p[32];
};

/// Keeps the part of P closer to si than to sj.
void clip(Poly& P, const Vec3& si, const Vec3& sj) {
  const Vec3 nrm = sj - si;
  const double off = 0.5 * (sj.squaredNorm() - si.squaredNorm());
  double d[32];
  bool any_out = false, any_in = false;
  for (int k = 0; k < P.n; ++k) {
    d[k] = P.p[k].dot(nrm) - off;  // ≤ 0 inside
    if (d[k] > 0)
      any_out = true;
    else
      any_in = true;
  }
  if (!any_out) return;
  if (!any_in) {
    P.n = 0;
    return;
  }
  Vec3 q[32];
  int m = 0;
  for (int k = 0; k < P.n; ++k) {
    const int l = (k + 1) % P.n;
    const bool in_k = d[k] <= 0, in_l = d[l] <= 0;
    if (in_k && m < 31) q[m++] = P.p[k];
    if (in_k != in_l && m < 31) {
      const double t = d[k] / (d[k] - d[l]);
      q[m++] = P.p[k] + t * (P.p[l] - P.p[k]);
    }
  }
  P.n = m;
  std::copy(q, q + m, P.p);
}

// ---------------------------------------------------------------------------------------------
// The engine state.

enum SeedKind : int { kInterior = 0, kBoundary = 1, kCorner = 2 };

struct Seed {
  int kind = kInterior;
  int tri = 0;  ///< support-mesh triangle
  Vec3 bary{1, 0, 0};
  Vec3 pos{0, 0, 0};  ///< on M'
};

struct Engine;
int merge_orphan_pieces(Engine& E);

struct Engine {
  SupportMesh S;
  TriangleAdjacency adj;
  std::vector<char> corner_vertex;  ///< per support vertex (original corners keep their ids)
  std::vector<Seed> seeds;
  std::vector<int> label;
  Vec3 lo, hi;
  double R = 1;
  double boundary_split = 0;  ///< see TessellationOptions

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

  /// Labels every support vertex from `first` on with its nearest seed (exact, uniform grid).
  /// Vertices below `labelled` keep their label as a hint (seeds move little between two
  /// diagrams, so the search box around the old seed is small); the result does not depend on it.
  void compute_labels(int first = 0, int labelled = 0) {
    const std::vector<Vec3> pts = seed_positions();
    SeedGrid grid(pts, lo, hi, R);
    const int nv = S.deformed.num_vertices();
    const int ns = static_cast<int>(seeds.size());
    labelled = std::min(labelled, static_cast<int>(label.size()));
    label.resize(nv, 0);
    tbb::parallel_for(
        tbb::blocked_range<int>(first, nv, 4096), [&](const tbb::blocked_range<int>& r) {
          for (int v = r.begin(); v < r.end(); ++v) {
            const Vec3 p = S.deformed.vertex(v);
            label[v] = v < labelled && label[v] >= 0 && label[v] < ns ? grid.nearest(p, label[v])
                                                                      : grid.nearest(p);
          }
        });
  }

  /// After a refinement with per-new-triangle `source`: moves every seed's (triangle,
  /// barycentrics) to the refined triangle that holds its (unchanged) position.
  void relocate_seeds(const std::vector<int>& source, int old_faces) {
    std::vector<int> start(old_faces + 1, 0);
    for (int s : source) ++start[s + 1];
    for (int i = 0; i < old_faces; ++i) start[i + 1] += start[i];
    std::vector<int> kids(source.size());
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < source.size(); ++t) kids[fill[source[t]]++] = static_cast<int>(t);
    const auto& F = S.deformed.F;
    for (Seed& sd : seeds) {
      double best = std::numeric_limits<double>::infinity();
      int bt = -1;
      Vec3 bb;
      for (int q = start[sd.tri]; q < start[sd.tri + 1]; ++q) {
        const int t = kids[q];
        const Vec3 w = closest_point_on_triangle(sd.pos, S.deformed.vertex(F(t, 0)),
                                                 S.deformed.vertex(F(t, 1)),
                                                 S.deformed.vertex(F(t, 2)))
                           .bary;
        const double d = (point(t, w) - sd.pos).squaredNorm();
        if (d < best) {
          best = d;
          bt = t;
          bb = w;
        }
      }
      if (bt >= 0) {
        sd.tri = bt;
        sd.bary = bb;
        sd.pos = point(bt, bb);
      }
    }
  }

  // Restricted Voronoi diagram integrals (filled by integrate()).
  std::vector<double> area;                ///< per seed: area of its region on M'
  std::vector<Vec3> moment;                ///< per seed: first moment ∫ x dA of its region
  double energy = 0;                       ///< CVT energy Σ_i ∫_{V_i} |x − s_i|² dA
  std::vector<int> cell_start, cell_tris;  ///< per seed: the triangles its region meets

  struct Piece {
    int cell, tri;
    double area, energy;
    Vec3 moment;
  };
  std::vector<std::vector<Piece>> chunk_pieces;  ///< per block of triangles, reused

  /// Integrates the restricted Voronoi diagram of the current seeds (labels must be current):
  /// a triangle whose three corners share a label goes whole to that seed; any other triangle is
  /// clipped by the bisector planes of the seeds labelling its corners and its neighbours'
  /// opposite corners. Blocks of triangles are clipped in parallel and summed in triangle order,
  /// so the result does not depend on the thread count.
  void integrate() {
    constexpr int kBlock = 2048;
    const int ns = static_cast<int>(seeds.size());
    const int nt = S.deformed.num_faces();
    const int nb = (nt + kBlock - 1) / kBlock;
    chunk_pieces.resize(nb);
    const auto& F = S.deformed.F;
    auto tri_energy = [](const Vec3& a, const Vec3& b, const Vec3& c, double ar) {
      return ar / 6.0 *
             (a.squaredNorm() + b.squaredNorm() + c.squaredNorm() + a.dot(b) + b.dot(c) + c.dot(a));
    };
    tbb::parallel_for(tbb::blocked_range<int>(0, nb, 1), [&](const tbb::blocked_range<int>& r) {
      for (int blk = r.begin(); blk < r.end(); ++blk) {
        auto& out = chunk_pieces[blk];
        out.clear();
        const int t1 = std::min(nt, (blk + 1) * kBlock);
        int cand[12];
        for (int t = blk * kBlock; t < t1; ++t) {
          const int a = F(t, 0), b = F(t, 1), c = F(t, 2);
          const int la = label[a], lb = label[b], lc = label[c];
          const Vec3 pa = S.deformed.vertex(a), pb = S.deformed.vertex(b),
                     pc = S.deformed.vertex(c);
          if (la == lb && lb == lc) {
            const double ar = triangle_area(pa, pb, pc);
            const Vec3& s = seeds[la].pos;
            out.push_back(
                {la, t, ar, tri_energy(pa - s, pb - s, pc - s, ar), ar * (pa + pb + pc) / 3.0});
            continue;
          }
          int nc = 0;
          auto add = [&](int l) {
            for (int q = 0; q < nc; ++q)
              if (cand[q] == l) return;
            cand[nc++] = l;
          };
          add(la);
          add(lb);
          add(lc);
          for (int k = 0; k < 3; ++k) {
            const int u = adj.neighbor[t][k];
            if (u < 0) continue;
            add(label[F(u, (adj.neighbor_edge[t][k] + 2) % 3)]);
          }
          for (int q = 0; q < nc; ++q) {
            const int i = cand[q];
            Poly P;
            P.n = 3;
            P.p[0] = pa;
            P.p[1] = pb;
            P.p[2] = pc;
            for (int r2 = 0; r2 < nc && P.n > 0; ++r2)
              if (r2 != q) clip(P, seeds[i].pos, seeds[cand[r2]].pos);
            if (P.n < 3) continue;
            const Vec3& s = seeds[i].pos;
            double ar = 0, en = 0;
            Vec3 mo = Vec3::Zero();
            for (int k = 1; k + 1 < P.n; ++k) {
              const double x = triangle_area(P.p[0], P.p[k], P.p[k + 1]);
              ar += x;
              mo += x * (P.p[0] + P.p[k] + P.p[k + 1]) / 3.0;
              en += tri_energy(P.p[0] - s, P.p[k] - s, P.p[k + 1] - s, x);
            }
            if (ar <= 0) continue;
            out.push_back({i, t, ar, en, mo});
          }
        }
      }
    });
    area.assign(ns, 0.0);
    moment.assign(ns, Vec3::Zero());
    energy = 0;
    cell_start.assign(ns + 1, 0);
    for (const auto& blk : chunk_pieces)
      for (const Piece& p : blk) {
        area[p.cell] += p.area;
        moment[p.cell] += p.moment;
        energy += p.energy;
        ++cell_start[p.cell + 1];
      }
    for (int i = 0; i < ns; ++i) cell_start[i + 1] += cell_start[i];
    cell_tris.resize(cell_start[ns]);
    std::vector<int> fill(cell_start.begin(), cell_start.end() - 1);
    for (const auto& blk : chunk_pieces)
      for (const Piece& p : blk) cell_tris[fill[p.cell]++] = p.tri;
  }

  /// Moves interior seed i to the closest point to `c` on the triangles its region meets
  /// (integrate() must be current). Returns the squared distance moved.
  double place_on_region(int i, const Vec3& c) {
    const auto& F = S.deformed.F;
    double best = std::numeric_limits<double>::infinity();
    int bt = seeds[i].tri;
    Vec3 bb = seeds[i].bary;
    for (int s = cell_start[i]; s < cell_start[i + 1]; ++s) {
      const int t = cell_tris[s];
      const Vec3 w = closest_point_on_triangle(c, S.deformed.vertex(F(t, 0)),
                                               S.deformed.vertex(F(t, 1)), S.deformed.vertex(F(t, 2)))
                         .bary;
      const double d = (point(t, w) - c).squaredNorm();
      if (d < best) {
        best = d;
        bt = t;
        bb = w;
      }
    }
    seeds[i].tri = bt;
    seeds[i].bary = bb;
    const Vec3 p = point(bt, bb);
    const double moved = (p - seeds[i].pos).squaredNorm();
    seeds[i].pos = p;
    return moved;
  }

  /// One Lloyd step (labels must be current), the move over-relaxed by `omega`. Returns the
  /// root-mean-square move of the interior seeds divided by omega.
  double lloyd_step(double omega = 1.0) {
    integrate();
    double sum_move2 = 0;
    int moved = 0;
    for (std::size_t i = 0; i < seeds.size(); ++i) {
      if (seeds[i].kind != kInterior || area[i] <= 0) continue;
      const Vec3 g = moment[i] / area[i];
      sum_move2 += place_on_region(static_cast<int>(i), seeds[i].pos + omega * (g - seeds[i].pos)) /
                   (omega * omega);
      ++moved;
    }
    return moved ? std::sqrt(sum_move2 / moved) : 0.0;
  }

  /// Minimises the CVT energy of the interior seeds by L-BFGS (Liu et al. 2009), the seeds kept
  /// on the surface: E = Σ_i ∫_{V_i} |x − s_i|² dA, ∂E/∂s_i = 2 m_i (s_i − c_i). Every point the
  /// solver asks for is first put back on the surface (each seed to the closest point of the
  /// triangles its region met at the previous evaluation, written back into the iterate), and the
  /// gradient is projected on the tangent plane there. Stops when the RMS tangential Lloyd move
  /// |P_T(c_i − s_i)| is below `tol` (m) — the measure of the Lloyd iteration, whose move is
  /// projected on the surface too — after `max_evals` diagrams, or when the line search can make
  /// no progress; the seeds are left at the evaluated point of lowest energy (labels and
  /// integrals are then not current). Returns the number of diagrams computed.
  int minimize_energy(double tol, int max_evals, int history, bool* converged = nullptr) {
    std::vector<int> free;
    for (std::size_t i = 0; i < seeds.size(); ++i)
      if (seeds[i].kind == kInterior) free.push_back(static_cast<int>(i));
    const int n = static_cast<int>(free.size());
    if (n == 0 || max_evals <= 0) return 0;
    // Scaled variables (positions / R about the box centre, energy / R⁴) keep the numbers O(1).
    const Vec3 o = 0.5 * (lo + hi);
    const double R3 = R * R * R, R4 = R3 * R;
    const auto& F = S.deformed.F;
    Eigen::VectorXd x(3 * n);
    for (int k = 0; k < n; ++k) x.segment<3>(3 * k) = (seeds[free[k]].pos - o) / R;
    std::vector<Seed> best_seeds;
    double best_f = std::numeric_limits<double>::infinity();
    int evals = 0;
    struct Stop {};
    auto f = [&](Eigen::VectorXd& y, Eigen::VectorXd& grad) -> double {
      if (evals > 0)
        for (int k = 0; k < n; ++k) {
          const int i = free[k];
          const Vec3 p = o + R * y.segment<3>(3 * k);
          if (cell_start[i + 1] > cell_start[i]) place_on_region(i, p);
          y.segment<3>(3 * k) = (seeds[i].pos - o) / R;
        }
      compute_labels(0, evals > 0 ? static_cast<int>(label.size()) : 0);
      integrate();
      ++evals;
      grad.resize(3 * n);
      double sum = 0;
      for (int k = 0; k < n; ++k) {
        const int i = free[k];
        const int t = seeds[i].tri;
        const Vec3 a = S.deformed.vertex(F(t, 0));
        const Vec3 nrm =
            (S.deformed.vertex(F(t, 1)) - a).cross(S.deformed.vertex(F(t, 2)) - a).normalized();
        Vec3 g = area[i] * seeds[i].pos - moment[i];
        if (nrm.allFinite()) g -= g.dot(nrm) * nrm;
        grad.segment<3>(3 * k) = 2.0 * g / R3;
        if (area[i] > 0) sum += g.squaredNorm() / (area[i] * area[i]);
      }
      const double fx = energy / R4;
      const double move = std::sqrt(sum / n);
      if (fx < best_f || move < tol) {
        best_f = move < tol ? -std::numeric_limits<double>::infinity() : fx;
        best_seeds = seeds;
        if (move < tol && converged) *converged = true;
      }
      spdlog::debug("cvt energy {} {:.9e} rms move/R {:.3e}", evals, fx, move / R);
      if (move < tol || evals >= max_evals) throw Stop{};
      return fx;
    };
    LBFGSpp::LBFGSParam<double> param;
    param.m = history;
    param.epsilon = 0;
    param.epsilon_rel = 0;
    param.max_iterations = 0;
    param.max_linesearch = 20;
    param.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_WOLFE;
    LBFGSpp::LBFGSSolver<double> solver(param);
    double fx = 0;
    try {
      solver.minimize(f, x, fx);
    } catch (const Stop&) {
    } catch (const std::exception& e) {
      spdlog::debug("cvt energy: L-BFGS stopped ({})", e.what());
    }
    if (!best_seeds.empty()) seeds = std::move(best_seeds);
    return evals;
  }
};

// ---------------------------------------------------------------------------------------------
// Seeding.

/// Boundary seeds: corners (fixed) and evenly spaced seeds between them along each loop (the
/// converged 1-D Lloyd sampling in M' arc length). Loops without corners get ≥ 3 seeds with a
/// random phase.
void seed_boundary(Engine& E, double spacing, Rng& rng) {
  const auto& V = E.S.deformed;
  for (std::size_t l = 0; l < E.adj.boundary_loops.size(); ++l) {
    const auto& loop = E.adj.boundary_loops[l];
    const auto& edges = E.adj.boundary_loop_edges[l];
    const int n = static_cast<int>(loop.size());
    std::vector<double> s(n + 1, 0.0);
    for (int k = 0; k < n; ++k)
      s[k + 1] = s[k] + (V.vertex(loop[(k + 1) % n]) - V.vertex(loop[k])).norm();
    const double total = s[n];
    auto place = [&](double arc, int kind) {
      arc = std::fmod(std::fmod(arc, total) + total, total);
      int k = static_cast<int>(std::upper_bound(s.begin(), s.end(), arc) - s.begin()) - 1;
      k = std::clamp(k, 0, n - 1);
      const double len = s[k + 1] - s[k];
      const double u = len > 0 ? std::clamp((arc - s[k]) / len, 0.0, 1.0) : 0.0;
      Seed sd;
      sd.kind = kind;
      sd.tri = edges[k][0];
      const int le = edges[k][1];
      sd.bary.setZero();
      sd.bary(le) = 1 - u;
      sd.bary((le + 1) % 3) = u;
      sd.pos = E.point(sd.tri, sd.bary);
      E.seeds.push_back(sd);
    };
    std::vector<int> corners;
    for (int k = 0; k < n; ++k)
      if (E.corner_vertex[loop[k]]) corners.push_back(k);
    if (corners.empty()) {
      const int m = std::max(3, static_cast<int>(std::lround(total / spacing)));
      const double phase = rng.uniform(0, total / m);
      for (int q = 0; q < m; ++q) place(phase + total * q / m, kBoundary);
      continue;
    }
    const int nc = static_cast<int>(corners.size());
    for (int c = 0; c < nc; ++c) {
      const double a = s[corners[c]];
      double b = s[corners[(c + 1) % nc]];
      if (b <= a) b += total;
      place(a, kCorner);
      const int gaps = std::max(1, static_cast<int>(std::lround((b - a) / spacing)));
      for (int q = 1; q < gaps; ++q) place(a + (b - a) * q / gaps, kBoundary);
    }
  }
}

/// 2-D Poisson-disk sampling of `count` interior seeds on M', constrained by the seeds present.
void seed_interior(Engine& E, int count, double radius, Rng& rng) {
  const auto& M = E.S.deformed;
  const int nt = M.num_faces();
  std::vector<double> cum(nt + 1, 0.0);
  for (int t = 0; t < nt; ++t)
    cum[t + 1] =
        cum[t] + triangle_area(M.vertex(M.F(t, 0)), M.vertex(M.F(t, 1)), M.vertex(M.F(t, 2)));
  const std::size_t fixed = E.seeds.size();
  double r = radius;
  int placed = 0;
  while (placed < count) {
    // Hash of the seeds so far at cell size r.
    std::unordered_map<std::uint64_t, std::vector<int>> grid;
    auto key = [&](const Vec3& p, int dx, int dy, int dz) {
      const auto ix = static_cast<std::int64_t>(std::floor((p(0) - E.lo(0)) / r)) + dx;
      const auto iy = static_cast<std::int64_t>(std::floor((p(1) - E.lo(1)) / r)) + dy;
      const auto iz = static_cast<std::int64_t>(std::floor((p(2) - E.lo(2)) / r)) + dz;
      return (static_cast<std::uint64_t>(ix & 0x1FFFFF) << 42) |
             (static_cast<std::uint64_t>(iy & 0x1FFFFF) << 21) |
             static_cast<std::uint64_t>(iz & 0x1FFFFF);
    };
    for (std::size_t i = 0; i < E.seeds.size(); ++i)
      grid[key(E.seeds[i].pos, 0, 0, 0)].push_back(static_cast<int>(i));
    const int attempts = 30 * (count - placed) + 100;
    for (int a = 0; a < attempts && placed < count; ++a) {
      const double x = rng.uniform(0, cum[nt]);
      int t = static_cast<int>(std::upper_bound(cum.begin(), cum.end(), x) - cum.begin()) - 1;
      t = std::clamp(t, 0, nt - 1);
      const double u = std::sqrt(rng.uniform()), v = rng.uniform();
      const Vec3 b(1 - u, u * (1 - v), u * v);
      const Vec3 p = E.point(t, b);
      bool ok = true;
      for (int dx = -1; dx <= 1 && ok; ++dx)
        for (int dy = -1; dy <= 1 && ok; ++dy)
          for (int dz = -1; dz <= 1 && ok; ++dz) {
            auto it = grid.find(key(p, dx, dy, dz));
            if (it == grid.end()) continue;
            for (int q : it->second)
              if ((E.seeds[q].pos - p).squaredNorm() < r * r) {
                ok = false;
                break;
              }
          }
      if (!ok) continue;
      Seed sd;
      sd.kind = kInterior;
      sd.tri = t;
      sd.bary = b;
      sd.pos = p;
      E.seeds.push_back(sd);
      grid[key(p, 0, 0, 0)].push_back(static_cast<int>(E.seeds.size() - 1));
      ++placed;
    }
    r *= 0.85;
    if (r < 1e-9 * (E.hi - E.lo).norm()) break;
  }
  (void)fixed;
}

// ---------------------------------------------------------------------------------------------
// Extraction.

struct Node {
  int tri = 0;  ///< support triangle
  Vec3 bary{1, 0, 0};
  int kind = 0;        ///< 0 Voronoi vertex, 1 border meets boundary, 2 corner
  int u = -1, v = -1;  ///< support edge (boundary nodes) or vertex (corner: u)
};

struct Extraction {
  bool ok = false;
  std::vector<Node> nodes;
  std::vector<std::vector<int>> faces;  ///< per seed (empty: seed without region)
  std::vector<int> bad_labels;          ///< cells to refine around on failure
  std::string problem;
};

Vec3 clamp_bary(Vec3 b) {
  b = b.cwiseMax(0.0);
  const double s = b.sum();
  return s > 0 ? Vec3(b / s) : Vec3(1.0 / 3, 1.0 / 3, 1.0 / 3);
}

Extraction extract(const Engine& E) {
  Extraction X;
  const auto& F = E.S.deformed.F;
  const auto& L = E.label;
  const int nt = static_cast<int>(F.rows());
  const int ns = static_cast<int>(E.seeds.size());
  auto mixed = [&](int t, int k) { return L[F(t, k)] != L[F(t, (k + 1) % 3)]; };
  auto nlabels = [&](int t) {
    const int a = L[F(t, 0)], b = L[F(t, 1)], c = L[F(t, 2)];
    return (a == b && b == c) ? 1 : (a != b && b != c && a != c) ? 3 : 2;
  };
  std::unordered_map<int, int> tri_node;
  std::unordered_map<int, int> edge_node;  // half-edge id 3t+k of boundary edges
  std::vector<int> corner_node(E.S.deformed.num_vertices(), -1);
  // Voronoi vertices.
  for (int t = 0; t < nt; ++t) {
    if (nlabels(t) != 3) continue;
    const Vec3 a = E.S.deformed.vertex(F(t, 0)), e1 = E.S.deformed.vertex(F(t, 1)) - a,
               e2 = E.S.deformed.vertex(F(t, 2)) - a;
    const Vec3 si = E.seeds[L[F(t, 0)]].pos, sj = E.seeds[L[F(t, 1)]].pos,
               sk = E.seeds[L[F(t, 2)]].pos;
    Eigen::Matrix2d A;
    Eigen::Vector2d rhs;
    const Vec3 dj = sj - si, dk = sk - si;
    A << 2 * e1.dot(dj), 2 * e2.dot(dj), 2 * e1.dot(dk), 2 * e2.dot(dk);
    rhs << sj.squaredNorm() - si.squaredNorm() - 2 * a.dot(dj),
        sk.squaredNorm() - si.squaredNorm() - 2 * a.dot(dk);
    Vec3 b(1.0 / 3, 1.0 / 3, 1.0 / 3);
    const double det = A.determinant();
    if (std::abs(det) > 1e-300) {
      const Eigen::Vector2d x = A.partialPivLu().solve(rhs);
      if (x.allFinite()) b = clamp_bary(Vec3(1 - x(0) - x(1), x(0), x(1)));
    }
    Node n;
    n.tri = t;
    n.bary = b;
    n.kind = 0;
    tri_node[t] = static_cast<int>(X.nodes.size());
    X.nodes.push_back(n);
  }
  // Boundary nodes and corners, and the boundary edges of the output, loop by loop.
  struct DirEdge {
    int from, to, cell;
  };
  std::vector<DirEdge> dedges;
  for (std::size_t l = 0; l < E.adj.boundary_loops.size(); ++l) {
    const auto& loop = E.adj.boundary_loops[l];
    const auto& edges = E.adj.boundary_loop_edges[l];
    std::vector<std::pair<int, int>> seq;  // (node, label after it)
    std::vector<double> seq_arc;           // arc length on M of each node along the loop
    const int nl = static_cast<int>(loop.size());
    std::vector<double> arc(nl + 1, 0.0);
    for (int k = 0; k < nl; ++k)
      arc[k + 1] = arc[k] + (E.S.rest.vertex(loop[(k + 1) % nl]) - E.S.rest.vertex(loop[k])).norm();
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const int v = loop[k];
      if (E.corner_vertex[v]) {
        const int t = edges[k][0], le = edges[k][1];
        Node n;
        n.tri = t;
        n.bary.setZero();
        n.bary(le) = 1;
        n.kind = 2;
        n.u = v;
        corner_node[v] = static_cast<int>(X.nodes.size());
        seq.emplace_back(corner_node[v], L[v]);
        seq_arc.push_back(arc[k]);
        X.nodes.push_back(n);
      }
      const int t = edges[k][0], le = edges[k][1];
      if (mixed(t, le)) {
        const int u = F(t, le), w = F(t, (le + 1) % 3);
        const Vec3 pu = E.S.deformed.vertex(u), pw = E.S.deformed.vertex(w);
        const Vec3 si = E.seeds[L[u]].pos, sj = E.seeds[L[w]].pos;
        const Vec3 d = sj - si;
        const double den = 2 * (pw - pu).dot(d);
        double s = 0.5;
        if (std::abs(den) > 1e-300) {
          s = (sj.squaredNorm() - si.squaredNorm() - 2 * pu.dot(d)) / den;
          if (!std::isfinite(s)) s = 0.5;
        }
        s = std::clamp(s, 0.0, 1.0);
        Node n;
        n.tri = t;
        n.bary.setZero();
        n.bary(le) = 1 - s;
        n.bary((le + 1) % 3) = s;
        n.kind = 1;
        n.u = u;
        n.v = w;
        edge_node[3 * t + le] = static_cast<int>(X.nodes.size());
        seq.emplace_back(static_cast<int>(X.nodes.size()), L[w]);
        seq_arc.push_back(arc[k] + s * (arc[k + 1] - arc[k]));
        X.nodes.push_back(n);
      }
    }
    if (seq.size() < 3) {
      X.problem = "a boundary loop meets fewer than 3 cell borders";
      X.bad_labels.push_back(L[loop[0]]);
      for (const auto& q : seq) X.bad_labels.push_back(q.second);
      return X;
    }
    for (std::size_t m = 0; m < seq.size(); ++m) {
      const std::size_t m1 = (m + 1) % seq.size();
      int from = seq[m].first;
      // Long boundary edges are divided along the input boundary into pieces of about
      // boundary_split·R (joints of valence 2 on the edge beam).
      if (E.boundary_split > 0) {
        const double a0 = seq_arc[m];
        double a1 = seq_arc[m1];
        if (a1 <= a0) a1 += arc[nl];
        const Node& na = X.nodes[seq[m].first];
        const Node& nb = X.nodes[seq[m1].first];
        const double chord = (E.rest_point(na.tri, na.bary) - E.rest_point(nb.tri, nb.bary)).norm();
        const int pieces = static_cast<int>(std::lround(chord / (E.boundary_split * E.R)));
        for (int q = 1; q < pieces; ++q) {
          double a = a0 + (a1 - a0) * q / pieces;
          if (a >= arc[nl]) a -= arc[nl];
          int k = static_cast<int>(std::upper_bound(arc.begin(), arc.end(), a) - arc.begin()) - 1;
          k = std::clamp(k, 0, nl - 1);
          const double len = arc[k + 1] - arc[k];
          const double u = len > 0 ? std::clamp((a - arc[k]) / len, 0.0, 1.0) : 0.0;
          Node n;
          n.tri = edges[k][0];
          const int le = edges[k][1];
          n.bary.setZero();
          n.bary(le) = 1 - u;
          n.bary((le + 1) % 3) = u;
          n.kind = 1;
          n.u = F(n.tri, le);
          n.v = F(n.tri, (le + 1) % 3);
          const int id = static_cast<int>(X.nodes.size());
          X.nodes.push_back(n);
          dedges.push_back({from, id, seq[m].second});
          from = id;
        }
      }
      dedges.push_back({from, seq[m1].first, seq[m].second});
    }
  }
  // Trace the borders between cells into chains from node to node.
  std::vector<char> visited(static_cast<std::size_t>(nt) * 3, 0);
  auto mark = [&](int t, int k) {
    visited[3 * t + k] = 1;
    const int u = E.adj.neighbor[t][k];
    if (u >= 0) visited[3 * u + E.adj.neighbor_edge[t][k]] = 1;
  };
  auto fail = [&](const std::string& what, std::initializer_list<int> labels) {
    X.problem = what;
    X.bad_labels.insert(X.bad_labels.end(), labels.begin(), labels.end());
  };
  // Walks from "inside triangle t, entered through local edge k" to the end node.
  auto walk = [&](int t, int k) -> int {
    for (int steps = 0; steps <= 3 * nt; ++steps) {
      if (nlabels(t) == 3) return tri_node.at(t);
      int k2 = -1;
      for (int q = 0; q < 3; ++q)
        if (q != k && mixed(t, q)) k2 = q;
      if (k2 < 0) return -1;
      mark(t, k2);
      const int u = E.adj.neighbor[t][k2];
      if (u < 0) return edge_node.at(3 * t + k2);
      k = E.adj.neighbor_edge[t][k2];
      t = u;
    }
    return -1;
  };
  auto add_chain = [&](int n0, int n1, int left, int right) {
    if (n1 < 0) {
      fail("a cell border could not be traced", {left, right});
      return;
    }
    if (n0 == n1) {
      fail("a cell border closes on itself", {left, right});
      return;
    }
    dedges.push_back({n0, n1, left});
    dedges.push_back({n1, n0, right});
  };
  for (int t = 0; t < nt && X.problem.empty(); ++t) {
    if (nlabels(t) != 3) continue;
    const int n0 = tri_node.at(t);
    for (int k = 0; k < 3; ++k) {
      if (visited[3 * t + k]) continue;
      const int u = F(t, k), w = F(t, (k + 1) % 3);
      mark(t, k);
      const int nb = E.adj.neighbor[t][k];
      const int n1 = nb < 0 ? edge_node.at(3 * t + k) : walk(nb, E.adj.neighbor_edge[t][k]);
      add_chain(n0, n1, L[w], L[u]);
    }
  }
  for (const auto& [h, n0] : edge_node) {
    if (!X.problem.empty()) break;
    const int t = h / 3, k = h % 3;
    if (visited[h]) continue;
    mark(t, k);
    add_chain(n0, walk(t, k), L[F(t, k)], L[F(t, (k + 1) % 3)]);
  }
  if (!X.problem.empty()) return X;
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k)
      if (mixed(t, k) && !visited[3 * t + k]) {
        fail("a cell is enclosed by another one (closed border)",
             {L[F(t, k)], L[F(t, (k + 1) % 3)]});
        return X;
      }
  // Each cell: its directed edges must form exactly one cycle.
  std::sort(dedges.begin(), dedges.end(), [](const DirEdge& a, const DirEdge& b) {
    return a.cell != b.cell ? a.cell < b.cell : a.from < b.from;
  });
  X.faces.assign(ns, {});
  for (std::size_t i = 0; i < dedges.size();) {
    std::size_t j = i;
    while (j < dedges.size() && dedges[j].cell == dedges[i].cell) ++j;
    const int cell = dedges[i].cell;
    std::unordered_map<int, int> next;
    bool ok = true;
    for (std::size_t q = i; q < j; ++q)
      if (!next.emplace(dedges[q].from, dedges[q].to).second) ok = false;
    std::vector<int> face;
    if (ok) {
      int cur = dedges[i].from;
      for (std::size_t q = i; q < j; ++q) {
        face.push_back(cur);
        auto it = next.find(cur);
        if (it == next.end()) {
          ok = false;
          break;
        }
        cur = it->second;
      }
      if (ok && (cur != dedges[i].from || face.size() < 3)) ok = false;
    }
    if (!ok) {
      fail("a cell is not a disk", {cell});
      return X;
    }
    X.faces[cell] = std::move(face);
    i = j;
  }
  X.ok = true;
  return X;
}

/// Makes every cell's region connected on the support mesh. The diagram is Euclidean in M′ (a
/// restricted Voronoi diagram), so where M′ bends sharply (a ridge, a narrow boundary lobe near a
/// support) the points nearest to one seed can fall into several pieces of the surface; such a
/// cell is not a disk, and refining does not change it. Each label keeps its largest connected
/// piece (vertices joined by support edges with that label; area on M′); every other piece (an
/// orphan) goes to the neighbouring cell it shares most support edges with, counting edges to kept
/// pieces only when there are any. Repeated until no orphan is left (at most 8 rounds). Sequential,
/// so deterministic. Returns the vertices relabelled.
int merge_orphan_pieces(Engine& E) {
  const auto& F = E.S.deformed.F;
  auto& L = E.label;
  const int nv = E.S.deformed.num_vertices();
  const int nt = static_cast<int>(F.rows());
  const int ns = static_cast<int>(E.seeds.size());
  int relabelled = 0;
  std::vector<int> parent(nv);
  std::vector<double> area(nv);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (int round = 0; round < 8; ++round) {
    std::iota(parent.begin(), parent.end(), 0);
    for (int t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k) {
        const int a = F(t, k), b = F(t, (k + 1) % 3);
        if (L[a] != L[b]) continue;
        const int ra = find(a), rb = find(b);
        if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
      }
    // Each label keeps its largest piece (area on M′; a vertex carries a third of its
    // triangles): the piece nearest to a fixed boundary seed can be a sliver.
    std::fill(area.begin(), area.end(), 0.0);
    for (int t = 0; t < nt; ++t) {
      const double third = triangle_area(E.S.deformed.vertex(F(t, 0)), E.S.deformed.vertex(F(t, 1)),
                                         E.S.deformed.vertex(F(t, 2))) /
                           3;
      for (int k = 0; k < 3; ++k) area[find(F(t, k))] += third;
    }
    std::vector<int> keep(ns, -1);
    std::vector<double> best(ns, -1.0);
    for (int v = 0; v < nv; ++v)
      if (find(v) == v && area[v] > best[L[v]]) {
        best[L[v]] = area[v];
        keep[L[v]] = v;
      }
    auto kept = [&](int v) { return find(v) == keep[L[v]]; };
    // Orphan pieces and their shared edges with other cells: (root, label) → (kept, any).
    std::map<std::pair<int, int>, std::pair<int, int>> shared;
    bool any_orphan = false;
    for (int t = 0; t < nt; ++t)
      for (int k = 0; k < 3; ++k) {
        const int a = F(t, k), b = F(t, (k + 1) % 3);
        if (L[a] == L[b]) continue;
        for (const auto& [o, n] : {std::pair{a, b}, std::pair{b, a}}) {
          if (kept(o)) continue;
          any_orphan = true;
          auto& c = shared[{find(o), L[n]}];
          c.first += kept(n) ? 1 : 0;
          c.second += 1;
        }
      }
    if (!any_orphan) {
      // An orphan piece with no border (a whole component of the surface) has nowhere to go.
      break;
    }
    std::unordered_map<int, std::pair<std::pair<int, int>, int>> target;  // root → (score, label)
    for (const auto& [key, c] : shared) {
      const auto [root, l] = key;
      auto it = target.find(root);
      if (it == target.end() || c > it->second.first) target[root] = {c, l};
    }
    for (int v = 0; v < nv; ++v) {
      if (kept(v)) continue;
      const auto it = target.find(find(v));
      if (it == target.end()) continue;
      L[v] = it->second.second;
      ++relabelled;
    }
  }
  return relabelled;
}

/// Collapses every output edge shorter than `min_length` that ends on the boundary: a Voronoi
/// vertex just inside the boundary, or two boundary joints side by side, would otherwise leave
/// a stub beam. The boundary end (a corner when there is one) is kept. Faces keep ≥ 3 corners;
/// unused nodes are dropped when the mesh is built.
int collapse_extraction_stubs(Extraction& X, const Engine& E, double min_length) {
  std::vector<Vec3> pos(X.nodes.size());
  std::vector<int> rank(X.nodes.size());
  for (std::size_t n = 0; n < X.nodes.size(); ++n) {
    pos[n] = E.rest_point(X.nodes[n].tri, X.nodes[n].bary);
    rank[n] = X.nodes[n].kind;  // Voronoi vertex, boundary joint, corner
  }
  return gridshell::collapse_boundary_stubs(X.faces, pos, rank, min_length);
}

int euler_of(const TriMesh& m) {
  const Topology t = build_topology(m);
  return m.num_vertices() - t.num_edges() + m.num_faces();
}

struct RunResult {
  Tessellation tess;
  bool ok = false;
};

Tessellation run_once(const TriMesh& rest, const TriMesh& deformed,
                      const std::vector<char>& supported, const std::vector<char>& corners,
                      int input_euler, int input_loops, double R, int cells,
                      const TessellationOptions& o) {
  const auto t_setup = std::chrono::steady_clock::now();
  Engine E;
  E.R = R;
  E.boundary_split = o.boundary_split;
  E.S = make_support_mesh(rest, deformed);
  const bool two_level = o.coarse_edge > o.support_edge;
  refine_to_length(E.S, (two_level ? o.coarse_edge : o.support_edge) * R);
  E.adj = build_triangle_adjacency(E.S.deformed.F, E.S.deformed.num_vertices());
  E.corner_vertex.assign(E.S.deformed.num_vertices(), 0);
  for (std::size_t v = 0; v < corners.size(); ++v) E.corner_vertex[v] = corners[v];
  E.lo = E.S.deformed.V.colwise().minCoeff().transpose();
  E.hi = E.S.deformed.V.colwise().maxCoeff().transpose();
  Rng rng(o.seed);
  const double spacing = o.boundary_spacing * kSqrt3 * R;
  seed_boundary(E, spacing, rng);
  const int nb = static_cast<int>(E.seeds.size());
  const double area = surface_area(deformed);
  int n_int = cells > 0 ? cells - nb
                        : static_cast<int>(std::lround((area - nb * 0.5 * kHexArea * R * R) /
                                                       (kHexArea * R * R)));
  n_int = std::max(n_int, 1);
  seed_interior(E, n_int, 0.8 * kSqrt3 * R, rng);
  Tessellation T;
  T.radius = R;
  T.seconds_setup =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_setup).count();
  const auto t_lloyd = std::chrono::steady_clock::now();
  const double tol = o.tolerance * R;
  int it = 0;
  // Level 1: the CVT on the (coarse) support mesh. The diagram is clipped exactly on the planar
  // triangles, so a coarse support mesh gives the same cells wherever every cell meeting a triangle
  // labels one of its corners or its neighbours' opposite corners.
  const double level1_tol = two_level ? o.coarse_tolerance * R : tol;
  // Lloyd steps until the seeds move less than `tolerance` (true) or `it` reaches `end`.
  const auto lloyd_until = [&](int end, double tolerance, const char* tag) {
    for (; it < end; ++it) {
      E.compute_labels(0, static_cast<int>(E.label.size()));
      const double move = E.lloyd_step(o.over_relaxation);
      spdlog::debug("{} {} move/R {:.3e}", tag, it, move / R);
      if (move < tolerance) {
        ++it;
        return true;
      }
    }
    return false;
  };
  if (o.quasi_newton) {
    it += E.minimize_energy(level1_tol, o.max_iterations, o.lbfgs_history, &T.converged);
    spdlog::debug("cvt: {} diagrams", it);
  } else {
    T.converged = lloyd_until(o.max_iterations, level1_tol, "lloyd");
  }
  // Level 2: a finer support mesh and a few (over-relaxed) Lloyd steps to `tolerance`.
  if (two_level && o.fine_iterations > 0) {
    std::vector<int> source;
    const int old_faces = E.S.deformed.num_faces();
    refine_to_length(E.S, o.support_edge * R, &source);
    E.adj = build_triangle_adjacency(E.S.deformed.F, E.S.deformed.num_vertices());
    E.corner_vertex.resize(E.S.deformed.num_vertices(), 0);
    E.relocate_seeds(source, old_faces);
    T.converged =
        lloyd_until(std::min(o.max_iterations, it + o.fine_iterations), tol, "fine lloyd");
  }
  T.support_vertices = E.S.deformed.num_vertices();
  T.iterations = it;
  T.seconds_lloyd =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_lloyd).count();
  const auto t_extract = std::chrono::steady_clock::now();
  // Seeds on M (before the mesh is refined further for extraction).
  std::vector<Vec3> seed_rest(E.seeds.size());
  for (std::size_t i = 0; i < E.seeds.size(); ++i)
    seed_rest[i] = E.rest_point(E.seeds[i].tri, E.seeds[i].bary);
  // Extraction: refine across borders, then extract; repair by refining around bad cells.
  E.compute_labels(0, static_cast<int>(E.label.size()));
  if (o.extraction_base > 0) {
    // A cell corner can poke between the corners of a coarse triangle without labelling any of
    // them; the border refinement below would not see it. Sample the whole surface at
    // extraction_base·R first (as the old single-level engine did at 0.2 R).
    const int nv0 = E.S.deformed.num_vertices();
    refine_to_length(E.S, o.extraction_base * R);
    E.corner_vertex.resize(E.S.deformed.num_vertices(), 0);
    E.compute_labels(nv0);
  }
  const double he = o.extraction_edge * R;
  // Passes to bring the longest border edge down to `extraction_edge`, and a few more.
  double longest = 0;
  for (int t = 0; t < E.S.deformed.num_faces(); ++t)
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (E.S.deformed.vertex(E.S.deformed.F(t, k)) -
                                   E.S.deformed.vertex(E.S.deformed.F(t, (k + 1) % 3)))
                                      .squaredNorm());
  const int passes =
      std::max(o.extraction_passes,
               static_cast<int>(std::ceil(std::log2(std::max(1.0, std::sqrt(longest) / he)))) + 1);
  for (int pass = 0; pass < passes; ++pass) {
    const double h2 = he * he;
    const int nv0 = E.S.deformed.num_vertices();
    const int n = refine_support_mesh(E.S, [&](int a, int b) {
      return E.label[a] != E.label[b] &&
             (E.S.deformed.vertex(a) - E.S.deformed.vertex(b)).squaredNorm() > h2;
    });
    E.corner_vertex.resize(E.S.deformed.num_vertices(), 0);
    if (n == 0) break;
    E.compute_labels(nv0);  // the seeds did not move: only the new vertices need labels
  }
  spdlog::debug(
      "extraction refinement: {} support vertices, {:.2f} s", E.S.deformed.num_vertices(),
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_extract).count());
  Extraction X;
  double hr = he;
  for (int attempt = 0;; ++attempt) {
    E.adj = build_triangle_adjacency(E.S.deformed.F, E.S.deformed.num_vertices());
    // Detached pieces of a cell's region (M′ bending back within a cell size) would make it
    // a non-disk that no refinement repairs: they join a neighbouring cell first.
    const int orphans = merge_orphan_pieces(E);
    if (orphans > 0)
      spdlog::debug("extraction: {} support vertices moved from detached cell pieces", orphans);
    X = extract(E);
    spdlog::debug(
        "extract attempt {}: {} ({:.2f} s)", attempt, X.ok ? "ok" : X.problem,
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_extract).count());
    PolyMesh poly;
    std::vector<int> face_seed;
    if (X.ok) {
      if (o.stub_length > 0) collapse_extraction_stubs(X, E, o.stub_length * R);
      // Keep the nodes that faces use, in order.
      std::vector<int> id(X.nodes.size(), -1);
      for (const auto& f : X.faces)
        for (int v : f) id[v] = 0;
      std::vector<Node> used;
      for (std::size_t n = 0; n < X.nodes.size(); ++n)
        if (id[n] >= 0) {
          id[n] = static_cast<int>(used.size());
          used.push_back(X.nodes[n]);
        }
      X.nodes = std::move(used);
      for (auto& f : X.faces)
        for (int& v : f) v = id[v];
      poly.V.resize(static_cast<int>(X.nodes.size()), 3);
      for (std::size_t n = 0; n < X.nodes.size(); ++n)
        poly.V.row(static_cast<int>(n)) = E.rest_point(X.nodes[n].tri, X.nodes[n].bary).transpose();
      for (std::size_t i = 0; i < X.faces.size(); ++i)
        if (!X.faces[i].empty()) {
          poly.faces.push_back(X.faces[i]);
          face_seed.push_back(static_cast<int>(i));
        }
      const TessellationQuality q = measure_quality(poly);
      if (!q.manifold) {
        X.ok = false;
        X.problem = "the extracted mesh is not a valid manifold";
      } else if (q.euler != input_euler || q.boundary_loops != input_loops) {
        X.ok = false;
        X.problem = "the extracted mesh changed the topology of the surface";
      }
      if (X.ok) {
        T.mesh = std::move(poly);
        T.quality = q;
        const int nn = T.mesh.num_vertices();
        T.on_boundary.assign(nn, 0);
        T.corner.assign(nn, 0);
        T.vertex_triangle.assign(nn, 0);
        T.vertex_bary.assign(nn, Vec3(1, 0, 0));
        std::vector<char> sup(nn, 0);
        for (int n = 0; n < nn; ++n) {
          const Node& nd = X.nodes[n];
          const auto [ot, ob] = to_original(E.S, nd.tri, nd.bary);
          T.vertex_triangle[n] = ot;
          T.vertex_bary[n] = ob;
          if (nd.kind == 2) {
            T.on_boundary[n] = 1;
            T.corner[n] = 1;
            sup[n] = supported[nd.u];
          } else if (nd.kind == 1) {
            T.on_boundary[n] = 1;
            // The original edge this support edge lies on.
            const auto ou = E.S.origin[nd.u], ow = E.S.origin[nd.v];
            int ids[4] = {ou[0], ou[1], ow[0], ow[1]};
            std::sort(ids, ids + 4);
            const int k = static_cast<int>(std::unique(ids, ids + 4) - ids);
            if (k == 2 && ids[0] >= 0) {
              const int a = ids[0], b = ids[1];
              const Vec3 pa = rest.vertex(a), pb = rest.vertex(b), p = T.mesh.vertex(n);
              const double s = (p - pa).dot(pb - pa) / std::max((pb - pa).squaredNorm(), 1e-300);
              if (supported[a] && supported[b])
                sup[n] = 1;
              else if (supported[a] && s <= 0.5)
                sup[n] = 1;
              else if (supported[b] && s >= 0.5)
                sup[n] = 1;
            }
          }
        }
        // Supported input vertices that the rule above cannot see: interior ones, and isolated
        // supported boundary vertices; their nearest output (boundary) vertex becomes a support.
        const TriangleAdjacency oadj = build_triangle_adjacency(rest.F, rest.num_vertices());
        std::vector<int> prev(rest.num_vertices(), -1), nextv(rest.num_vertices(), -1);
        for (const auto& loop : oadj.boundary_loops)
          for (std::size_t k = 0; k < loop.size(); ++k) {
            nextv[loop[k]] = loop[(k + 1) % loop.size()];
            prev[loop[(k + 1) % loop.size()]] = loop[k];
          }
        for (int v = 0; v < rest.num_vertices(); ++v) {
          if (!supported[v]) continue;
          const bool on_b = nextv[v] >= 0;
          if (on_b && (supported[nextv[v]] || supported[prev[v]])) continue;
          int best = -1;
          double bd = std::numeric_limits<double>::infinity();
          for (int n = 0; n < nn; ++n) {
            if (on_b && !T.on_boundary[n]) continue;
            const double d = (T.mesh.vertex(n) - rest.vertex(v)).squaredNorm();
            if (d < bd) {
              bd = d;
              best = n;
            }
          }
          if (best >= 0) sup[best] = 1;
        }
        for (int n = 0; n < nn; ++n)
          if (sup[n]) T.supports.push_back(n);
        for (int f : face_seed) T.seeds.push_back(seed_rest[f]);
        T.repairs = attempt;
        T.orphan_vertices = orphans;
        T.seconds_extraction =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t_extract).count();
        return T;
      }
    }
    if (attempt >= 4)
      throw ExtractionError("tessellation", "could not extract a valid polygon mesh (" + X.problem +
                                      "); try another --seed or size");
    spdlog::info("tessellation: repairing ({}), refining the support mesh", X.problem);
    hr *= 0.5;
    std::vector<char> bad(E.seeds.size(), X.bad_labels.empty() ? 1 : 0);
    for (int l : X.bad_labels)
      if (l >= 0 && l < static_cast<int>(bad.size())) bad[l] = 1;
    for (int pass = 0; pass < 3; ++pass) {
      const double h2 = hr * hr;
      const int nv0 = E.S.deformed.num_vertices();
      const int n = refine_support_mesh(E.S, [&](int a, int b) {
        return (bad[E.label[a]] || bad[E.label[b]]) && (E.label[a] != E.label[b] || pass == 0) &&
               (E.S.deformed.vertex(a) - E.S.deformed.vertex(b)).squaredNorm() > h2;
      });
      E.corner_vertex.resize(E.S.deformed.num_vertices(), 0);
      if (n == 0) break;
      E.compute_labels(nv0);
    }
  }
}

double radius_for_cells(double area, double perimeter, int cells, double bs) {
  // cells ≈ area / (kHexArea R²) + (boundary seeds) / 2, boundary seeds ≈ perimeter / (bs √3 R).
  const double a = area / kHexArea, b = perimeter / (2 * bs * kSqrt3);
  const double x = (-b + std::sqrt(b * b + 4 * a * cells)) / (2 * a);
  return 1.0 / x;
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

namespace {
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
}  // namespace

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
  const TriangleAdjacency adj = build_triangle_adjacency(rest.F, rest.num_vertices());
  std::vector<char> supported(rest.num_vertices(), 0);
  for (int v : rest_supports) {
    if (v < 0 || v >= rest.num_vertices()) throw Error("supports", "vertex id out of range");
    supported[v] = 1;
  }
  const std::vector<char> corners = boundary_corners(rest.V, adj.boundary_loops, o.corner_angle_deg);
  const int input_euler = euler_of(rest);
  const int input_loops = static_cast<int>(adj.boundary_loops.size());
  const double area = surface_area(deformed);
  double perimeter = 0;
  for (const auto& loop : adj.boundary_loops)
    for (std::size_t k = 0; k < loop.size(); ++k)
      perimeter += (deformed.vertex(loop[k]) - deformed.vertex(loop[(k + 1) % loop.size()])).norm();
  if (!(area > 0)) throw Error("surface", "zero area");
  const double bs = o.boundary_spacing;
  auto guard_R = [&](double R, const char* subject) {
    if (!(R > 0) || !std::isfinite(R)) throw Error(subject, "gives no valid cell size");
    const double cells_est = area / (kHexArea * R * R);
    if (cells_est > 2e5) throw Error(subject, "asks for too many cells (more than 200000)");
    return R;
  };
  if (o.length > 0) {
    // Total length ≈ 3 R per cell ⇒ ℓ(R) ≈ 3 area / (kHexArea R): solve by secant in log-log.
    double R = guard_R(3 * area / (kHexArea * o.length), "--length");
    Tessellation best;
    double best_err = std::numeric_limits<double>::infinity();
    double lr_prev = 0, ll_prev = 0;
    bool have_prev = false;
    int runs = 0;
    for (; runs < 8; ++runs) {
      Tessellation t = run_once(rest, deformed, supported, corners, input_euler, input_loops,
                                guard_R(R, "--length"), 0, o);
      const double len = t.quality.total_length - length_on_planes(t.mesh, o);
      const double err = std::abs(len / o.length - 1);
      spdlog::info("tessellation: R = {:.4g} m gives total length {:.5g} m (target {:.5g})", R, len,
                   o.length);
      if (err < best_err) {
        best_err = err;
        best = std::move(t);
      }
      if (err <= 0.4 * o.length_tolerance) break;
      const double lr = std::log(R), ll = std::log(len);
      double slope = -1;
      if (have_prev && std::abs(lr - lr_prev) > 1e-9) {
        slope = (ll - ll_prev) / (lr - lr_prev);
        if (!(slope < -0.3 && slope > -3)) slope = -1;
      }
      lr_prev = lr;
      ll_prev = ll;
      have_prev = true;
      R = std::exp(lr + (std::log(o.length) - ll) / slope);
    }
    best.length_runs = runs + 1;
    if (best_err > o.length_tolerance)
      spdlog::warn("tessellation: total length off target by {:.1f}%", 100 * best_err);
    return best;
  }
  double R = o.radius;
  int cells = o.cells;
  if (R <= 0) {
    if (cells <= 0) cells = o.default_cells;
    R = radius_for_cells(area, perimeter, cells, bs);
  }
  guard_R(R, o.radius > 0 ? "--radius" : "--cells");
  return run_once(rest, deformed, supported, corners, input_euler, input_loops, R, cells, o);
}

LloydBenchmark benchmark_lloyd(const TriMesh& surface, int cells, double support_edge, int warmup,
                               std::uint64_t seed) {
  Engine E;
  double area = surface_area(surface);
  const TriangleAdjacency adj0 = build_triangle_adjacency(surface.F, surface.num_vertices());
  double perimeter = 0;
  for (const auto& loop : adj0.boundary_loops)
    for (std::size_t k = 0; k < loop.size(); ++k)
      perimeter += (surface.vertex(loop[k]) - surface.vertex(loop[(k + 1) % loop.size()])).norm();
  E.R = radius_for_cells(area, perimeter, cells, 1.0);
  E.S = make_support_mesh(surface, surface);
  refine_to_length(E.S, support_edge * E.R);
  E.adj = build_triangle_adjacency(E.S.deformed.F, E.S.deformed.num_vertices());
  const std::vector<char> corners = boundary_corners(surface.V, adj0.boundary_loops, 30);
  E.corner_vertex.assign(E.S.deformed.num_vertices(), 0);
  for (std::size_t v = 0; v < corners.size(); ++v) E.corner_vertex[v] = corners[v];
  E.lo = E.S.deformed.V.colwise().minCoeff().transpose();
  E.hi = E.S.deformed.V.colwise().maxCoeff().transpose();
  Rng rng(seed);
  seed_boundary(E, kSqrt3 * E.R, rng);
  const int nb = static_cast<int>(E.seeds.size());
  seed_interior(E, std::max(1, cells - nb), 0.8 * kSqrt3 * E.R, rng);
  for (int i = 0; i < warmup; ++i) {
    E.compute_labels();
    E.lloyd_step();
  }
  LloydBenchmark b;
  b.support_vertices = E.S.deformed.num_vertices();
  b.seeds = static_cast<int>(E.seeds.size());
  const auto t0 = std::chrono::steady_clock::now();
  E.compute_labels();
  b.max_move = E.lloyd_step();
  b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return b;
}

}  // namespace gridshell
