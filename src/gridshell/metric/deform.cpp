#include "gridshell/metric/deform.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <Eigen/Sparse>

#include "gridshell/core/sparse_cholesky.h"
#include "gridshell/core/error.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

namespace {

using Mat32 = Eigen::Matrix<double, 3, 2>;
using Mat33 = Eigen::Matrix3d;

constexpr double kBoundaryBending = 0.1;
/// A face's membrane stiffness area · D Dᵀ has the trace Σ cot θ (√3 for an equilateral
/// triangle), which grows without bound on a sliver (a boundary "cap" of a mapped disk: area
/// 1e-7 m², trace ~1e8, and the bending term squares it): the global system is then not
/// positive definite in floating point. Above this trace the face's weight is scaled down so its
/// trace is this (a positive multiple of a positive semi-definite term: the sum stays positive
/// definite); faces with no angle below about 0.1° keep their area.
constexpr double kMaxCotangentSum = 1e3;

/// The global step's factorisation: supernodal (BLAS blocks: 2× faster than the simplicial one on
/// the bending system's two-ring stencil), then converted to a simplicial factor, whose solves
/// with three right-hand sides are faster than the supernodal ones (per-supernode BLAS calls
/// on small blocks) — the iterations only solve.
SparseCholeskyOptions global_llt_options() {
  SparseCholeskyOptions o;
  o.simplicial_solves = true;
  return with_environment(o);
}

/// Per-face data of the local/global solver on one mesh level.
struct Level {
  std::vector<Mat32> D;                 ///< J = X D, X = (x0 x1 x2) of the face on M′
  std::vector<Mat32> frame;             ///< (u, u⊥) in 3D
  std::vector<Eigen::Vector2d> target;  ///< (d/a, d)
  std::vector<double> area;
  /// The face's weight in the energy: its area, less on a sliver (kMaxCotangentSum).
  std::vector<double> weight;
  std::vector<int> free_index;  ///< vertex → unknown index or -1 when fixed
  int num_free = 0;
  Eigen::SparseMatrix<double> Lff;          ///< free × free
  std::vector<Eigen::Triplet<double>> Lfc;  ///< free × fixed couplings
  Eigen::SparseMatrix<double> muB;          ///< bending matrix (all vertices), may be empty
  Eigen::MatrixXd bending_rhs;              ///< muB · X_ref (all vertices), may be empty
  SparseCholesky llt{global_llt_options()};
};

/// Unit tangent u of face f (field direction projected) and u⊥ = n × u.
Mat32 face_frame(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& u_in) {
  const Vec3 n = (p1 - p0).cross(p2 - p0).normalized();
  Vec3 u = u_in - u_in.dot(n) * n;
  if (!(u.norm() > 1e-9)) u = (p1 - p0);
  u.normalize();
  Mat32 fr;
  fr.col(0) = u;
  fr.col(1) = n.cross(u);
  return fr;
}

/// `bending_length`: the length h of the bending weight μ = bending · h².
void build_level(Level& lv, const TriMesh& rest, const Field& field, double bending,
                 double bending_length) {
  const int nf = rest.num_faces(), nv = rest.num_vertices();
  lv.D.resize(nf);
  lv.frame.resize(nf);
  lv.target.resize(nf);
  lv.area.resize(nf);
  lv.weight.resize(nf);
  const double diag = bbox_diagonal(rest.V);
  for (int f = 0; f < nf; ++f) {
    const Vec3 p0 = rest.vertex(rest.F(f, 0)), p1 = rest.vertex(rest.F(f, 1)),
               p2 = rest.vertex(rest.F(f, 2));
    const double area = triangle_area(p0, p1, p2);
    if (!(area > 1e-14 * diag * diag))
      throw Error("mesh", fmt::format("degenerate triangle {} (zero area)", f));
    const double d = field.d[f], a = field.a[f];
    if (!std::isfinite(d) || !std::isfinite(a) || !(d > 0) || !(a > 0))
      throw Error("field", fmt::format("invalid density/anisotropy at face {}", f));
    if (!field.u[f].allFinite()) throw Error("field", fmt::format("non-finite u at face {}", f));
    lv.frame[f] = face_frame(p0, p1, p2, field.u[f]);
    Eigen::Matrix2d E;
    E.col(0) = lv.frame[f].transpose() * (p1 - p0);
    E.col(1) = lv.frame[f].transpose() * (p2 - p0);
    Eigen::Matrix<double, 3, 2> G;
    G << -1, -1, 1, 0, 0, 1;
    lv.D[f] = G * E.inverse();
    lv.target[f] = Eigen::Vector2d(d / a, d);
    lv.area[f] = area;
    const double trace = area * lv.D[f].squaredNorm();
    lv.weight[f] = trace > kMaxCotangentSum ? area * kMaxCotangentSum / trace : area;
  }
  // One fixed vertex per connected component; unreferenced vertices are fixed too.
  DisjointSets sets(nv);
  std::vector<char> used(nv, 0);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      used[rest.F(f, k)] = 1;
      sets.unite(rest.F(f, k), rest.F(f, (k + 1) % 3));
    }
  lv.free_index.assign(nv, -1);
  std::vector<char> root_fixed(nv, 0);
  lv.num_free = 0;
  for (int v = 0; v < nv; ++v) {
    if (!used[v]) continue;
    const int r = sets.find(v);
    if (!root_fixed[r]) {
      root_fixed[r] = 1;  // the first vertex of each component stays put
      continue;
    }
    lv.free_index[v] = lv.num_free++;
  }
  // Membrane part: the cotangent Laplacian K = Σ area D Dᵀ of the rest mesh.
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(9 * static_cast<std::size_t>(nf));
  std::vector<double> vertex_area(nv, 0.0);
  std::vector<char> boundary(nv, 0);
  for (int f = 0; f < nf; ++f) {
    const Mat33 K = lv.weight[f] * lv.D[f] * lv.D[f].transpose();
    for (int i = 0; i < 3; ++i) {
      vertex_area[rest.F(f, i)] += lv.area[f] / 3;
      for (int j = 0; j < 3; ++j) trip.emplace_back(rest.F(f, i), rest.F(f, j), K(i, j));
    }
  }
  Eigen::SparseMatrix<double> A(nv, nv);
  A.setFromTriplets(trip.begin(), trip.end());
  // Bending part: μ Σ_v β_v |(K (x′ − x_ref))_v|² / area_v, μ = bending · h², β = 1 inside and
  // kBoundaryBending on the boundary (there K x also measures in-plane stretch of the boundary,
  // which the membrane term must stay free to change).
  if (bending > 0) {
    const Topology topo = build_topology(rest);
    Eigen::VectorXd w = Eigen::VectorXd::Zero(nv);
    for (int v = 0; v < nv; ++v)
      if (vertex_area[v] > 0)
        w[v] = (topo.on_boundary[v] ? kBoundaryBending : 1.0) / vertex_area[v];
    const double h = bending_length;
    lv.muB = (bending * h * h) * Eigen::SparseMatrix<double>(A * w.asDiagonal() * A);
    A = A + lv.muB;
  } else {
    lv.muB.resize(0, 0);
  }
  lv.bending_rhs.resize(0, 3);
  lv.Lfc.clear();
  trip.clear();
  for (int k = 0; k < A.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, k); it; ++it) {
      const int fi = lv.free_index[it.row()];
      if (fi < 0) continue;
      const int fj = lv.free_index[it.col()];
      if (fj >= 0)
        trip.emplace_back(fi, fj, it.value());
      else
        lv.Lfc.emplace_back(fi, static_cast<int>(it.col()), it.value());
    }
  lv.Lff.resize(lv.num_free, lv.num_free);
  lv.Lff.setFromTriplets(trip.begin(), trip.end());
  if (lv.num_free > 0) {
    if (!lv.llt.compute(lv.Lff).ok)
      throw Error("metric", "deformation system could not be factorised");
  }
}

/// Best orthonormal-column R (3×2) maximising tr(Rᵀ M).
Mat32 polar32(const Mat32& M) {
  const Eigen::Matrix2d S = M.transpose() * M;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es;
  es.computeDirect(S);
  const Eigen::Vector2d ev = es.eigenvalues();
  const double scale = std::max(ev[1], 1e-300);
  if (ev[0] > 1e-12 * scale && std::isfinite(ev[0])) {
    const Eigen::Matrix2d& V = es.eigenvectors();
    const Eigen::Vector2d inv(1 / std::sqrt(ev[0]), 1 / std::sqrt(ev[1]));
    return M * (V * inv.asDiagonal() * V.transpose());
  }
  Eigen::JacobiSVD<Mat32> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU().leftCols<2>() * svd.matrixV().transpose();
}

/// Global step: positions X (free vertices) best fitting the targets B_t = R_t S_t.
void global_step(Level& lv, const TriMesh& rest, Points& X, const std::vector<Mat32>& R) {
  const int nf = rest.num_faces();
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(lv.num_free, 3);
  for (int f = 0; f < nf; ++f) {
    const Mat32 B = R[f] * lv.target[f].asDiagonal();
    const Mat33 C = lv.weight[f] * lv.D[f] * B.transpose();  // row i → vertex i
    for (int i = 0; i < 3; ++i) {
      const int fi = lv.free_index[rest.F(f, i)];
      if (fi >= 0) rhs.row(fi) += C.row(i);
    }
  }
  for (const auto& t : lv.Lfc) rhs.row(t.row()) -= t.value() * X.row(t.col());
  if (lv.bending_rhs.rows() == rest.num_vertices())
    for (int v = 0; v < rest.num_vertices(); ++v)
      if (lv.free_index[v] >= 0) rhs.row(lv.free_index[v]) += lv.bending_rhs.row(v);
  if (lv.num_free > 0) {
    const Eigen::MatrixXd sol = lv.llt.solve(rhs);
    if (!sol.allFinite())
      throw Error("metric", "deformation solve failed");
    for (int v = 0; v < rest.num_vertices(); ++v)
      if (lv.free_index[v] >= 0) X.row(v) = sol.row(lv.free_index[v]);
  }
}

/// The bending term penalises |K (x′ − X_ref)|²: curvature changes against the reference, so
/// crumpling is expensive while the reference shape itself costs nothing.
void set_reference(Level& lv, const Points& X) {
  if (lv.muB.rows() == X.rows()) lv.bending_rhs = lv.muB * Eigen::MatrixXd(X);
}

/// Local step: best frames for the current X; returns the relative residual before the update.
/// Orientation-preserving fit for a triangle turned over in M′: the membrane energy cannot tell a
/// triangle from its mirror image (both have the same metric), so the plain polar fit keeps a
/// flipped triangle flipped. Here R spans the triangle's plane with the orientation of `n_ref`
/// (the normal of the surface around it) and its 2×2 part is the rotation (det +1) closest to
/// the reflection the triangle shows; the global step then turns the triangle back.
Mat32 oriented_fit(const Mat32& M, const Vec3& n_ref) {
  Vec3 n = M.col(0).cross(M.col(1));
  if (!(n.norm() > 0)) return polar32(M);
  n.normalize();
  if (n.dot(n_ref) < 0) n = -n;  // the plane of the triangle, oriented like its surroundings
  Vec3 b1 = M.col(0).norm() > M.col(1).norm() ? M.col(0) : M.col(1);
  b1 = (b1 - b1.dot(n) * n).normalized();
  Mat32 B;
  B.col(0) = b1;
  B.col(1) = n.cross(b1);
  const Eigen::Matrix2d M2 = B.transpose() * M;
  Eigen::JacobiSVD<Eigen::Matrix2d> svd(M2, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix2d U = svd.matrixU();
  if ((U * svd.matrixV().transpose()).determinant() < 0) U.col(1) *= -1;
  return B * (U * svd.matrixV().transpose());
}

/// Local step: best frames for the current X; returns the relative residual before the update.
double local_step(const Level& lv, const TriMesh& rest, const Points& X, std::vector<Mat32>& R) {
  const int nf = rest.num_faces();
  std::vector<double> e(nf), s(nf);
  // Normal of the surface around each face: the area-weighted normals of the faces sharing a
  // vertex with it (itself excluded), to detect triangles turned over against their neighbours.
  std::vector<Vec3> fn(nf);
  Eigen::MatrixXd vn = Eigen::MatrixXd::Zero(X.rows(), 3);
  for (int f = 0; f < nf; ++f) {
    const Vec3 p0 = X.row(rest.F(f, 0)).transpose();
    fn[f] = (Vec3(X.row(rest.F(f, 1)).transpose()) - p0)
                .cross(Vec3(X.row(rest.F(f, 2)).transpose()) - p0);
    for (int k = 0; k < 3; ++k) vn.row(rest.F(f, k)) += fn[f].transpose();
  }
  tbb::parallel_for(0, nf, [&](int f) {
    Mat33 Xt;
    for (int k = 0; k < 3; ++k) Xt.col(k) = X.row(rest.F(f, k)).transpose();
    const Mat32 J = Xt * lv.D[f];
    const Mat32 M = J * lv.target[f].asDiagonal();
    const Vec3 around =
        (vn.row(rest.F(f, 0)) + vn.row(rest.F(f, 1)) + vn.row(rest.F(f, 2))).transpose() -
        3 * fn[f];
    R[f] = fn[f].dot(around) < 0 ? oriented_fit(M, around) : polar32(M);
    e[f] = lv.weight[f] * (J - R[f] * lv.target[f].asDiagonal()).squaredNorm();
    s[f] = lv.area[f] * lv.target[f].squaredNorm();
  });
  // Serial sums: independent of the thread count.
  const double num = std::accumulate(e.begin(), e.end(), 0.0);
  const double den = std::accumulate(s.begin(), s.end(), 0.0);
  return den > 0 ? num / den : 0;
}

double longest_edge(const TriMesh& m) {
  double best = 0;
  for (int f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      best = std::max(best, (m.V.row(m.F(f, k)) - m.V.row(m.F(f, (k + 1) % 3))).squaredNorm());
  return std::sqrt(best);
}

int count_folds(const TriMesh& m) {
  const Topology topo = build_topology(m);
  auto normal = [&](int f) {
    const Vec3 p0 = m.vertex(m.F(f, 0));
    return Vec3((m.vertex(m.F(f, 1)) - p0).cross(m.vertex(m.F(f, 2)) - p0));
  };
  int folds = 0;
  for (const auto& ef : topo.edge_faces)
    if (ef.size() == 2 && normal(ef[0]).dot(normal(ef[1])) < 0) ++folds;
  return folds;
}

/// Runs `iters` local/global iterations; returns the final relative residual.
double iterate(Level& lv, const TriMesh& rest, Points& X, int iters) {
  std::vector<Mat32> R(rest.num_faces());
  for (int it = 0; it < iters; ++it) {
    local_step(lv, rest, X, R);
    global_step(lv, rest, X, R);
  }
  return local_step(lv, rest, X, R);
}

}  // namespace

int split_long_edges(TriMesh& rest, TriMesh& deformed, double max_edge, std::vector<int>& parent) {
  const int nf = rest.num_faces();
  const Topology topo = build_topology(rest);
  std::vector<int> mid(topo.num_edges(), -1);
  int nv = rest.num_vertices();
  int count = 0;
  for (int e = 0; e < topo.num_edges(); ++e) {
    const auto [a, b] = topo.edges[e];
    if ((deformed.V.row(a) - deformed.V.row(b)).norm() > max_edge) {
      mid[e] = nv++;
      ++count;
    }
  }
  parent.clear();
  if (count == 0) {
    parent.resize(nf);
    std::iota(parent.begin(), parent.end(), 0);
    return 0;
  }
  Points rv(nv, 3), dv(nv, 3);
  rv.topRows(rest.num_vertices()) = rest.V;
  dv.topRows(rest.num_vertices()) = deformed.V;
  for (int e = 0; e < topo.num_edges(); ++e)
    if (mid[e] >= 0) {
      const auto [a, b] = topo.edges[e];
      rv.row(mid[e]) = 0.5 * (rest.V.row(a) + rest.V.row(b));
      dv.row(mid[e]) = 0.5 * (deformed.V.row(a) + deformed.V.row(b));
    }
  std::vector<std::array<int, 3>> faces;
  faces.reserve(static_cast<std::size_t>(nf) * 2);
  auto add = [&](int a, int b, int c, int p) {
    faces.push_back({a, b, c});
    parent.push_back(p);
  };
  for (int f = 0; f < nf; ++f) {
    const int v[3] = {rest.F(f, 0), rest.F(f, 1), rest.F(f, 2)};
    int m[3];
    int n = 0;
    for (int k = 0; k < 3; ++k) {
      m[k] = mid[topo.face_edges[f][k]];  // edge v_k → v_{k+1}
      n += m[k] >= 0;
    }
    if (n == 0) {
      add(v[0], v[1], v[2], f);
    } else if (n == 3) {
      add(v[0], m[0], m[2], f);
      add(v[1], m[1], m[0], f);
      add(v[2], m[2], m[1], f);
      add(m[0], m[1], m[2], f);
    } else if (n == 1) {
      int k = m[0] >= 0 ? 0 : (m[1] >= 0 ? 1 : 2);
      const int a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3], x = m[k];
      add(a, x, c, f);
      add(x, b, c, f);
    } else {
      int k = m[0] < 0 ? 0 : (m[1] < 0 ? 1 : 2);  // the unsplit edge a → b
      const int a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
      const int m1 = m[(k + 1) % 3], m2 = m[(k + 2) % 3];  // on b–c and c–a
      add(m2, m1, c, f);
      // Quad a, b, m1, m2: cut along the shorter diagonal on M′.
      if ((dv.row(a) - dv.row(m1)).squaredNorm() <= (dv.row(b) - dv.row(m2)).squaredNorm()) {
        add(a, b, m1, f);
        add(a, m1, m2, f);
      } else {
        add(a, b, m2, f);
        add(b, m1, m2, f);
      }
    }
  }
  Triangles F(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i)
    F.row(static_cast<Eigen::Index>(i)) << faces[i][0], faces[i][1], faces[i][2];
  rest.V = std::move(rv);
  rest.F = F;
  deformed.V = std::move(dv);
  deformed.F = std::move(F);
  return count;
}

namespace {

void check_input(const TriMesh& mesh, const Field& field, const DeformOptions& o) {
  const int nf = mesh.num_faces();
  if (field.size() != nf || static_cast<int>(field.d.size()) != nf ||
      static_cast<int>(field.a.size()) != nf)
    throw Error("field", fmt::format("field has {} entries for {} faces", field.size(), nf));
  if (nf == 0) throw Error("mesh", "no faces to deform");
  if (!mesh.V.allFinite()) throw Error("mesh", "non-finite vertex coordinates");
  if (o.iterations < 0 || o.refine_iterations < 0 || o.max_rounds < 0 || o.max_faces <= 0 ||
      o.membrane_iterations < 0)
    throw Error("metric", "iteration counts and limits must be non-negative");
  if (std::isnan(o.max_edge)) throw Error("metric", "max_edge is NaN");
  if (!std::isfinite(o.bending) || o.bending < 0) throw Error("metric", "bending must be ≥ 0");
  if (!(o.resolve_fraction >= 0 && o.resolve_fraction <= 1))
    throw Error("metric", "resolve_fraction must be in [0, 1]");
  if (!(o.split_ratio > 0 && o.split_ratio <= 1))
    throw Error("metric", "split_ratio must be in (0, 1]");
}

/// The mean edge length of `mesh`.
double mean_edge_length(const TriMesh& mesh) {
  double length = 0;
  const Topology topo = build_topology(mesh);
  for (const auto& [a, b] : topo.edges) length += (mesh.vertex(a) - mesh.vertex(b)).norm();
  return length / std::max(1, topo.num_edges());
}

/// After a refinement round: the field on the new faces (each child carries its parent's values,
/// `parent` per new face) and the new faces' input faces (`parent_face` per old face, updated).
Field children_field(const Field& field, const std::vector<int>& parent,
                     std::vector<int>& parent_face) {
  Field child;
  const std::size_t n = parent.size();
  child.u.resize(n);
  child.d.resize(n);
  child.a.resize(n);
  const bool raw = field.u_raw.size() == field.u.size() && field.d_raw.size() == field.u.size() &&
                   field.a_raw.size() == field.u.size();
  if (raw) {
    child.u_raw.resize(n);
    child.d_raw.resize(n);
    child.a_raw.resize(n);
  }
  const bool coherent = field.coherence.size() == field.u.size();
  if (coherent) child.coherence.resize(n);
  std::vector<int> grand(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int p = parent[i];
    child.u[i] = field.u[p];
    child.d[i] = field.d[p];
    child.a[i] = field.a[p];
    if (raw) {
      child.u_raw[i] = field.u_raw[p];
      child.d_raw[i] = field.d_raw[p];
      child.a_raw[i] = field.a_raw[p];
    }
    if (coherent) child.coherence[i] = field.coherence[p];
    grand[i] = parent_face[p];
  }
  parent_face = std::move(grand);
  return child;
}

}  // namespace

Deformed deform_metric(const TriMesh& mesh, const Field& field, const DeformOptions& o) {
  check_input(mesh, field, o);
  const int nf = mesh.num_faces();
  const bool refine = o.max_edge > 0 && std::isfinite(o.max_edge);

  Deformed out;
  out.rest = mesh;
  out.field = field;
  out.parent_face.resize(nf);
  std::iota(out.parent_face.begin(), out.parent_face.end(), 0);
  out.deformed = mesh;

  Level lv;
  // The regulariser's length h is the input mesh's mean edge length on every level: with the
  // level's own (halving) h the bending weight fell 4× per refinement round and M′ creased on
  // the finer levels (barrel, D = A = 3: 8–16 folded edges along the crown).
  const double bending_length = mean_edge_length(mesh);
  // Initial guess: integrate the target Jacobians in the rest frames (membrane energy only), a
  // few membrane-only iterations to undo its folds, then that shape is the bending reference of
  // the iterations (a fold in the reference would be kept by the regulariser).
  build_level(lv, out.rest, out.field, 0.0, 0.0);
  global_step(lv, out.rest, out.deformed.V, lv.frame);
  out.iterations = 0;
  if (o.bending > 0) {
    const int membrane = std::min(o.membrane_iterations, o.iterations);
    iterate(lv, out.rest, out.deformed.V, membrane);
    out.iterations += membrane;
    build_level(lv, out.rest, out.field, o.bending, bending_length);
    set_reference(lv, out.deformed.V);
  }
  out.residual = iterate(lv, out.rest, out.deformed.V, o.iterations - out.iterations);
  out.iterations = o.iterations;

  while (refine) {
    const double longest = longest_edge(out.deformed);
    if (longest <= o.max_edge) break;
    if (out.rounds >= o.max_rounds)
      throw Error("metric", fmt::format("edges of M' still exceed q = {} after {} rounds "
                                        "(longest {})",
                                        o.max_edge, out.rounds, longest));
    std::vector<int> parent;
    const int edges_before = out.rest.num_faces() * 3 / 2;
    const int split = split_long_edges(out.rest, out.deformed, o.split_ratio * o.max_edge, parent);
    if (out.rest.num_faces() > o.max_faces)
      throw Error("metric", fmt::format("refinement exceeds {} faces (q = {} too small for the "
                                        "surface)",
                                        o.max_faces, o.max_edge));
    out.field = children_field(out.field, parent, out.parent_face);
    ++out.rounds;
    // Midpoint splits keep M′ the same piecewise-linear map and the children carry the parent's
    // target, so the residual is unchanged: a round that split only a few edges is not worth a
    // new factorisation.
    if (split < o.resolve_fraction * edges_before) continue;
    build_level(lv, out.rest, out.field, o.bending, bending_length);
    set_reference(lv, out.deformed.V);
    out.residual = iterate(lv, out.rest, out.deformed.V, o.refine_iterations);
    out.iterations += o.refine_iterations;
    spdlog::debug("metric: round {}: {} faces, residual {:.3g}", out.rounds, out.rest.num_faces(),
                  out.residual);
  }
  out.max_edge = longest_edge(out.deformed);
  if (!out.deformed.V.allFinite()) throw Error("metric", "deformation produced non-finite values");
  out.folded_edges = count_folds(out.deformed);
  spdlog::info(
      "metric: {} → {} faces, {} refinement rounds, {} iterations, residual {:.3g}, "
      "longest edge {:.4g} m, {} folded edges",
      nf, out.rest.num_faces(), out.rounds, out.iterations, out.residual, out.max_edge,
      out.folded_edges);
  return out;
}

Stretch measure_stretch(const TriMesh& rest, const TriMesh& deformed, const Field& field) {
  if (rest.num_faces() != deformed.num_faces() || rest.num_vertices() != deformed.num_vertices() ||
      field.size() != rest.num_faces())
    throw Error("metric", "rest, deformed and field must match");
  Stretch s;
  const int nf = rest.num_faces();
  s.along.resize(nf);
  s.across.resize(nf);
  for (int f = 0; f < nf; ++f) {
    const Vec3 p0 = rest.vertex(rest.F(f, 0)), p1 = rest.vertex(rest.F(f, 1)),
               p2 = rest.vertex(rest.F(f, 2));
    const Mat32 fr = face_frame(p0, p1, p2, field.u[f]);
    Eigen::Matrix2d E;
    E.col(0) = fr.transpose() * (p1 - p0);
    E.col(1) = fr.transpose() * (p2 - p0);
    Mat32 Q;
    Q.col(0) = deformed.vertex(deformed.F(f, 1)) - deformed.vertex(deformed.F(f, 0));
    Q.col(1) = deformed.vertex(deformed.F(f, 2)) - deformed.vertex(deformed.F(f, 0));
    const Mat32 J = Q * E.inverse();
    s.along[f] = J.col(0).norm();
    s.across[f] = J.col(1).norm();
  }
  return s;
}

}  // namespace gridshell
