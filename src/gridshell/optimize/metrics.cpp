#include "gridshell/optimize/metrics.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>
#include <Eigen/Eigenvalues>

#include "gridshell/core/error.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

namespace {

double perimeter(const std::vector<Vec3>& p) {
  double s = 0;
  for (std::size_t i = 0; i < p.size(); ++i) s += (p[(i + 1) % p.size()] - p[i]).norm();
  return s;
}

Vec3 vector_area(const std::vector<Vec3>& p) {
  Vec3 a = Vec3::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) a += p[i].cross(p[(i + 1) % p.size()]);
  return 0.5 * a;
}

}  // namespace

FaceFrame face_frame(const std::vector<Vec3>& p) {
  FaceFrame fr;
  const std::size_t n = p.size();
  if (n == 0) return fr;
  Vec3 c = Vec3::Zero();
  for (const Vec3& x : p) c += x;
  c /= static_cast<double>(n);
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const Vec3& x : p) C += (x - c) * (x - c).transpose();
  C /= static_cast<double>(n);
  // Normal: eigenvector of the smallest eigenvalue by the closed form (it is well separated from
  // the in-plane pair for any face worth the name). The in-plane axes and spreads then come from
  // the exact 2 × 2 PCA in that plane: where σ1 ≈ σ2 the 3 × 3 closed form loses ~1e-9 in the
  // axes, this does not. About 3× cheaper than the iterative 3 × 3 solver, which matters in
  // the regularizer's per-face step.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(C);
  Vec3 normal = es.eigenvectors().col(0).normalized();
  const Vec3 area = vector_area(p);
  if (normal.dot(area) < 0) normal = -normal;
  const Vec3 e1 =
      (std::abs(normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(normal).normalized();
  const Vec3 e2 = normal.cross(e1);
  const double cxx = e1.dot(C * e1), cyy = e2.dot(C * e2), cxy = e1.dot(C * e2);
  const double half_diff = 0.5 * (cxx - cyy), mean = 0.5 * (cxx + cyy);
  const double radius = std::hypot(half_diff, cxy);
  const double theta = 0.5 * std::atan2(cxy, half_diff);  // direction of the larger spread
  fr.centroid = c;
  fr.normal = normal;
  fr.axis1 = std::cos(theta) * e1 + std::sin(theta) * e2;
  fr.axis2 = normal.cross(fr.axis1);
  fr.sigma1 = std::sqrt(std::max(0.0, mean + radius));
  fr.sigma2 = std::sqrt(std::max(0.0, mean - radius));
  return fr;
}

double polygon_stretch(const std::vector<Vec3>& p) {
  const FaceFrame fr = face_frame(p);
  if (!(fr.sigma1 > 0)) return 1.0;
  return fr.sigma1 / std::max(fr.sigma2, 1e-6 * fr.sigma1);
}

std::vector<Vec3> regular_targets(const std::vector<Vec3>& p, double max_stretch) {
  if (p.size() < 3) return p;
  return regular_targets(p, face_frame(p), max_stretch);
}

std::vector<Vec3> regular_targets(const std::vector<Vec3>& p, const FaceFrame& fr,
                                  double max_stretch) {
  std::vector<Vec3> out;
  regular_targets(p, fr, max_stretch, out);
  return out;
}

namespace {

/// Vertices (cos 2πi/n, sin 2πi/n) of the unit regular n-gon, tabulated for the usual sizes.
constexpr int kTabulated = 16;
const std::vector<Eigen::Vector2d>& unit_polygon(int n) {
  static const auto table = [] {
    std::vector<std::vector<Eigen::Vector2d>> t(kTabulated + 1);
    for (int m = 3; m <= kTabulated; ++m)
      for (int i = 0; i < m; ++i) {
        const double a = 2 * std::numbers::pi * i / m;
        t[m].emplace_back(std::cos(a), std::sin(a));
      }
    return t;
  }();
  return table[n];
}

}  // namespace

void regular_targets(const std::vector<Vec3>& p, const FaceFrame& fr, double max_stretch,
                     std::vector<Vec3>& out) {
  const int n = static_cast<int>(p.size());
  out.assign(p.begin(), p.end());
  if (n < 3 || !(fr.sigma1 > 0)) return;  // too few or coincident vertices: kept
  const double s1 = fr.sigma1, s2 = std::max(fr.sigma2, 1e-6 * fr.sigma1);
  const double g = std::sqrt(s1 * s2);
  std::vector<Eigen::Vector2d> computed;
  if (n > kTabulated) {
    for (int i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * i / n;
      computed.emplace_back(std::cos(a), std::sin(a));
    }
  }
  const std::vector<Eigen::Vector2d>& e = n > kTabulated ? computed : unit_polygon(n);
  // One pass over the un-stretched 2-D polygon u_i = (x_i g/σ1, y_i g/σ2): its perimeter and the
  // least-squares rotation of the unit template onto it, angle = atan2(Σ e × u, Σ e · u) (the
  // template's radius, perimeter / (2n sin(π/n)), does not change the angle). The template is
  // counter-clockwise, like the frame.
  auto unstretched = [&](int i) {
    const Vec3 d = p[i] - fr.centroid;
    return Eigen::Vector2d(d.dot(fr.axis1) * g / s1, d.dot(fr.axis2) * g / s2);
  };
  const Eigen::Vector2d u0 = unstretched(0);
  Eigen::Vector2d u = u0;
  double per = 0, sdot = 0, scross = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d next = i + 1 < n ? unstretched(i + 1) : u0;
    per += (next - u).norm();
    sdot += e[i].dot(u);
    scross += e[i].x() * u.y() - e[i].y() * u.x();
    u = next;
  }
  const double r = per / (2 * n * std::sin(std::numbers::pi / n));
  const double phi = std::atan2(scross, sdot);
  const double cs = r * std::cos(phi), sn = r * std::sin(phi);
  // Re-stretch: by (σ1, σ2)/σ̄, or with the ratio capped at max_stretch (σ̄ kept).
  double r1 = s1 / g, r2 = s2 / g;
  if (s1 / s2 > max_stretch) {
    r1 = std::sqrt(std::max(max_stretch, 1.0));
    r2 = 1.0 / r1;
  }
  for (int i = 0; i < n; ++i) {
    const double x = cs * e[i].x() - sn * e[i].y(), y = sn * e[i].x() + cs * e[i].y();
    out[i] = fr.centroid + (x * r1) * fr.axis1 + (y * r2) * fr.axis2;
  }
}

std::vector<Vec3> plane_targets(const std::vector<Vec3>& p) {
  const FaceFrame fr = face_frame(p);
  std::vector<Vec3> out(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    out[i] = p[i] - (p[i] - fr.centroid).dot(fr.normal) * fr.normal;
  return out;
}

double polygon_planarity(const std::vector<Vec3>& p) {
  if (p.size() < 3) return 0;
  const FaceFrame fr = face_frame(p);
  double s = 0;
  for (const Vec3& x : p) s += std::abs((x - fr.centroid).dot(fr.normal));
  const double half = 0.5 * perimeter(p);
  return half > 0 ? s / static_cast<double>(p.size()) / half : 0.0;
}

double polygon_regularity(const std::vector<Vec3>& p) {
  if (p.size() < 3) return 0;
  const std::vector<Vec3> t = regular_targets(p);
  double s = 0;
  for (std::size_t i = 0; i < p.size(); ++i) s += (p[i] - t[i]).squaredNorm();
  const double per = perimeter(p);
  const double area = std::max(vector_area(p).norm(), 1e-12 * per * per);
  return area > 0 ? s / area : 0.0;
}

std::vector<Vec3> face_points(const PolyMesh& mesh, int f) {
  const auto& face = mesh.faces[f];
  std::vector<Vec3> p(face.size());
  for (std::size_t i = 0; i < face.size(); ++i) p[i] = mesh.vertex(face[i]);
  return p;
}

MeshMetrics mesh_metrics(const PolyMesh& mesh) {
  const int nf = mesh.num_faces(), nv = mesh.num_vertices();
  for (int f = 0; f < nf; ++f) {
    if (mesh.faces[f].size() < 3) throw Error("mesh", "face with fewer than 3 vertices");
    for (int v : mesh.faces[f])
      if (v < 0 || v >= nv) throw Error("mesh", "face index out of range");
  }
  MeshMetrics m;
  m.planarity.assign(nf, 0.0);
  m.regularity.assign(nf, 0.0);
  tbb::parallel_for(0, nf, [&](int f) {
    const std::vector<Vec3> p = face_points(mesh, f);
    m.planarity[f] = polygon_planarity(p);
    m.regularity[f] = polygon_regularity(p);
  });
  for (int f = 0; f < nf; ++f) {  // serial sums: deterministic
    m.planarity_mean += m.planarity[f];
    m.regularity_mean += m.regularity[f];
    m.planarity_max = std::max(m.planarity_max, m.planarity[f]);
    m.regularity_max = std::max(m.regularity_max, m.regularity[f]);
  }
  if (nf > 0) {
    m.planarity_mean /= nf;
    m.regularity_mean /= nf;
  }
  const Topology topo = build_topology(mesh);
  const int ne = topo.num_edges();
  std::vector<double> len(ne);
  for (int e = 0; e < ne; ++e)
    len[e] = (mesh.vertex(topo.edges[e][0]) - mesh.vertex(topo.edges[e][1])).norm();
  for (double l : len) m.total_length += l;
  if (ne > 0) {
    m.edge_length_mean = m.total_length / ne;
    double var = 0;
    for (double l : len) var += (l - m.edge_length_mean) * (l - m.edge_length_mean);
    var /= ne;
    m.edge_length_cv = m.edge_length_mean > 0 ? std::sqrt(var) / m.edge_length_mean : 0.0;
  }
  return m;
}

}  // namespace gridshell
