// The planes of flat panels (flat_panels_internal.h): energy, Gauss–Newton blocks, start and
// Levenberg–Marquardt.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <array>

#include <Eigen/Sparse>

#include "gridshell/core/sparse_cholesky.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/optimize/flat_panels_internal.h"
#include "gridshell/optimize/metrics.h"
#include "gridshell/optimize/projector.h"

namespace gridshell::flat_detail {

void plane_of(const Problem& P, const Planes& pl, int ref, Vec3& n, double& d) {
  if (ref >= 0) {
    n = pl.n[ref];
    d = pl.d[ref];
  } else {
    n = P.L->fixed_normal[-1 - ref];
    d = P.L->fixed_offset[-1 - ref];
  }
}

/// All joints of `pl`; false when a joint's planes are nearly parallel.
bool joints_of(const Problem& P, const Planes& pl, std::vector<Vec3>& x, std::vector<double>& det,
               double min_det) {
  const int nj = static_cast<int>(P.L->joints.size());
  x.resize(nj);
  det.resize(nj);
  std::vector<char> ok(nj, 1);
  tbb::parallel_for(0, nj, [&](int j) {
    Vec3 n[3];
    double d[3];
    for (int s = 0; s < 3; ++s) plane_of(P, pl, P.L->joints[j].plane[s], n[s], d[s]);
    ok[j] = intersect_planes(n, d, x[j], det[j], min_det) && x[j].allFinite();
  });
  return std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
}


namespace {

/// The energy's residuals of joint j (kJointResiduals): surface, design (3), barrier, and the
/// three sides of its cells' triangle (inside).
int joint_residuals(const Problem& P, int j, const Vec3& x, double det,
                    double r[kJointResiduals]) {
  const double ws = std::sqrt(P.o.surface_weight) / P.h;
  const double w0 = std::sqrt(design_weight_of(P, j)) / P.h;
  r[0] = ws * P.anchor[j].normal.dot(x - P.anchor[j].point);
  for (int k = 0; k < 3; ++k) r[1 + k] = w0 * (x[k] - P.x0[j][k]);
  const double a = std::abs(det);
  r[4] = a < P.o.barrier_det ? std::sqrt(P.o.barrier_weight) * std::log(P.o.barrier_det / a) : 0;
  const double wi = std::sqrt(P.o.inside_weight) / P.h;
  for (int k = 0; k < 3; ++k) {
    const Side& side = P.inside[j][k];
    const double sigma = side.normal.dot(x) - side.offset;
    r[5 + k] = sigma < 0 ? -wi * sigma : 0;
  }
  return kJointResiduals;
}

/// The fairness residual of face f: n_f − mean of its neighbours' normals.
Vec3 fairness_residual(const Problem& P, const Planes& pl, int f) {
  const auto& nb = P.face_neighbours[f];
  Vec3 m = Vec3::Zero();
  for (int g : nb) m += pl.n[g];
  if (nb.empty()) return Vec3::Zero();
  return std::sqrt(P.o.fairness_weight) * (pl.n[f] - m / static_cast<double>(nb.size()));
}

/// The hinge of beam b: sqrt(w_beam) max(0, ℓ_min − u·(x_b − x_a)) / h.
double beam_residual(const Problem& P, const Beam& b, const std::vector<Vec3>& x) {
  const double s = b.u.dot(x[b.b] - x[b.a]);
  return s < b.min_length ? std::sqrt(P.o.beam_weight) * (b.min_length - s) / P.h : 0;
}

double energy(const Problem& P, const Planes& pl, const std::vector<Vec3>& x,
              const std::vector<double>& det) {
  double e = 0;
  for (std::size_t j = 0; j < x.size(); ++j) {
    double r[kJointResiduals];
    joint_residuals(P, static_cast<int>(j), x[j], det[j], r);
    for (double v : r) e += v * v;
  }
  for (std::size_t f = 0; f < pl.n.size(); ++f)
    e += fairness_residual(P, pl, static_cast<int>(f)).squaredNorm();
  for (const Beam& b : P.beams) {
    const double r = beam_residual(P, b, x);
    e += r * r;
  }
  return e;
}



/// Number of panels that are not simple polygons (in their own planes).
int self_intersections(const Layout& L, const Planes& pl, const std::vector<Vec3>& x) {
  int count = 0;
  for (std::size_t f = 0; f < L.faces.size(); ++f) {
    std::vector<Vec3> p;
    for (int j : L.faces[f]) p.push_back(x[j]);
    count += !simple_2d(in_plane(p, pl.n[f]));
  }
  return count;
}



}  // namespace

int short_beams(const Problem& P, const std::vector<Vec3>& x) {
  int count = 0;
  for (const Beam& b : P.beams) count += !(b.u.dot(x[b.b] - x[b.a]) > P.shortest_allowed);
  return count;
}

/// The closest points on M of the joints `x` and M's normals there (walks from the last ones).
void update_anchors(const TriMesh& surface, const SurfaceProjector& projector,
                    const std::vector<Vec3>& x, std::vector<Anchor>& anchor) {
  anchor.resize(x.size());
  tbb::parallel_for(0, static_cast<int>(x.size()), [&](int j) {
    Anchor& a = anchor[j];
    a.point = projector.closest_point_walk(x[j], a.triangle);
    if (a.triangle >= 0 && a.triangle < surface.num_faces()) {
      const auto& t = surface.F.row(a.triangle);
      const Vec3 p0 = surface.V.row(t[0]).transpose(), p1 = surface.V.row(t[1]).transpose(),
                 p2 = surface.V.row(t[2]).transpose();
      const Vec3 n = (p1 - p0).cross(p2 - p0);
      if (n.norm() > 0) a.normal = n.normalized();
    }
  });
}

namespace {


/// Adds the local Gauss–Newton block G (rows × cols, residuals r) at the unknowns `col` (−1 =
/// none) to JᵀJ (triplets) and Jᵀr.
void add_block(const Eigen::MatrixXd& G, const Eigen::VectorXd& r, const std::vector<int>& col,
               std::vector<Eigen::Triplet<double>>& H, Eigen::VectorXd& g) {
  const Eigen::MatrixXd GtG = G.transpose() * G;
  const Eigen::VectorXd Gtr = G.transpose() * r;
  const int m = static_cast<int>(col.size());
  for (int a = 0; a < m; ++a) {
    if (col[a] < 0) continue;
    g[col[a]] += Gtr[a];
    for (int b = 0; b < m; ++b)
      if (col[b] >= 0 && col[b] <= col[a]) H.emplace_back(col[a], col[b], GtG(a, b));
  }
}

/// A joint's derivatives with respect to its planes' unknowns (α1, α2, β per plane; col −1 for a
/// fixed plane).
struct JointDerivative {
  Eigen::Matrix<double, 3, 9> Dx = Eigen::Matrix<double, 3, 9>::Zero();
  Eigen::Matrix<double, 1, 9> Ddet = Eigen::Matrix<double, 1, 9>::Zero();
  std::array<int, 9> col{-1, -1, -1, -1, -1, -1, -1, -1, -1};
};

JointDerivative joint_derivative(const Problem& P, const Planes& pl, int j) {
  const Joint& J = P.L->joints[j];
  Vec3 n[3];
  double d[3];
  for (int s = 0; s < 3; ++s) plane_of(P, pl, J.plane[s], n[s], d[s]);
  Vec3 xj;
  double dj;
  Eigen::Matrix<double, 3, 12> Jx;
  intersect_planes(n, d, xj, dj, 0, &Jx);
  JointDerivative D;
  const Vec3 cof[3] = {n[1].cross(n[2]), n[2].cross(n[0]), n[0].cross(n[1])};
  for (int s = 0; s < 3; ++s) {
    const int f = J.plane[s];
    if (f < 0) continue;
    const auto [b1, b2] = plane_axes(pl.n[f]);
    D.Dx.col(3 * s) = Jx.block<3, 3>(0, 4 * s) * b1;
    D.Dx.col(3 * s + 1) = Jx.block<3, 3>(0, 4 * s) * b2;
    D.Dx.col(3 * s + 2) = Jx.col(4 * s + 3);
    D.Ddet(3 * s) = cof[s].dot(b1);
    D.Ddet(3 * s + 1) = cof[s].dot(b2);
    for (int k = 0; k < 3; ++k) D.col[3 * s + k] = 3 * f + k;
  }
  return D;
}

/// The joint terms' and the beams' Gauss–Newton blocks (9 unknowns per joint: the three planes'
/// (α1, α2, β); 18 per beam).
void joint_blocks(const Problem& P, const Planes& pl, const std::vector<Vec3>& x,
                  const std::vector<double>& det, std::vector<Eigen::Triplet<double>>& H,
                  Eigen::VectorXd& g) {
  const int nj = static_cast<int>(x.size());
  std::vector<JointDerivative> D(nj);
  tbb::parallel_for(0, nj, [&](int j) { D[j] = joint_derivative(P, pl, j); });
  for (int j = 0; j < nj; ++j) {
    double res[kJointResiduals];
    joint_residuals(P, j, x[j], det[j], res);
    const double ws = std::sqrt(P.o.surface_weight) / P.h;
    const double w0 = std::sqrt(design_weight_of(P, j)) / P.h;
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(kJointResiduals, 9);
    G.row(0) = ws * P.anchor[j].normal.transpose() * D[j].Dx;
    G.middleRows(1, 3) = w0 * D[j].Dx;
    if (res[4] > 0) G.row(4) = -std::sqrt(P.o.barrier_weight) / det[j] * D[j].Ddet;
    const double wi = std::sqrt(P.o.inside_weight) / P.h;
    for (int k = 0; k < 3; ++k)
      if (res[5 + k] > 0) G.row(5 + k) = -wi * P.inside[j][k].normal.transpose() * D[j].Dx;
    add_block(G, Eigen::Map<Eigen::VectorXd>(res, kJointResiduals), {D[j].col.begin(), D[j].col.end()}, H, g);
  }
  for (const Beam& b : P.beams) {
    const double r = beam_residual(P, b, x);
    if (r <= 0) continue;
    Eigen::MatrixXd G(1, 18);
    const double w = -std::sqrt(P.o.beam_weight) / P.h;
    G.leftCols(9) = -w * b.u.transpose() * D[b.a].Dx;
    G.rightCols(9) = w * b.u.transpose() * D[b.b].Dx;
    std::vector<int> col(D[b.a].col.begin(), D[b.a].col.end());
    col.insert(col.end(), D[b.b].col.begin(), D[b.b].col.end());
    add_block(G, Eigen::VectorXd::Constant(1, r), col, H, g);
  }
}

/// The fairness terms' blocks: face f and its neighbours' (α1, α2).
void fairness_blocks(const Problem& P, const Planes& pl, std::vector<Eigen::Triplet<double>>& H,
                     Eigen::VectorXd& g) {
  const double w = std::sqrt(P.o.fairness_weight);
  for (std::size_t f = 0; f < pl.n.size(); ++f) {
    const auto& nb = P.face_neighbours[f];
    if (nb.empty()) continue;
    const int m = 2 + 2 * static_cast<int>(nb.size());
    Eigen::MatrixXd G(3, m);
    std::vector<int> col(m);
    const auto [b1, b2] = plane_axes(pl.n[f]);
    G.col(0) = w * b1;
    G.col(1) = w * b2;
    col[0] = 3 * static_cast<int>(f);
    col[1] = 3 * static_cast<int>(f) + 1;
    for (std::size_t k = 0; k < nb.size(); ++k) {
      const auto [c1, c2] = plane_axes(pl.n[nb[k]]);
      G.col(2 + 2 * k) = -w / nb.size() * c1;
      G.col(3 + 2 * k) = -w / nb.size() * c2;
      col[2 + 2 * k] = 3 * nb[k];
      col[3 + 2 * k] = 3 * nb[k] + 1;
    }
    const Vec3 r = fairness_residual(P, pl, static_cast<int>(f));
    add_block(G, r, col, H, g);
  }
}

/// The planes after the step δ: n ← normalize(n + α1 b1 + α2 b2), d ← d + β.
Planes step(const Planes& pl, const Eigen::VectorXd& delta) {
  Planes out = pl;
  for (std::size_t f = 0; f < pl.n.size(); ++f) {
    const auto [b1, b2] = plane_axes(pl.n[f]);
    out.n[f] = (pl.n[f] + delta[3 * f] * b1 + delta[3 * f + 1] * b2).normalized();
    out.d[f] = pl.d[f] + delta[3 * f + 2];
  }
  return out;
}


}  // namespace

/// The design's joints lifted by the paraboloid −σ κ/2 |P_t(x − o)|² along M's normal (o the
/// centre of the grid-shell, κ = lift / bbox diagonal, σ the side the panels' normals point to):
/// on flat and cylindrical parts the tangent planes of a paraboloid meet over the circumcentres
/// of neighbouring cells (a power diagram), so joint positions become well defined.
std::vector<Vec3> lifted_targets(const Problem& P, double lift, double diagonal) {
  std::vector<Vec3> t = P.x0;
  if (lift <= 0) return t;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& x : P.x0) centre += x;
  centre /= std::max<std::size_t>(1, P.x0.size());
  double side = 0;
  for (std::size_t j = 0; j < t.size(); ++j) side += P.anchor[j].normal.dot(P.x0[j] - centre);
  const double sigma = side >= 0 ? 1 : -1, kappa = lift / std::max(1e-300, diagonal);
  for (std::size_t j = 0; j < t.size(); ++j) {
    const Vec3& n = P.anchor[j].normal;
    const Vec3 y = (P.x0[j] - centre) - (P.x0[j] - centre).dot(n) * n;
    t[j] -= 0.5 * sigma * kappa * y.squaredNorm() * n;
  }
  return t;
}


namespace {

/// Best-fit plane of each panel's joints `x` (normal kept on the side of the previous one).
void fit_planes(const Layout& L, const std::vector<Vec3>& x, Planes& pl) {
  tbb::parallel_for(0, static_cast<int>(L.faces.size()), [&](int f) {
    std::vector<Vec3> p;
    for (int j : L.faces[f]) p.push_back(x[j]);
    const FaceFrame fr = face_frame(p);
    Vec3 n = fr.normal;
    if (pl.n[f].dot(n) < 0) n = -n;
    pl.n[f] = n;
    pl.d[f] = n.dot(fr.centroid);
  });
}


}  // namespace

/// The starting planes: nearly planar panels by alternation (ShapeUp-like, Bouaziz et al. 2012)
/// with a rising planarity weight w_p = 1 … 1e6: each panel's best-fit plane, then each joint at
/// argmin w_p Σ (n·x − d)² over its three planes + the joint terms of the energy (towards the
/// lifted design joint). Where the planes then meet well, their intersections are next to these
/// joints and the Levenberg–Marquardt steps start close to a minimum.
Planes start_planes(Problem& P, const TriMesh& surface, const SurfaceProjector& projector,
                    const std::vector<Vec3>& target) {
  const Layout& L = *P.L;
  const int nj = static_cast<int>(L.joints.size()), nf = static_cast<int>(L.faces.size());
  Planes pl;
  pl.n.assign(nf, Vec3::Zero());
  pl.d.assign(nf, 0);
  std::vector<Vec3> x = target;
  std::vector<std::vector<int>> beams_at(nj);  // per joint: its beams (index into P.beams)
  for (std::size_t e = 0; e < P.beams.size(); ++e) {
    beams_at[P.beams[e].a].push_back(static_cast<int>(e));
    beams_at[P.beams[e].b].push_back(static_cast<int>(e));
  }
  for (int stage = 0; stage <= 6; ++stage) {
    const double wp = std::pow(10.0, stage);
    // The beams' push keeps its weight while w_p rises (measured: rising with w_p, as √w_p or
    // w_p / 10, it throws joints far off on every failing surface).
    const double wb = P.o.beam_weight;
    for (int it = 0; it < 8; ++it) {
      fit_planes(L, x, pl);
      update_anchors(surface, projector, x, P.anchor);
      const std::vector<Vec3> previous = x;
      tbb::parallel_for(0, nj, [&](int j) {
        const Joint& J = L.joints[j];
        const double w0 = design_weight_of(P, j);
        const Anchor& a = P.anchor[j];
        Eigen::Matrix3d A = w0 * Eigen::Matrix3d::Identity() +
                            P.o.surface_weight * a.normal * a.normal.transpose();
        Vec3 b = w0 * target[j] + P.o.surface_weight * a.normal * a.normal.dot(a.point);
        for (int s = 0; s < 3; ++s) {
          Vec3 n;
          double d;
          plane_of(P, pl, J.plane[s], n, d);
          A += wp * n * n.transpose();
          b += wp * d * n;
        }
        // A beam shorter than its least length pushes its end away from the other end's last
        // position, along the beam's design direction.
        for (int e : beams_at[j]) {
          const Beam& B = P.beams[e];
          if (B.u.dot(previous[B.b] - previous[B.a]) >= B.min_length) continue;
          const double goal = j == B.a ? B.u.dot(previous[B.b]) - B.min_length
                                       : B.u.dot(previous[B.a]) + B.min_length;
          A += wb * B.u * B.u.transpose();
          b += wb * goal * B.u;
        }
        x[j] = A.ldlt().solve(b);
      });
    }
  }
  fit_planes(L, x, pl);
  return pl;
}

/// Levenberg–Marquardt on the planes; returns the iterations run, `converged` when it stopped on
/// its tolerance.
int optimise(Problem& P, Planes& pl, const TriMesh& surface, const SurfaceProjector& projector,
             FlatPanelStats& stats) {
  const int nu = 3 * static_cast<int>(pl.n.size());
  std::vector<Vec3> x;
  std::vector<double> det;
  if (!joints_of(P, pl, x, det, P.o.min_det))
    throw FlatPanelsFailed("the panels' first planes are parallel at a joint");
  int crossings = self_intersections(*P.L, pl, x), shorts = short_beams(P, x);
  if (spdlog::should_log(spdlog::level::debug)) {
    int far_interior = 0, far_boundary = 0, boundary = 0;
    for (std::size_t j = 0; j < x.size(); ++j) {
      const bool b = P.L->joints[j].plane[0] < 0 || P.L->joints[j].plane[1] < 0 ||
                     P.L->joints[j].plane[2] < 0;
      boundary += b;
      if ((x[j] - P.x0[j]).norm() > P.h) (b ? far_boundary : far_interior)++;
    }
    spdlog::debug("[flat panels] start: {} joints ({} boundary); farther than a beam from the "
                  "design: {} interior, {} boundary",
                  x.size(), boundary, far_interior, far_boundary);
  }
  // A factorisation that fails (a step with too small a damping on a nearly singular system) is
  // handled below by more damping.
  SparseCholesky solver;
  double mu = 1e-3;
  int it = 0;
  for (; it < P.o.max_iterations; ++it) {
    update_anchors(surface, projector, x, P.anchor);
    const double E = energy(P, pl, x, det);
    if (it == 0) stats.energy_start = E;
    stats.energy = E;
    std::vector<Eigen::Triplet<double>> T;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(nu);
    joint_blocks(P, pl, x, det, T, g);
    fairness_blocks(P, pl, T, g);
    for (int i = 0; i < nu; ++i) T.emplace_back(i, i, 0.0);
    Eigen::SparseMatrix<double> H(nu, nu);
    H.setFromTriplets(T.begin(), T.end());
    const Eigen::VectorXd diag = H.diagonal();
    bool accepted = false;
    for (int attempt = 0; attempt < 12 && !accepted; ++attempt) {
      Eigen::SparseMatrix<double> A = H;
      for (int i = 0; i < nu; ++i) A.coeffRef(i, i) += mu * (diag[i] + 1e-9);
      if (!solver.analyzed()) solver.analyze(A);
      if (!solver.factorize(A).ok) {
        mu *= 10;
        continue;
      }
      const Eigen::VectorXd delta = solver.solve(-g);
      const Planes trial = step(pl, delta);
      std::vector<Vec3> xt;
      std::vector<double> dt;
      if (delta.allFinite() && joints_of(P, trial, xt, dt, P.o.min_det)) {
        const int ct = self_intersections(*P.L, trial, xt), st = short_beams(P, xt);
        const double Et = energy(P, trial, xt, dt);
        if (((ct <= crossings && st <= shorts) || !P.o.guard) && Et < E) {
          pl = trial, x = std::move(xt), det = std::move(dt), crossings = ct, shorts = st;
          stats.energy = Et;
          accepted = true;
          mu = std::max(mu / 3, 1e-9);
          if (E - Et < P.o.tolerance * E) {
            stats.converged = true;
            return it + 1;
          }
        }
      }
      if (!accepted) mu *= 5;
    }
    spdlog::debug("[flat panels] iteration {}: energy {:.6g}, {} self-intersecting, {} short beams, "
                  "mu {:.3g}{}",
                  it, stats.energy, crossings, shorts, mu, accepted ? "" : " (no step)");
    if (!accepted) {  // no step lowers the energy: a minimum to the solver's accuracy
      stats.converged = true;
      return it;
    }
  }
  return it;
}


}  // namespace gridshell::flat_detail
