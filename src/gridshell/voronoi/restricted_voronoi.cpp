#include "gridshell/voronoi/engine.h"

// The restricted Voronoi diagram of the seeds on M′ (Euclidean in M′, exact on the support
// mesh's planar triangles): nearest-seed labels of the support vertices, clipping of the
// triangles with several labels, per-cell integrals; placing seeds back on the surface.
// docs/voronoi.md "Method", Voronoi diagram.

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace gridshell::voronoi {

namespace {

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

  /// Index of the seed nearest to p (ties: lowest index), seed `exclude` left out, knowing a
  /// seed `hint` (not `exclude`): only the cells meeting the box of half-width |p − hint| around p
  /// can hold a nearer (or tied) seed.
  int nearest(const Vec3& p, int hint, int exclude = -1) const {
    double bd = (pts_[hint] - p).squaredNorm();
    int best = hint;
    const double r = std::sqrt(bd);
    int c0[3], c1[3];
    coords(p - Vec3::Constant(r), c0);
    coords(p + Vec3::Constant(r), c1);
    for (int k = c0[2]; k <= c1[2]; ++k)
      for (int j = c0[1]; j <= c1[1]; ++j)
        for (int i = c0[0]; i <= c1[0]; ++i)
          scan((k * n_[1] + j) * n_[0] + i, p, bd, best, exclude);
    return best;
  }

  /// Index of the seed nearest to p (ties: lowest index).
  int nearest(const Vec3& p) const { return nearest_except(p, -1); }

  /// Index of the seed nearest to p (ties: lowest index), seed `exclude` left out, searched ring
  /// by ring from p's grid cell; -1 when there is no other seed.
  int nearest_except(const Vec3& p, int exclude) const {
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
            scan((k * n_[1] + j) * n_[0] + i, p, bd, best, exclude);
          }
        }
      }
      // Points outside the searched cube are at least r·cell away.
      if (best >= 0 && std::sqrt(bd) <= r * cell_) break;
    }
    return best;
  }

 private:
  /// Updates (bd, best) with the seeds of grid cell cc but `exclude`: squared distance, ties to
  /// the lowest index.
  void scan(int cc, const Vec3& p, double& bd, int& best, int exclude = -1) const {
    for (int s = start_[cc]; s < start_[cc + 1]; ++s) {
      const int q = items_[s];
      if (q == exclude) continue;
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

/// Fills the engine's per-triangle cache for the current support mesh when it is stale (the
/// same arithmetic as a whole triangle's piece had, so the integrals do not change by a bit).
void cache_triangles(Engine& E) {
  const int nt = E.S.deformed.num_faces();
  if (static_cast<int>(E.tri_area.size()) == nt) return;
  E.tri_area.resize(nt);
  E.tri_moment.resize(nt);
  E.tri_center.resize(nt);
  E.tri_radius.resize(nt);
  const auto& F = E.S.deformed.F;
  tbb::parallel_for(tbb::blocked_range<int>(0, nt, 4096), [&](const tbb::blocked_range<int>& r) {
    for (int t = r.begin(); t < r.end(); ++t) {
      const Vec3 pa = E.S.deformed.vertex(F(t, 0)), pb = E.S.deformed.vertex(F(t, 1)),
                 pc = E.S.deformed.vertex(F(t, 2));
      const double ar = triangle_area(pa, pb, pc);
      E.tri_area[t] = ar;
      E.tri_moment[t] = ar * (pa + pb + pc) / 3.0;
      const Vec3 g = (pa + pb + pc) / 3.0;
      E.tri_center[t] = g;
      E.tri_radius[t] =
          std::sqrt(std::max({(pa - g).squaredNorm(), (pb - g).squaredNorm(), (pc - g).squaredNorm()}));
    }
  });
}

}  // namespace

void compute_labels(Engine& E, int first, int labelled) {
  const std::vector<Vec3> pts = E.seed_positions();
  SeedGrid grid(pts, E.lo, E.hi, E.R);
  const int nv = E.S.deformed.num_vertices();
  const int ns = static_cast<int>(E.seeds.size());
  labelled = std::min(labelled, static_cast<int>(E.label.size()));
  E.label.resize(nv, 0);
  // A vertex without a label of its own takes the label of the vertex whose edge split made it
  // (followed back to a labelled one) as its hint: any seed is an exact hint, a near one is cheap.
  const int known = std::max(labelled, std::min(first, static_cast<int>(E.label.size())));
  const auto hint = [&](int v) {
    int u = v;
    while (u >= known && u < static_cast<int>(E.S.split_end.size())) u = E.S.split_end[u];
    const int l = u >= 0 && u < known ? E.label[u] : -1;
    return l >= 0 && l < ns ? l : -1;
  };
  // A point closer to seed s than half the distance from s to its nearest other seed has s as
  // its only nearest seed (triangle inequality): most vertices keep their hint's label after one
  // distance (the disk of that radius is 91 % of a regular hexagon; 61–68 % of the support
  // vertices on a funicular during its first Lloyd steps, tests/voronoi_test.cpp). The bound is
  // shrunk by a relative 4e-9, far above the rounding of the squared distances, so the label is
  // the exhaustive search's, bit for bit; coincident seeds give a bound of 0 (always searched).
  std::vector<double> sure(ns, std::numeric_limits<double>::infinity());
  E.nearest_seed.resize(ns, -1);
  if (ns > 1)
    tbb::parallel_for(tbb::blocked_range<int>(0, ns, 1024), [&](const tbb::blocked_range<int>& r) {
      for (int i = r.begin(); i < r.end(); ++i) {
        const int h = E.nearest_seed[i];
        const int j = h >= 0 && h < ns && h != i ? grid.nearest(pts[i], h, i)
                                                 : grid.nearest_except(pts[i], i);
        E.nearest_seed[i] = j;
        sure[i] = 0.25 * (pts[j] - pts[i]).squaredNorm() * (1 - 4e-9);
      }
    });
  tbb::parallel_for(
      tbb::blocked_range<int>(first, nv, 4096), [&](const tbb::blocked_range<int>& r) {
        for (int v = r.begin(); v < r.end(); ++v) {
          const Vec3 p = E.S.deformed.vertex(v);
          const int h = hint(v);
          if (h >= 0 && (pts[h] - p).squaredNorm() < sure[h])
            E.label[v] = h;
          else
            E.label[v] = h >= 0 ? grid.nearest(p, h) : grid.nearest(p);
        }
      });
}

/// A triangle whose three corners share a label goes whole to that seed; any other triangle is
/// clipped by the bisector planes of the seeds labelling its corners and its neighbours'
/// opposite corners. Blocks of triangles are clipped in parallel and summed in triangle order,
/// so the result does not depend on the thread count.
void integrate(Engine& E) {
  constexpr int kBlock = 2048;
  const int ns = static_cast<int>(E.seeds.size());
  const int nt = E.S.deformed.num_faces();
  const int nb = (nt + kBlock - 1) / kBlock;
  E.chunk_pieces.resize(nb);
  const auto& F = E.S.deformed.F;
  cache_triangles(E);
  auto tri_energy = [](const Vec3& a, const Vec3& b, const Vec3& c, double ar) {
    return ar / 6.0 *
           (a.squaredNorm() + b.squaredNorm() + c.squaredNorm() + a.dot(b) + b.dot(c) + c.dot(a));
  };
  tbb::parallel_for(tbb::blocked_range<int>(0, nb, 1), [&](const tbb::blocked_range<int>& r) {
    for (int blk = r.begin(); blk < r.end(); ++blk) {
      auto& out = E.chunk_pieces[blk];
      out.clear();
      const int t1 = std::min(nt, (blk + 1) * kBlock);
      int cand[12];
      for (int t = blk * kBlock; t < t1; ++t) {
        const int a = F(t, 0), b = F(t, 1), c = F(t, 2);
        const int la = E.label[a], lb = E.label[b], lc = E.label[c];
        const Vec3 pa = E.S.deformed.vertex(a), pb = E.S.deformed.vertex(b),
                   pc = E.S.deformed.vertex(c);
        if (la == lb && lb == lc) {
          const double ar = E.tri_area[t];
          const Vec3& s = E.seeds[la].pos;
          out.push_back({la, t, ar, tri_energy(pa - s, pb - s, pc - s, ar), E.tri_moment[t]});
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
          const int u = E.adj.neighbor[t][k];
          if (u < 0) continue;
          add(E.label[F(u, (E.adj.neighbor_edge[t][k] + 2) % 3)]);
        }
        for (int q = 0; q < nc; ++q) {
          const int i = cand[q];
          Poly P;
          P.n = 3;
          P.p[0] = pa;
          P.p[1] = pb;
          P.p[2] = pc;
          for (int r2 = 0; r2 < nc && P.n > 0; ++r2)
            if (r2 != q) clip(P, E.seeds[i].pos, E.seeds[cand[r2]].pos);
          if (P.n < 3) continue;
          const Vec3& s = E.seeds[i].pos;
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
  E.area.assign(ns, 0.0);
  E.moment.assign(ns, Vec3::Zero());
  E.energy = 0;
  E.cell_start.assign(ns + 1, 0);
  for (const auto& blk : E.chunk_pieces)
    for (const Piece& p : blk) {
      E.area[p.cell] += p.area;
      E.moment[p.cell] += p.moment;
      E.energy += p.energy;
      ++E.cell_start[p.cell + 1];
    }
  for (int i = 0; i < ns; ++i) E.cell_start[i + 1] += E.cell_start[i];
  E.cell_tris.resize(E.cell_start[ns]);
  std::vector<int> fill(E.cell_start.begin(), E.cell_start.end() - 1);
  for (const auto& blk : E.chunk_pieces)
    for (const Piece& p : blk) E.cell_tris[fill[p.cell]++] = p.tri;
}

/// The closest point is the first, in the region's order, of the triangles at the least
/// distance. A triangle whose ball (tri_center, tri_radius) is farther from c than an upper
/// bound of that distance cannot be it and is skipped: the bound is the distance to the triangle
/// whose centre is nearest to c, the skip test keeps a relative margin of 1e-9 far above
/// round-off, so the answer is the one of the full search, bit for bit.
double place_on_region(Engine& E, int i, const Vec3& c) {
  cache_triangles(E);
  const auto& F = E.S.deformed.F;
  const auto distance2 = [&](int t, Vec3& w) {
    w = closest_point_on_triangle(c, E.S.deformed.vertex(F(t, 0)), E.S.deformed.vertex(F(t, 1)),
                                  E.S.deformed.vertex(F(t, 2)))
            .bary;
    return (E.point(t, w) - c).squaredNorm();
  };
  double bound = std::numeric_limits<double>::infinity();
  {
    int near = -1;
    double g2 = std::numeric_limits<double>::infinity();
    for (int s = E.cell_start[i]; s < E.cell_start[i + 1]; ++s) {
      const int t = E.cell_tris[s];
      const double d = (E.tri_center[t] - c).squaredNorm();
      if (d < g2) {
        g2 = d;
        near = t;
      }
    }
    Vec3 w;
    if (near >= 0) bound = distance2(near, w) * (1 + 1e-9);
  }
  double best = std::numeric_limits<double>::infinity();
  int bt = E.seeds[i].tri;
  Vec3 bb = E.seeds[i].bary;
  for (int s = E.cell_start[i]; s < E.cell_start[i + 1]; ++s) {
    const int t = E.cell_tris[s];
    const double gap = (E.tri_center[t] - c).norm() - E.tri_radius[t] * (1 + 1e-9) - 1e-12;
    if (gap > 0 && gap * gap > std::min(best, bound) * (1 + 1e-9)) continue;
    Vec3 w;
    const double d = distance2(t, w);
    if (d < best) {
      best = d;
      bt = t;
      bb = w;
    }
  }
  E.seeds[i].tri = bt;
  E.seeds[i].bary = bb;
  const Vec3 p = E.point(bt, bb);
  const double moved = (p - E.seeds[i].pos).squaredNorm();
  E.seeds[i].pos = p;
  return moved;
}

void relocate_seeds(Engine& E, const std::vector<int>& source, int old_faces) {
  std::vector<int> start(old_faces + 1, 0);
  for (int s : source) ++start[s + 1];
  for (int i = 0; i < old_faces; ++i) start[i + 1] += start[i];
  std::vector<int> kids(source.size());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < source.size(); ++t) kids[fill[source[t]]++] = static_cast<int>(t);
  const auto& F = E.S.deformed.F;
  for (Seed& sd : E.seeds) {
    double best = std::numeric_limits<double>::infinity();
    int bt = -1;
    Vec3 bb;
    for (int q = start[sd.tri]; q < start[sd.tri + 1]; ++q) {
      const int t = kids[q];
      const Vec3 w = closest_point_on_triangle(sd.pos, E.S.deformed.vertex(F(t, 0)),
                                               E.S.deformed.vertex(F(t, 1)),
                                               E.S.deformed.vertex(F(t, 2)))
                         .bary;
      const double d = (E.point(t, w) - sd.pos).squaredNorm();
      if (d < best) {
        best = d;
        bt = t;
        bb = w;
      }
    }
    if (bt >= 0) {
      sd.tri = bt;
      sd.bary = bb;
      sd.pos = E.point(bt, bb);
    }
  }
}

}  // namespace gridshell::voronoi
