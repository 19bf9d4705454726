#include "gridshell/voronoi/engine.h"

// Seeding: the support mesh a run starts on, boundary seeds along the loops, Poisson-disk
// interior seeds. docs/voronoi.md "Method", Seeds.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace gridshell::voronoi {

void set_up_support(Engine& E, const TriMesh& rest, const TriMesh& deformed,
                    const std::vector<char>& corners, double R, double max_edge) {
  E.R = R;
  E.S = make_support_mesh(rest, deformed);
  refine_to_length(E.S, max_edge);
  E.adj = build_triangle_adjacency(E.S.deformed.F, E.S.deformed.num_vertices());
  E.corner_vertex.assign(E.S.deformed.num_vertices(), 0);
  for (std::size_t v = 0; v < corners.size(); ++v) E.corner_vertex[v] = corners[v];
  E.lo = E.S.deformed.V.colwise().minCoeff().transpose();
  E.hi = E.S.deformed.V.colwise().maxCoeff().transpose();
}

void place_seeds(Engine& E, double area, int cells, const TessellationOptions& o) {
  const double R = E.R;
  Rng rng(o.seed);
  const double spacing = o.boundary_spacing * kSqrt3 * R;
  seed_boundary(E, spacing, rng);
  const int nb = static_cast<int>(E.seeds.size());
  int n_int = cells > 0 ? cells - nb
                        : static_cast<int>(std::lround((area - nb * 0.5 * kHexArea * R * R) /
                                                       (kHexArea * R * R)));
  n_int = std::max(n_int, 1);
  seed_interior(E, n_int, 0.8 * kSqrt3 * R, rng);
}

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

void seed_interior(Engine& E, int count, double radius, Rng& rng) {
  const auto& M = E.S.deformed;
  const int nt = M.num_faces();
  std::vector<double> cum(nt + 1, 0.0);
  for (int t = 0; t < nt; ++t)
    cum[t + 1] =
        cum[t] + triangle_area(M.vertex(M.F(t, 0)), M.vertex(M.F(t, 1)), M.vertex(M.F(t, 2)));
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
}

}  // namespace gridshell::voronoi
