#include "gridshell/optimize/buildability.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <unordered_map>

#include <fmt/format.h>
#include <Eigen/SVD>

#include "gridshell/core/error.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/metrics.h"

namespace gridshell {

namespace {

using Star = std::vector<Vec3>;

/// The squared RMS distance between a[i] and R·b[pair[i]] for the best proper rotation R
/// (Kabsch): with H = Σ b_p a_iᵀ = U S Vᵀ, the largest tr(R H) over rotations is
/// s₁ + s₂ + sign(det U · det V)·s₃, and Σ|a_i − R b_p|² = Σ|a_i|² + Σ|b_p|² − 2 tr(R H).
double kabsch_rms2(const Star& a, const Star& b, const std::vector<int>& pair) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  double sq = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec3& q = b[pair[i]];
    H += q * a[i].transpose();
    sq += a[i].squaredNorm() + q.squaredNorm();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  // A copy: a reference makes GCC 12 warn (maybe-uninitialized) through Eigen's storage.
  const Vec3 s = svd.singularValues();  // NOLINT(performance-unnecessary-copy-initialization)
  const double d = svd.matrixU().determinant() * svd.matrixV().determinant() < 0 ? -1.0 : 1.0;
  const double r2 = (sq - 2 * (s(0) + s(1) + d * s(2))) / static_cast<double>(a.size());
  return std::max(0.0, r2);
}

/// Whether some pairing of the beams of a and b (same valence k) has an RMS distance of at most
/// `limit` after the best rotation. Depth-first over pairings, i ↦ pair[i]; a partial pairing
/// survives only while every paired dot product agrees within `bound` (for a pairing within
/// `limit`, |a_i·a_j − b_p·b_q| ≤ e_i + e_j ≤ √(2k)·limit, e_i the paired vectors' distance).
/// Iterative (no recursion); stops after `max_nodes` tried extensions (`capped`).
bool within(const Star& a, const Star& b, double limit, double bound, long max_nodes,
            bool& capped) {
  const int k = static_cast<int>(a.size());
  if (k == 0) return true;
  std::vector<int> pair(k, -1);
  std::vector<char> used(k, 0);
  const double limit2 = limit * limit;
  long nodes = 0;
  int i = 0;
  while (i >= 0) {
    if (pair[i] >= 0) used[pair[i]] = 0;
    int j = pair[i] + 1;
    for (; j < k; ++j) {
      if (used[j]) continue;
      nodes += i + 1;  // the dot products this extension checks
      if (nodes > max_nodes) {
        capped = true;
        return false;
      }
      bool ok = true;
      for (int p = 0; p < i && ok; ++p)
        ok = std::abs(a[p].dot(a[i]) - b[pair[p]].dot(b[j])) <= bound;
      if (ok) break;
    }
    if (j == k) {  // no candidate left here: back up
      pair[i] = -1;
      --i;
      continue;
    }
    pair[i] = j;
    used[j] = 1;
    if (i + 1 == k) {
      if (kabsch_rms2(a, b, pair) <= limit2) return true;
    } else {
      pair[++i] = -1;
    }
  }
  return false;
}

/// The hash cell of a star: its valence and up to three coordinates, each on a grid of step h.
struct Cell {
  int valence = 0;
  int dims = 0;
  std::array<std::int64_t, 3> c{0, 0, 0};
  bool operator==(const Cell& o) const { return valence == o.valence && c == o.c; }
};

struct CellHash {
  std::size_t operator()(const Cell& x) const {
    std::uint64_t h = static_cast<std::uint64_t>(x.valence) * 0x9E3779B97F4A7C15ull;
    for (std::int64_t v : x.c)
      h = (h ^ static_cast<std::uint64_t>(v)) * 0x100000001B3ull + 0x7F4A7C15u;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

/// The bound on how far a descriptor entry moves between stars within δ: √(2k)·δ, with a
/// little slack for rounding.
double dot_bound(int k, double delta) {
  return std::sqrt(2.0 * k) * delta * (1 + 1e-9) + 1e-12;
}

/// Above this valence a star is described by its mean dot product alone (O(k) instead of
/// O(k²) work and memory).
constexpr int kFullDescriptorValence = 64;

/// A star's descriptor: its pairwise dot products u_i·u_j (i < j) sorted ascending, or for a
/// valence above kFullDescriptorValence their mean, (|Σu|² − Σ|u|²) / (k(k − 1)). Between two
/// stars within δ each entry moves by at most √(2k)·δ (sorting keeps that bound).
std::vector<double> star_descriptor(const Star& s) {
  const int k = static_cast<int>(s.size());
  std::vector<double> d;
  if (k < 2) return d;
  if (k > kFullDescriptorValence) {
    Vec3 sum = Vec3::Zero();
    double sq = 0;
    for (const Vec3& u : s) sum += u, sq += u.squaredNorm();
    d.push_back((sum.squaredNorm() - sq) / (k * (k - 1.0)));
    return d;
  }
  d.reserve(k * (k - 1) / 2);
  for (int i = 0; i < k; ++i)
    for (int j = i + 1; j < k; ++j) d.push_back(s[i].dot(s[j]));
  std::sort(d.begin(), d.end());
  return d;
}

/// The cell of a star: its valence and the three largest entries of its descriptor (fewer
/// when it has fewer) on a grid of step h. The largest dot products vary the most between
/// stars of a grid-shell (those near −1, beams running straight on, vary only to second order).
Cell star_cell(int valence, const std::vector<double>& d, double h) {
  Cell cell;
  cell.valence = valence;
  cell.dims = std::min<int>(3, static_cast<int>(d.size()));
  for (int i = 0; i < cell.dims; ++i)
    cell.c[i] = static_cast<std::int64_t>(std::floor(d[d.size() - 1 - i] / h));
  return cell;
}

/// Whether two descriptors (same valence) are within h entry by entry.
bool descriptors_near(const std::vector<double>& a, const std::vector<double>& b, double h) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::abs(a[i] - b[i]) > h) return false;
  return true;
}

void check_options(const BuildabilityOptions& o) {
  if (!(o.joint_tolerance >= 1e-6 && o.joint_tolerance <= 1))
    throw Error("buildability",
                fmt::format("joint tolerance {} is outside [1e-6, 1]", o.joint_tolerance));
  if (!(o.min_beam_length >= 0) || !std::isfinite(o.min_beam_length))
    throw Error("buildability", "the shortest beam length counted must be a number ≥ 0");
  if (o.max_search_nodes < 1 || o.max_candidates < 1)
    throw Error("buildability", "max_search_nodes and max_candidates must be ≥ 1");
}

}  // namespace

double joint_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  if (a.empty()) return 0;
  if (a.size() > 9) throw Error("buildability", "joint_distance compares at most 9 beams");
  std::vector<int> pair(a.size());
  std::iota(pair.begin(), pair.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do {
    best = std::min(best, kabsch_rms2(a, b, pair));
  } while (std::next_permutation(pair.begin(), pair.end()));
  return std::sqrt(best);
}

JointClusters cluster_joints(const std::vector<std::vector<Vec3>>& stars,
                             const BuildabilityOptions& options) {
  check_options(options);
  const double delta = options.joint_tolerance;
  JointClusters r;
  r.cluster.assign(stars.size(), -1);
  std::unordered_map<Cell, std::vector<int>, CellHash> centres;  // star ids of the centres
  std::vector<std::vector<double>> descriptor(stars.size());
  std::map<int, ValenceClusters> per;
  for (std::size_t s = 0; s < stars.size(); ++s) {
    const Star& star = stars[s];
    const int k = static_cast<int>(star.size());
    const double h = dot_bound(k, delta);
    descriptor[s] = star_descriptor(star);
    const Cell cell = star_cell(k, descriptor[s], h);
    ValenceClusters& v = per[k];
    v.valence = k;
    ++v.joints;
    // Every centre within δ lies in one of the 3^dims cells around this one.
    const int n = cell.dims == 0 ? 1 : cell.dims == 1 ? 3 : cell.dims == 2 ? 9 : 27;
    bool capped = false;
    int compared = 0;
    for (int o = 0; o < n && r.cluster[s] < 0 && compared <= options.max_candidates; ++o) {
      Cell q = cell;
      for (int d = 0, code = o; d < cell.dims; ++d, code /= 3) q.c[d] += code % 3 - 1;
      const auto it = centres.find(q);
      if (it == centres.end()) continue;
      for (int c : it->second) {
        if (!descriptors_near(descriptor[s], descriptor[c], h)) continue;
        if (++compared > options.max_candidates) {
          capped = true;  // the star becomes a centre without further comparisons
          break;
        }
        if (within(star, stars[c], delta, h, options.max_search_nodes, capped)) {
          r.cluster[s] = r.cluster[c];
          break;
        }
      }
    }
    if (capped) ++r.capped_comparisons;
    if (r.cluster[s] < 0) {
      r.cluster[s] = r.clusters++;
      ++v.clusters;
      centres[cell].push_back(static_cast<int>(s));
    } else {
      descriptor[s] = {};  // only centres' descriptors are read again
    }
  }
  for (const auto& [k, v] : per) r.by_valence.push_back(v);
  return r;
}

Buildability buildability(const PolyMesh& mesh, const std::vector<std::string>& member_sections,
                          const BuildabilityOptions& options) {
  check_options(options);
  const int nv = mesh.num_vertices();
  if (!mesh.V.allFinite()) throw Error("buildability", "a joint has a non-finite coordinate");
  for (const auto& f : mesh.faces)
    for (int v : f)
      if (v < 0 || v >= nv)
        throw Error("buildability", fmt::format("face index {} out of range (0…{})", v, nv - 1));
  Buildability b;
  // Face planarity: triangles (and smaller) count as 0, as in the benchmark.
  double sum = 0;
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (mesh.faces[f].size() >= 4) sum += polygon_planarity(face_points(mesh, f));
  if (mesh.num_faces() > 0) b.face_planarity = 1 + sum / mesh.num_faces();

  const Topology topo = build_topology(mesh);
  b.beams = topo.num_edges();
  // Beam lengths: mean and sample standard deviation of those longer than min_beam_length.
  std::vector<double> lengths;
  for (const auto& [i, j] : topo.edges) {
    const double l = (mesh.vertex(i) - mesh.vertex(j)).norm();
    if (l > options.min_beam_length)
      lengths.push_back(l);
    else
      ++b.short_beams;
  }
  if (lengths.size() >= 2) {
    const double n = static_cast<double>(lengths.size());
    const double mean = std::accumulate(lengths.begin(), lengths.end(), 0.0) / n;
    double ss = 0;
    for (double l : lengths) ss += (l - mean) * (l - mean);
    b.beam_length_similarity = 1 + std::sqrt(ss / (n - 1)) / mean;
  }

  // Joints and their stars (unit vectors along the beams; a beam of zero length has none).
  std::vector<Star> stars;
  std::vector<int> joint_of;
  for (int v = 0; v < nv; ++v) {
    if (topo.vertex_neighbors[v].empty()) continue;
    Star s;
    for (int w : topo.vertex_neighbors[v]) {
      const Vec3 e = mesh.vertex(w) - mesh.vertex(v);
      const double l = e.norm();
      if (l > 0) s.push_back(e / l);
    }
    stars.push_back(std::move(s));
    joint_of.push_back(v);
  }
  b.joints = static_cast<int>(stars.size());
  JointClusters c = cluster_joints(stars, options);
  b.joint_clusters = c.clusters;
  b.by_valence = std::move(c.by_valence);
  b.capped_comparisons = c.capped_comparisons;
  b.joint_cluster.assign(nv, -1);
  for (std::size_t s = 0; s < stars.size(); ++s) b.joint_cluster[joint_of[s]] = c.cluster[s];

  if (!member_sections.empty()) {
    if (static_cast<int>(member_sections.size()) != b.beams)
      throw Error("buildability",
                  fmt::format("{} member sections for {} beams", member_sections.size(), b.beams));
    std::vector<std::string> names = member_sections;
    std::sort(names.begin(), names.end());
    b.distinct_sections = static_cast<int>(std::unique(names.begin(), names.end()) - names.begin());
  }
  return b;
}

}  // namespace gridshell
