#include "gridshell/grids/quad_aniso_internal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Sparse>

#include "gridshell/core/error.h"

namespace gridshell::quad_aniso_internal {

namespace {

/// Per vertex of a triangle mesh (M′ or M): unit normal, area-weighted over its triangles.
std::vector<Vec3> vertex_normals(const TriMesh& m) {
  std::vector<Vec3> n(m.num_vertices(), Vec3::Zero());
  for (int f = 0; f < m.num_faces(); ++f) {
    const Vec3 a = m.vertex(m.F(f, 0)), b = m.vertex(m.F(f, 1)), c = m.vertex(m.F(f, 2));
    const Vec3 fn = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) n[m.F(f, k)] += fn;
  }
  for (Vec3& v : n) v = v.norm() > 0 ? Vec3(v.normalized()) : Vec3(Vec3::UnitZ());
  return n;
}

/// J_t u_t: the field direction of each face of `rest` carried onto `deformed` (unit), and the
/// area of the face in M′.
void pushed_directions(const TriMesh& rest, const TriMesh& def, const Field& field,
                       std::vector<Vec3>& w, std::vector<double>& area) {
  w.assign(rest.num_faces(), Vec3::Zero());
  area.assign(rest.num_faces(), 0);
  for (int f = 0; f < rest.num_faces(); ++f) {
    const Vec3 a = rest.vertex(rest.F(f, 0));
    const Vec3 e1 = rest.vertex(rest.F(f, 1)) - a, e2 = rest.vertex(rest.F(f, 2)) - a;
    const Vec3 a2 = def.vertex(def.F(f, 0));
    const Vec3 d1 = def.vertex(def.F(f, 1)) - a2, d2 = def.vertex(def.F(f, 2)) - a2;
    Eigen::Matrix2d G;
    G << e1.dot(e1), e1.dot(e2), e1.dot(e2), e2.dot(e2);
    const Eigen::Vector2d ab =
        G.ldlt().solve(Eigen::Vector2d(e1.dot(field.u[f]), e2.dot(field.u[f])));
    const Vec3 j = ab(0) * d1 + ab(1) * d2;
    area[f] = 0.5 * d1.cross(d2).norm();
    if (j.norm() > 0 && std::isfinite(j.norm())) w[f] = j.normalized();
  }
}

/// Levels from M′ down to ≤ `coarsest` vertices (or until pairing stops shrinking the level):
/// neighbours are paired greedily, most similar first (normals alike, areas alike); a vertex left
/// without a partner goes up alone. Deterministic (ties broken by vertex ids).
std::vector<Level> build_hierarchy(const TriMesh& def, const Topology& topo, int coarsest) {
  std::vector<Level> levels(1);
  {
    Level& l = levels[0];
    const int nv = def.num_vertices();
    l.p.resize(nv);
    for (int v = 0; v < nv; ++v) l.p[v] = def.vertex(v);
    l.n = vertex_normals(def);
    l.area.assign(nv, 0);
    for (int f = 0; f < def.num_faces(); ++f) {
      const double a =
          triangle_area(def.vertex(def.F(f, 0)), def.vertex(def.F(f, 1)), def.vertex(def.F(f, 2)));
      for (int k = 0; k < 3; ++k) l.area[def.F(f, k)] += a / 3;
    }
    for (double& a : l.area) a = std::max(a, 1e-300);
    l.nbr = topo.vertex_neighbors;
  }
  while (coarsest > 0 && levels.back().size() > coarsest && levels.size() < 40) {
    const Level& f = levels.back();
    const int nv = f.size();
    std::vector<std::tuple<double, int, int>> pairs;
    for (int i = 0; i < nv; ++i)
      for (int j : f.nbr[i])
        if (i < j)
          pairs.emplace_back(
              -f.n[i].dot(f.n[j]) * std::min(f.area[i] / f.area[j], f.area[j] / f.area[i]), i, j);
    std::sort(pairs.begin(), pairs.end());
    std::vector<int> parent(nv, -1);
    int count = 0;
    for (const auto& [score, i, j] : pairs)
      if (parent[i] < 0 && parent[j] < 0) parent[i] = parent[j] = count++;
    for (int v = 0; v < nv; ++v)
      if (parent[v] < 0) parent[v] = count++;
    if (count > 0.95 * nv) break;  // nothing left to pair (e.g. isolated vertices)
    Level c;
    c.p.assign(count, Vec3::Zero());
    c.n.assign(count, Vec3::Zero());
    c.area.assign(count, 0);
    c.nbr.resize(count);
    std::vector<std::set<int>> nbr(count);
    for (int v = 0; v < nv; ++v) {
      const int P = parent[v];
      c.p[P] += f.area[v] * f.p[v];
      c.n[P] += f.area[v] * f.n[v];
      c.area[P] += f.area[v];
      for (int j : f.nbr[v])
        if (parent[j] != P) nbr[P].insert(parent[j]);
    }
    for (int P = 0; P < count; ++P) {
      c.p[P] /= c.area[P];
      c.n[P] = c.n[P].norm() > 0 ? Vec3(c.n[P].normalized()) : Vec3(Vec3::UnitZ());
      c.nbr[P].assign(nbr[P].begin(), nbr[P].end());
    }
    levels.back().parent = std::move(parent);
    levels.push_back(std::move(c));
  }
  return levels;
}

/// Gauss–Seidel sweeps of the cross field on one level, with the data term q_data weighted by
/// λ × the vertex's neighbour count.
void smooth_cross(const Level& l, const std::vector<Vec3>& q_data,
                  const std::vector<double>& lambda, std::vector<Vec3>& q, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    for (int v = 0; v < l.size(); ++v) {
      const auto& nb = l.nbr[v];
      Vec3 sum = lambda[v] * static_cast<double>(nb.size()) * match_cross(q_data[v], l.n[v], q[v]);
      for (int j : nb) sum += match_cross(q[j], l.n[j], q[v]);
      sum -= l.n[v] * l.n[v].dot(sum);
      if (sum.norm() > 1e-12) q[v] = sum.normalized();
    }
  }
}

/// `x` in the tangent plane of normal n, unit; any perpendicular of n when x is along n.
Vec3 tangent_unit(const Vec3& x, const Vec3& n) {
  const Vec3 y = x - n * n.dot(x);
  return y.norm() > 1e-12 ? Vec3(y.normalized()) : any_perpendicular(n);
}

/// Per face, how much the field's direction counts in the cross field's data (0 … 1): where the
/// metric is isotropic (a = 1) any cross gives square cells, so u there is no constraint; the
/// weight grows linearly with a − 1 up to 1 at a = min(a_full, the field's largest a). A field
/// without anisotropy (A = 1) keeps weight 1 everywhere: its directions are then the only ones
/// there are (the isotropic, stress-aligned baseline). a_full ≤ 1: weight 1 everywhere.
std::vector<double> direction_strength(const Field& field, double a_full) {
  const int nf = static_cast<int>(field.a.size());
  const double a_max = nf > 0 ? *std::max_element(field.a.begin(), field.a.end()) : 1;
  const double a_top = std::min(a_full, a_max);
  std::vector<double> strength(nf, 1.0);
  if (a_full <= 1 || a_top <= 1 + 1e-9) return strength;
  for (int f = 0; f < nf; ++f) strength[f] = std::clamp((field.a[f] - 1) / (a_top - 1), 0.0, 1.0);
  return strength;
}

/// Step 1: the 4-fold average of J u per vertex of M′ (each triangle weighted by its area and
/// direction_strength: the data), carried down the hierarchy
/// (area × coherence weighted), solved on the coarsest level and refined level by level with the
/// data term on each: where the stress field has a clear direction the data holds, where it
/// cancels (a singularity of the stress directions) the coarse levels fill in a smooth cross.
/// Returns the cross field of every level.
std::vector<CrossField> cross_field(const TriMesh& rest, const TriMesh& def, const Field& field,
                                    const Topology& topo, const std::vector<Level>& levels,
                                    double h, const QuadAnisoOptions& o) {
  const int nv = def.num_vertices();
  const std::vector<Vec3>& n = levels[0].n;
  std::vector<Vec3> w;
  std::vector<double> warea;
  pushed_directions(rest, def, field, w, warea);
  const int nl = static_cast<int>(levels.size());
  std::vector<std::vector<Vec3>> q_data(nl);
  std::vector<std::vector<double>> lambda(nl);
  q_data[0].resize(nv);
  lambda[0].assign(nv, 0);
  const std::vector<double> strength = direction_strength(field, o.full_alignment_anisotropy);
  for (int v = 0; v < nv; ++v) {
    const Vec3 r = any_perpendicular(n[v]), s = n[v].cross(r);
    std::complex<double> z = 0;
    double total = 0;
    for (int f : topo.vertex_faces[v]) {
      const double theta = std::atan2(w[f].dot(s), w[f].dot(r));
      z += strength[f] * warea[f] * std::polar(1.0, 4 * theta);
      total += warea[f];
    }
    const double phi = std::abs(z) > 0 ? std::arg(z) / 4 : 0;
    q_data[0][v] = std::cos(phi) * r + std::sin(phi) * s;
    // Data weight per neighbour for a smoothing length ℓ = direction_smoothing × h: on a mesh of
    // edge e the balance of the two terms is ℓ ≈ e / (2 √weight), so weight = (e / 2ℓ)².
    double edge = 0;
    for (int j : levels[0].nbr[v]) edge += (levels[0].p[j] - levels[0].p[v]).norm();
    edge /= std::max<size_t>(1, levels[0].nbr[v].size());
    const double per_neighbour = std::pow(edge / (2 * o.direction_smoothing * h), 2);
    lambda[0][v] = total > 0 ? per_neighbour * std::abs(z) / total : 0;
  }
  for (int k = 0; k + 1 < nl; ++k) {  // restriction: weighted sums of the crosses matched
    const Level &f = levels[k], &c = levels[k + 1];
    std::vector<Vec3> sum(c.size(), Vec3::Zero()), ref(c.size(), Vec3::Zero());
    std::vector<double> weight(c.size(), 0);
    for (int v = 0; v < f.size(); ++v) {
      const int P = f.parent[v];
      const double wv = f.area[v] * lambda[k][v];
      if (ref[P].squaredNorm() == 0) ref[P] = q_data[k][v];
      sum[P] += wv * match_cross(q_data[k][v], f.n[v], ref[P]);
      weight[P] += f.area[v];
    }
    q_data[k + 1].resize(c.size());
    lambda[k + 1].resize(c.size());
    for (int P = 0; P < c.size(); ++P) {
      q_data[k + 1][P] = tangent_unit(sum[P], c.n[P]);
      lambda[k + 1][P] = sum[P].norm() / weight[P];
    }
  }
  std::vector<CrossField> cf(nl);
  for (int k = nl - 1; k >= 0; --k) {
    const Level& l = levels[k];
    std::vector<Vec3> q(l.size());
    if (k == nl - 1)
      q = q_data[k];
    else
      for (int v = 0; v < l.size(); ++v) q[v] = tangent_unit(cf[k + 1].q[l.parent[v]], l.n[v]);
    smooth_cross(l, q_data[k], lambda[k], q, o.orientation_iterations);
    cf[k].n = l.n;
    cf[k].t.resize(l.size());
    for (int v = 0; v < l.size(); ++v) cf[k].t[v] = l.n[v].cross(q[v]);
    cf[k].q = std::move(q);
  }
  return cf;
}

/// The matched neighbour frames of level `l` (MatchedFrames).
MatchedFrames matched_frames(const Level& l, const CrossField& cf) {
  MatchedFrames m;
  m.offset.assign(l.size() + 1, 0);
  for (int i = 0; i < l.size(); ++i)
    m.offset[i + 1] = m.offset[i] + static_cast<int>(l.nbr[i].size());
  m.q.resize(m.offset.back());
  m.t.resize(m.offset.back());
  for (int i = 0; i < l.size(); ++i)
    for (size_t k = 0; k < l.nbr[i].size(); ++k) {
      const int j = l.nbr[i][k];
      const Vec3 qj = match_cross(cf.q[j], cf.n[j], cf.q[i]);
      m.q[m.offset[i] + k] = qj;
      m.t[m.offset[i] + k] = cf.n[j].cross(qj);
    }
  return m;
}

/// The lattice spacing's factor e^s per vertex of M′ (and of each coarser level) that lets the
/// lattice follow the cross field with fewer rows of cells starting. A cross field that turns
/// (∇θ, on M′ with its curvature) is the frame of a grid without such defects only if the
/// spacing varies with ∇s = −J ∇θ — a conformal grid: lines along hoops and meridians need
/// cells ∝ r. At a constant spacing every turn is paid in dislocations. s is the least-squares
/// solution of ∇s = −J ∇θ (P1 gradients, cotangent Laplacian; triangles where the cross's
/// matchings do not close — its singularities — are left out). Part of it is the field's own
/// grading: M′ is M scaled by about d / √a, and a lattice that is regular on M (a constant u on
/// a plane, any d) has spacing ∝ d / √a on M′; that part, log(d / √a), is subtracted, so the
/// cells keep the sizes d asks for and only the directions' turning and M's own curvature are
/// absorbed. The rest is shifted to area-weighted mean 0,
/// multiplied by `integrable_scale`, and clamped to ± log `max_scale_change`; coarser levels
/// take the area-weighted mean of log scale over their children.
std::vector<std::vector<double>> integrable_scale(const TriMesh& def, const Field& field,
                                                  const std::vector<Level>& levels,
                                                  const CrossField& cf, const QuadAnisoOptions& o) {
  const int nv = def.num_vertices(), nf = def.num_faces();
  std::vector<std::vector<double>> scale(levels.size());
  for (size_t k = 0; k < levels.size(); ++k) scale[k].assign(levels[k].size(), 1.0);
  if (o.integrable_scale == 0 || o.max_scale_change == 1) return scale;
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nv), mass = Eigen::VectorXd::Zero(nv),
                  asked = Eigen::VectorXd::Zero(nv);
  for (int f = 0; f < nf; ++f) {
    const int id[3] = {def.F(f, 0), def.F(f, 1), def.F(f, 2)};
    const Vec3 p[3] = {def.vertex(id[0]), def.vertex(id[1]), def.vertex(id[2])};
    Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
    const double area2 = n.norm();
    if (!(area2 > 0)) continue;
    n /= area2;
    const double area = 0.5 * area2;
    // ∇ of the hat functions: n × (opposite edge) / (2 area).
    Vec3 grad[3];
    for (int c = 0; c < 3; ++c) grad[c] = n.cross(p[(c + 2) % 3] - p[(c + 1) % 3]) / area2;
    // M′ is M scaled by d/a along u and d across: its conformal part, log(d / √a), is grading the
    // field asks for, not turning to absorb.
    const double graded = std::log(field.d[f] / std::sqrt(field.a[f]));
    for (int a = 0; a < 3; ++a) {
      mass[id[a]] += area / 3;
      asked[id[a]] += area / 3 * graded;
      for (int b = 0; b < 3; ++b) trip.emplace_back(id[a], id[b], area * grad[a].dot(grad[b]));
    }
    // The cross's angle at the three corners, matched to corner 0's and measured in the
    // triangle's plane; a singular triangle (the matchings around it do not close) is skipped.
    const Vec3 r = tangent_unit(cf.q[id[0]], n), rs = n.cross(r);
    double theta[3] = {0, 0, 0};
    Vec3 prev = cf.q[id[0]];
    for (int c = 1; c < 3; ++c) {
      prev = match_cross(cf.q[id[c]], cf.n[id[c]], prev);
      const Vec3 qc = tangent_unit(prev, n);
      theta[c] = std::atan2(qc.dot(rs), qc.dot(r));
    }
    const Vec3 back = match_cross(cf.q[id[0]], cf.n[id[0]], prev);
    if (back.dot(cf.q[id[0]]) < 0.5) continue;
    Vec3 grad_theta = Vec3::Zero();
    for (int c = 0; c < 3; ++c) grad_theta += theta[c] * grad[c];
    const Vec3 g = -n.cross(grad_theta);  // −J ∇θ
    for (int a = 0; a < 3; ++a) rhs[id[a]] += area * g.dot(grad[a]);
  }
  Eigen::SparseMatrix<double> L(nv, nv);
  L.setFromTriplets(trip.begin(), trip.end());
  double total = mass.sum(), diag = 0;
  for (int v = 0; v < nv; ++v) diag += L.coeff(v, v);
  // A weak pull to 0 fixes the free constant (the solve is otherwise singular).
  const double eps = 1e-8 * diag / std::max(1.0, total);
  for (int v = 0; v < nv; ++v) L.coeffRef(v, v) += eps * mass[v];
  // One small 2D Laplacian per M′: Eigen's simplicial factorisation, without CHOLMOD's
  // supernodal BLAS blocks and symbolic-analysis lock (core/cholmod_support.h), which pay off on
  // the frame and shell systems, not here.
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(L);
  if (solver.info() != Eigen::Success) return scale;
  Eigen::VectorXd sv = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !sv.allFinite()) return scale;
  for (int v = 0; v < nv; ++v) sv[v] -= mass[v] > 0 ? asked[v] / mass[v] : 0;
  const double mean = sv.dot(mass) / total, cap = std::log(o.max_scale_change);
  for (int v = 0; v < nv; ++v)
    scale[0][v] = std::exp(std::clamp(o.integrable_scale * (sv[v] - mean), -cap, cap));
  for (size_t k = 1; k < levels.size(); ++k) {
    std::vector<double> sum(levels[k].size(), 0), w(levels[k].size(), 0);
    for (int v = 0; v < levels[k - 1].size(); ++v) {
      const int pa = levels[k - 1].parent[v];
      sum[pa] += levels[k - 1].area[v] * std::log(scale[k - 1][v]);
      w[pa] += levels[k - 1].area[v];
    }
    for (int v = 0; v < levels[k].size(); ++v)
      scale[k][v] = w[v] > 0 ? std::exp(sum[v] / w[v]) : 1.0;
  }
  return scale;
}

}  // namespace

Vec3 any_perpendicular(const Vec3& n) {
  return plane_axes(n).first;
}

Vec3 match_cross(const Vec3& q, const Vec3& n, const Vec3& target) {
  const Vec3 t = n.cross(q);
  const std::array<Vec3, 4> c = {q, t, Vec3(-q), Vec3(-t)};
  int best = 0;
  for (int k = 1; k < 4; ++k)
    if (c[k].dot(target) > c[best].dot(target)) best = k;
  return c[best];
}

MetricFrames metric_frames(const TriMesh& rest, const TriMesh& def, const Field& field, double h,
                           const QuadAnisoOptions& o) {
  if (rest.num_faces() != def.num_faces() || rest.num_vertices() != def.num_vertices() ||
      field.size() != rest.num_faces())
    throw Error("quad-aniso", "M, M' and the field do not match");
  MetricFrames m;
  m.topo = build_topology(def);
  m.pos.resize(def.num_vertices());
  for (int v = 0; v < def.num_vertices(); ++v) m.pos[v] = def.vertex(v);
  m.levels = build_hierarchy(def, m.topo, o.coarsest);
  m.cfs = cross_field(rest, def, field, m.topo, m.levels, h, o);
  for (size_t k = 0; k < m.levels.size(); ++k)
    m.matched.push_back(matched_frames(m.levels[k], m.cfs[k]));
  m.scale = integrable_scale(def, field, m.levels, m.cfs[0], o);
  m.rest_normal = vertex_normals(rest);
  std::vector<std::pair<double, double>> sw;
  for (int v = 0; v < m.levels[0].size(); ++v) sw.emplace_back(m.scale[0][v], m.levels[0].area[v]);
  std::sort(sw.begin(), sw.end());
  double total = 0, acc = 0;
  for (const auto& [x, w] : sw) total += w;
  for (const auto& [x, w] : sw) {
    if (acc <= 0.1 * total) m.scale_p10 = x;
    if (acc <= 0.9 * total) m.scale_p90 = x;
    acc += w;
  }
  return m;
}

}  // namespace gridshell::quad_aniso_internal
