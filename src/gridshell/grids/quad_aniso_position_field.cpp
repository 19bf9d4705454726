#include "gridshell/grids/quad_aniso_internal.h"

#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <utility>
#include <vector>

#include "gridshell/core/rng.h"

namespace gridshell::quad_aniso_internal {

namespace {

/// The lattice point (origin o, axes q, t, spacing h) nearest p, or the one below-left of p.
Vec3 lattice_round(const Vec3& o, const Vec3& q, const Vec3& t, const Vec3& p, double h) {
  const Vec3 d = p - o;
  return o + q * (h * std::round(q.dot(d) / h)) + t * (h * std::round(t.dot(d) / h));
}

Vec3 lattice_floor(const Vec3& o, const Vec3& q, const Vec3& t, const Vec3& p, double h) {
  const Vec3 d = p - o;
  return o + q * (h * std::floor(q.dot(d) / h)) + t * (h * std::floor(t.dot(d) / h));
}

/// Gauss–Seidel sweeps of the position field on one level: each vertex's lattice origin is the
/// average of its neighbours' lattices compared at the edges' middles, rounded back to the
/// lattice point nearest the vertex.
void smooth_position(const Level& l, const CrossField& cf, const MatchedFrames& mf,
                     const std::vector<double>& hs, std::vector<Vec3>& org, int iterations) {
  const std::vector<Vec3>&n = cf.n, &q = cf.q, &t = cf.t, &pos = l.p;
  for (int it = 0; it < iterations; ++it) {
    for (int i = 0; i < l.size(); ++i) {
      Vec3 sum = org[i];
      double weight = 0;
      const int k0 = mf.offset[i];
      for (size_t k = 0; k < l.nbr[i].size(); ++k) {
        const int j = l.nbr[i][k];
        const auto [a, b] = compat_position(pos[i], q[i], t[i], sum, hs[i], pos[j], mf.q[k0 + k],
                                            mf.t[k0 + k], org[j], hs[j]);
        sum = (a * weight + b) / (weight + 1);
        weight += 1;
        sum -= n[i] * n[i].dot(sum - pos[i]);
      }
      org[i] = lattice_round(sum, q[i], t[i], pos[i], hs[i]);
    }
  }
}

}  // namespace

std::pair<Vec3, Vec3> compat_position(const Vec3& v0, const Vec3& q0, const Vec3& t0,
                                      const Vec3& o0, double h0, const Vec3& v1, const Vec3& q1,
                                      const Vec3& t1, const Vec3& o1, double h1) {
  const Vec3 m = 0.5 * (v0 + v1);
  const Vec3 a = lattice_floor(o0, q0, t0, m, h0), b = lattice_floor(o1, q1, t1, m, h1);
  std::array<Vec3, 4> as, bs;  // the 4 corners of the cell around m, on each side
  for (int i = 0; i < 4; ++i) {
    as[i] = a + h0 * ((i & 1) * q0 + (i >> 1) * t0);
    bs[i] = b + h1 * ((i & 1) * q1 + (i >> 1) * t1);
  }
  int best_i = 0, best_j = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const double d = (as[i] - bs[j]).squaredNorm();
      if (d < best_d) best_d = d, best_i = i, best_j = j;
    }
  return {as[best_i], bs[best_j]};
}

std::vector<Vec3> position_field(const std::vector<Level>& levels,
                                 const std::vector<CrossField>& cfs,
                                 const std::vector<MatchedFrames>& matched,
                                 const std::vector<std::vector<double>>& scale, double h,
                                 const QuadAnisoOptions& o) {
  const int nl = static_cast<int>(levels.size());
  std::vector<Vec3> org;
  for (int k = nl - 1; k >= 0; --k) {
    const Level& l = levels[k];
    const std::vector<Vec3>&n = cfs[k].n, &q = cfs[k].q, &t = cfs[k].t, &pos = l.p;
    std::vector<double> hs(l.size());
    for (int v = 0; v < l.size(); ++v) hs[v] = h * scale[k][v];
    std::vector<Vec3> next(l.size());
    if (k == nl - 1) {
      std::vector<char> seen(l.size(), 0);
      Rng rng(o.seed);
      for (int root = 0; root < l.size(); ++root) {
        if (seen[root]) continue;
        next[root] = pos[root] + hs[root] * (rng.uniform(-0.5, 0.5) * q[root] +
                                             rng.uniform(-0.5, 0.5) * t[root]);
        seen[root] = 1;
        std::deque<int> queue{root};
        while (!queue.empty()) {
          const int i = queue.front();
          queue.pop_front();
          for (int j : l.nbr[i]) {
            if (seen[j]) continue;
            seen[j] = 1;
            const Vec3 oj = next[i] - n[j] * n[j].dot(next[i] - pos[j]);
            next[j] = lattice_round(oj, q[j], t[j], pos[j], hs[j]);
            queue.push_back(j);
          }
        }
      }
    } else {
      for (int v = 0; v < l.size(); ++v) {
        const Vec3& op = org[l.parent[v]];
        next[v] = lattice_round(op - n[v] * n[v].dot(op - pos[v]), q[v], t[v], pos[v], hs[v]);
      }
    }
    org = std::move(next);
    smooth_position(l, cfs[k], matched[k], hs, org,
                    k == 0 ? o.position_iterations : o.coarse_position_iterations);
  }
  return org;
}

}  // namespace gridshell::quad_aniso_internal
