#include "gridshell/field/field.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <queue>

#include <fmt/format.h>
#include <Eigen/OrderingMethods>
#include <Eigen/Sparse>

#include "gridshell/core/enum_words.h"
#include "gridshell/core/error.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

namespace {

/// Adjacent face pairs through shared (manifold or not) edges, with the shared edge's vertices.
struct FaceAdjacency {
  struct Pair {
    int f, g, a, b;  // faces f < g, shared edge a → b
  };
  std::vector<Pair> pairs;
};

FaceAdjacency face_adjacency(const TriMesh& mesh) {
  const Topology topo = build_topology(mesh);
  FaceAdjacency adj;
  for (int e = 0; e < topo.num_edges(); ++e) {
    const auto& ef = topo.edge_faces[e];
    for (std::size_t i = 0; i < ef.size(); ++i)
      for (std::size_t j = i + 1; j < ef.size(); ++j)
        adj.pairs.push_back(
            {std::min(ef[i], ef[j]), std::max(ef[i], ef[j]), topo.edges[e][0], topo.edges[e][1]});
  }
  return adj;
}

Vec3 centroid(const TriMesh& mesh, int f) {
  return (mesh.vertex(mesh.F(f, 0)) + mesh.vertex(mesh.F(f, 1)) + mesh.vertex(mesh.F(f, 2))) / 3;
}

void check_finite(const std::vector<double>& v, const char* what) {
  for (double x : v)
    if (!std::isfinite(x)) throw Error("field", fmt::format("non-finite {} value", what));
}

/// Unit projection of `v` onto the plane of face f; falls back to t1 when v is (nearly) normal.
Vec3 tangent_unit(const FaceFrames& fr, int f, const Vec3& v) {
  Vec3 t = v - v.dot(fr.n[f]) * fr.n[f];
  const double len = t.norm();
  if (!(len > 1e-12 * std::max(1.0, v.norm()))) return fr.t1[f];
  return t / len;
}

}  // namespace

FaceFrames face_frames(const TriMesh& mesh) {
  const int nf = mesh.num_faces();
  FaceFrames fr;
  fr.t1.resize(nf);
  fr.t2.resize(nf);
  fr.n.resize(nf);
  fr.area.resize(nf);
  const double diag = bbox_diagonal(mesh.V);
  // Each face on its own (in parallel: 2 M faces on a fine input); the first degenerate one,
  // whatever the threads, is the one reported.
  std::vector<char> degenerate(nf, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, nf, 4096), [&](const tbb::blocked_range<int>& r) {
    for (int f = r.begin(); f < r.end(); ++f) {
      const Vec3 p0 = mesh.vertex(mesh.F(f, 0)), p1 = mesh.vertex(mesh.F(f, 1)),
                 p2 = mesh.vertex(mesh.F(f, 2));
      const Vec3 c = (p1 - p0).cross(p2 - p0);
      const double twice = c.norm();
      if (!(twice > 1e-14 * diag * diag)) {
        degenerate[f] = 1;
        continue;
      }
      fr.n[f] = c / twice;
      fr.t1[f] = (p1 - p0).normalized();
      fr.t2[f] = fr.n[f].cross(fr.t1[f]);
      fr.area[f] = 0.5 * twice;
    }
  });
  for (int f = 0; f < nf; ++f)
    if (degenerate[f])
      throw Error("mesh", fmt::format("degenerate triangle {} (zero area)", f));
  return fr;
}

std::vector<Vec3> smooth_line_field(const TriMesh& mesh, const std::vector<Vec3>& directions,
                                    const std::vector<double>& weights,
                                    const LineFieldOptions& options,
                                    std::vector<double>* coherence) {
  const int nf = mesh.num_faces();
  if (static_cast<int>(directions.size()) != nf || static_cast<int>(weights.size()) != nf)
    throw Error("field", "line field and weights must have one entry per face");
  check_finite(weights, "weight");
  const FaceFrames fr = face_frames(mesh);
  const double ell = options.smoothing > 0 ? options.smoothing : 0.05 * bbox_diagonal(mesh.V);
  if (!std::isfinite(ell) || !(ell > 0)) throw Error("field", "invalid smoothing length");

  // z0 = e^{2iθ} in the face frame; Hermitian system H z = b, solved as complex.
  using Cplx = std::complex<double>;
  std::vector<Vec3> dir(nf);
  Eigen::VectorXcd b = Eigen::VectorXcd::Zero(nf);
  std::vector<Eigen::Triplet<Cplx>> trip;
  trip.reserve(nf + 4 * 3 * static_cast<std::size_t>(nf) / 2 + 8);
  for (int f = 0; f < nf; ++f) {
    if (!directions[f].allFinite()) throw Error("field", "non-finite direction");
    if (weights[f] < 0) throw Error("field", "negative faithfulness weight");
    dir[f] = tangent_unit(fr, f, directions[f]);
    const double th = std::atan2(dir[f].dot(fr.t2[f]), dir[f].dot(fr.t1[f]));
    const double alpha = fr.area[f] * weights[f] / (ell * ell);
    b[f] = alpha * std::polar(1.0, 2 * th);
    trip.emplace_back(f, f, alpha);
  }
  // Dirichlet energy with transport: |z_f − r z_g|², r = e^{2i(φ_f − φ_g)}.
  const FaceAdjacency adj = face_adjacency(mesh);
  double wsum = 0;
  for (const auto& p : adj.pairs) {
    const Vec3 e = mesh.vertex(p.b) - mesh.vertex(p.a);
    const double len = e.norm();
    const double h = (centroid(mesh, p.f) - centroid(mesh, p.g)).norm();
    if (!(len > 0) || !(h > 0)) continue;
    const double w = len / h;
    wsum += w;
    const double phi_f = std::atan2(e.dot(fr.t2[p.f]), e.dot(fr.t1[p.f]));
    const double phi_g = std::atan2(e.dot(fr.t2[p.g]), e.dot(fr.t1[p.g]));
    const Cplx r = std::polar(1.0, 2 * (phi_f - phi_g));
    trip.emplace_back(p.f, p.f, w);
    trip.emplace_back(p.g, p.g, w);
    trip.emplace_back(p.f, p.g, -w * r);             // coefficient of conj(z_f) z_g
    trip.emplace_back(p.g, p.f, -w * std::conj(r));  // Hermitian mate
  }
  // A tiny Tikhonov term keeps the system definite when all weights vanish (z → 0 there and the
  // input direction is returned).
  const double reg = 1e-12 * (wsum > 0 ? wsum / nf : 1.0);
  for (int f = 0; f < nf; ++f) trip.emplace_back(f, f, reg);
  Eigen::SparseMatrix<Cplx> H(nf, nf);
  H.setFromTriplets(trip.begin(), trip.end());
  Eigen::SimplicialLLT<Eigen::SparseMatrix<Cplx>, Eigen::Lower, Eigen::AMDOrdering<int>> llt(H);
  if (llt.info() != Eigen::Success) throw Error("field", "line-field system is not definite");
  const Eigen::VectorXcd z = llt.solve(b);
  if (llt.info() != Eigen::Success || !z.allFinite())
    throw Error("field", "line-field solve failed");

  std::vector<Vec3> out(nf);
  if (coherence) coherence->resize(nf);
  for (int f = 0; f < nf; ++f) {
    const double x = z[f].real(), y = z[f].imag();
    if (coherence) (*coherence)[f] = std::min(1.0, std::hypot(x, y));
    if (std::hypot(x, y) < 1e-9) {
      out[f] = dir[f];
      continue;
    }
    const double th = 0.5 * std::atan2(y, x);
    out[f] = (std::cos(th) * fr.t1[f] + std::sin(th) * fr.t2[f]).normalized();
  }
  return out;
}

std::vector<double> saturate_lipschitz(const TriMesh& mesh, const std::vector<double>& values,
                                       double L, const SaturationStretch* stretch) {
  const int nf = mesh.num_faces();
  if (static_cast<int>(values.size()) != nf)
    throw Error("field", "saturation needs one value per face");
  check_finite(values, "field");
  std::vector<double> out = values;
  if (!(L > 0) || nf == 0) return out;
  if (!std::isfinite(L)) throw Error("field", "non-finite Lipschitz constant");
  // Face graph with centroid distances (CSR).
  const FaceAdjacency adj = face_adjacency(mesh);
  std::vector<Vec3> c(nf);
  for (int f = 0; f < nf; ++f) c[f] = centroid(mesh, f);
  std::vector<int> start(nf + 1, 0);
  for (const auto& p : adj.pairs) {
    ++start[p.f + 1];
    ++start[p.g + 1];
  }
  for (int f = 0; f < nf; ++f) start[f + 1] += start[f];
  std::vector<int> nb(start[nf]), fill(start.begin(), start.end() - 1);
  std::vector<double> dist(start[nf]);
  if (stretch &&
      (static_cast<int>(stretch->u.size()) != nf || static_cast<int>(stretch->a.size()) != nf))
    throw Error("field", "saturation stretch needs one direction and factor per face");
  auto length = [&](int f, const Vec3& e) {
    const double eu = e.dot(stretch->u[f]) / stretch->u[f].norm();
    return std::sqrt(eu * eu / (stretch->a[f] * stretch->a[f]) +
                     std::max(0.0, e.squaredNorm() - eu * eu));
  };
  for (const auto& p : adj.pairs) {
    const Vec3 e = c[p.g] - c[p.f];
    const double h = stretch ? 0.5 * (length(p.f, e) + length(p.g, e)) : e.norm();
    nb[fill[p.f]] = p.g;
    dist[fill[p.f]++] = h;
    nb[fill[p.g]] = p.f;
    dist[fill[p.g]++] = h;
  }
  // Max-first sweep: each face is settled at its final value before it relaxes its neighbours.
  using Item = std::pair<double, int>;
  std::priority_queue<Item> heap;
  for (int f = 0; f < nf; ++f) heap.emplace(out[f], f);
  std::vector<char> done(nf, 0);
  while (!heap.empty()) {
    const auto [v, f] = heap.top();
    heap.pop();
    if (done[f] || v < out[f]) continue;
    done[f] = 1;
    for (int k = start[f]; k < start[f + 1]; ++k) {
      const int g = nb[k];
      const double cand = v - L * dist[k];
      if (!done[g] && cand > out[g]) {
        out[g] = cand;
        heap.emplace(cand, g);
      }
    }
  }
  return out;
}

std::vector<double> rescale_robust(const std::vector<double>& values, double top,
                                   double low_percentile, double high_percentile) {
  if (!std::isfinite(top) || top < 1) throw Error("field", "rescaling target must be ≥ 1");
  if (!(low_percentile >= 0 && low_percentile <= high_percentile && high_percentile <= 1))
    throw Error("field", "percentiles must satisfy 0 ≤ low ≤ high ≤ 1");
  check_finite(values, "field");
  std::vector<double> out(values.size(), 1.0);
  if (values.empty()) return out;
  std::vector<double> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  const double n1 = static_cast<double>(sorted.size() - 1);
  const double lo = sorted[static_cast<std::size_t>(std::lround(low_percentile * n1))];
  const double hi = sorted[static_cast<std::size_t>(std::lround(high_percentile * n1))];
  const double scale = std::max({std::abs(lo), std::abs(hi), 1e-300});
  if (!(hi - lo > 1e-12 * scale)) return out;  // constant field → 1
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = values[i];
    if (v <= lo)
      out[i] = 1.0;
    else if (v >= hi)
      out[i] = top;
    else
      out[i] = std::clamp(1.0 + (top - 1.0) * (v - lo) / (hi - lo), 1.0, top);
  }
  return out;
}

namespace {
constexpr EnumWords<StressMeasure, 3> kMeasures{{{"magnitude", StressMeasure::magnitude},
                                                 {"tension", StressMeasure::tension},
                                                 {"compression", StressMeasure::compression}}};
constexpr EnumWords<StretchAxis, 2> kStretch{
    {{"along", StretchAxis::along}, {"across", StretchAxis::across}}};
constexpr EnumWords<DensityTrend, 2> kDensity{
    {{"rising", DensityTrend::rising}, {"falling", DensityTrend::falling}}};
}  // namespace

StressMeasure parse_stress_measure(const std::string& w) {
  return parse_word(w, "--stress-measure", kMeasures);
}
StretchAxis parse_stretch_axis(const std::string& w) { return parse_word(w, "--stretch", kStretch); }
DensityTrend parse_density_trend(const std::string& w) {
  return parse_word(w, "--density", kDensity);
}
const char* to_string(StressMeasure m) { return word_of(m, kMeasures); }
const char* to_string(StretchAxis s) { return word_of(s, kStretch); }
const char* to_string(DensityTrend d) { return word_of(d, kDensity); }

Field uniform_field(const TriMesh& mesh) {
  const FaceFrames fr = face_frames(mesh);
  Field fd;
  fd.u = fr.t1;
  fd.u_raw = fr.t1;
  const auto nf = static_cast<std::size_t>(mesh.num_faces());
  fd.d.assign(nf, 1.0);
  fd.a.assign(nf, 1.0);
  fd.d_raw.assign(nf, 1.0);
  fd.a_raw.assign(nf, 1.0);
  fd.coherence.assign(nf, 1.0);
  return fd;
}

Field make_field(const TriMesh& mesh, const StressField& stress, const FieldOptions& o) {
  const int nf = mesh.num_faces();
  if (static_cast<int>(stress.size()) != nf)
    throw Error("field",
                fmt::format("stress field has {} entries for {} faces", stress.size(), nf));
  if (!std::isfinite(o.D) || o.D < 1) throw Error("-D", "density ratio D must be ≥ 1");
  if (!std::isfinite(o.A) || o.A < 1) throw Error("-A", "anisotropy ratio A must be ≥ 1");
  if (!std::isfinite(o.anisotropy_cap) || o.anisotropy_cap <= 1)
    throw Error("field", "anisotropy cap must be > 1");
  const FaceFrames fr = face_frames(mesh);
  Field fd;
  fd.u_raw.resize(nf);
  fd.d_raw.resize(nf);
  fd.a_raw.resize(nf);
  for (int f = 0; f < nf; ++f) {
    const PrincipalStress& p = stress[f];
    if (!std::isfinite(p.s1) || !std::isfinite(p.s2) || !p.d1.allFinite() || !p.d2.allFinite())
      throw Error("field", fmt::format("non-finite stress at face {}", f));
    // The two measured stresses and the driving direction (the first one's).
    double m1 = 0, m2 = 0;
    Vec3 dir = p.d1;
    switch (o.measure) {
      case StressMeasure::magnitude:
        m1 = std::abs(p.s1), m2 = std::abs(p.s2);
        if (m2 > m1) std::swap(m1, m2), dir = p.d2;
        break;
      case StressMeasure::tension:
        m1 = std::max(p.s1, 0.0), m2 = std::max(p.s2, 0.0);
        break;
      case StressMeasure::compression:
        m1 = std::max(-p.s2, 0.0), m2 = std::max(-p.s1, 0.0), dir = p.d2;
        break;
    }
    const double mx = m1, mn = m2;
    fd.u_raw[f] = tangent_unit(fr, f, dir);
    if (o.stretch == StretchAxis::across) fd.u_raw[f] = fr.n[f].cross(fd.u_raw[f]);
    fd.d_raw[f] = mx;
    fd.a_raw[f] = mn > 0 ? std::min(mx / mn, o.anisotropy_cap) : (mx > 0 ? o.anisotropy_cap : 1);
  }
  // Faithfulness: directional information of the tensor, 0 for an isotropic one.
  std::vector<double> w(nf);
  for (int f = 0; f < nf; ++f) w[f] = 1.0 - 1.0 / fd.a_raw[f] + 1e-3;
  fd.u = smooth_line_field(mesh, fd.u_raw, w, LineFieldOptions{o.smoothing}, &fd.coherence);

  const double diag = bbox_diagonal(mesh.V);
  if (!std::isfinite(o.coherence_exponent) || o.coherence_exponent < 0)
    throw Error("field", "coherence exponent must be ≥ 0");
  // `blend` (may be null): per-face factor in [0, 1] applied to the excess over the low level
  // after saturation.
  auto process = [&](const std::vector<double>& raw, double top, const std::vector<double>* blend,
                     const SaturationStretch* stretch) {
    // Clamp first (so isolated spikes do not flood the saturation), then saturate, then map
    // min..max linearly onto [1, top] (exact ends).
    std::vector<double> sorted = raw;
    std::sort(sorted.begin(), sorted.end());
    const double n1 = static_cast<double>(sorted.size() - 1);
    const double lo = sorted[static_cast<std::size_t>(std::lround(o.low_percentile * n1))];
    const double hi = sorted[static_cast<std::size_t>(std::lround(o.high_percentile * n1))];
    std::vector<double> v(raw.size());
    for (std::size_t i = 0; i < raw.size(); ++i) v[i] = std::clamp(raw[i], lo, hi);
    if (o.lipschitz > 0 && hi > lo)
      v = saturate_lipschitz(mesh, v, o.lipschitz * (hi - lo) / diag, stretch);
    if (blend)
      for (std::size_t i = 0; i < v.size(); ++i) v[i] = lo + (v[i] - lo) * (*blend)[i];
    return rescale_robust(v, top, 0.0, 1.0);
  };
  if (!(o.low_percentile >= 0 && o.low_percentile <= o.high_percentile && o.high_percentile <= 1))
    throw Error("field", "percentiles must satisfy 0 ≤ low ≤ high ≤ 1");
  if (nf == 0) return fd;
  std::vector<double> blend;
  if (o.coherence_exponent > 0) {
    blend.resize(nf);
    for (int f = 0; f < nf; ++f) blend[f] = std::pow(fd.coherence[f], o.coherence_exponent);
  }
  fd.a = process(fd.a_raw, o.A, blend.empty() ? nullptr : &blend, nullptr);
  const SaturationStretch stretch{fd.u, fd.a};
  if (o.density == DensityTrend::rising) {
    fd.d = process(fd.d_raw, o.D, nullptr, &stretch);
  } else {  // small cells where the stress is low: the same processing of −d_raw
    std::vector<double> negated(fd.d_raw.size());
    for (std::size_t i = 0; i < negated.size(); ++i) negated[i] = -fd.d_raw[i];
    fd.d = process(negated, o.D, nullptr, &stretch);
  }
  return fd;
}

io::Attributes field_attributes(const Field& field) {
  io::Attributes at;
  const auto n = static_cast<Eigen::Index>(field.u.size());
  auto vec = [&](const std::vector<Vec3>& v) {
    Eigen::MatrixXd m(n, 3);
    for (Eigen::Index i = 0; i < n && i < static_cast<Eigen::Index>(v.size()); ++i)
      m.row(i) = v[i].transpose();
    return m;
  };
  auto sca = [&](const std::vector<double>& v) {
    Eigen::MatrixXd m = Eigen::MatrixXd::Ones(n, 1);
    for (Eigen::Index i = 0; i < n && i < static_cast<Eigen::Index>(v.size()); ++i) m(i, 0) = v[i];
    return m;
  };
  at["u"] = vec(field.u);
  at["u_raw"] = vec(field.u_raw.empty() ? field.u : field.u_raw);
  at["d"] = sca(field.d);
  at["a"] = sca(field.a);
  at["d_raw"] = sca(field.d_raw);
  at["a_raw"] = sca(field.a_raw);
  at["coherence"] = sca(field.coherence);
  return at;
}

bool identical(const Field& a, const Field& b) {
  return a.u == b.u && a.d == b.d && a.a == b.a && a.u_raw == b.u_raw && a.d_raw == b.d_raw &&
         a.a_raw == b.a_raw && a.coherence == b.coherence;
}

}  // namespace gridshell
