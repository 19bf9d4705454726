#include "gridshell/fabrication/fabrication.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include <Eigen/Dense>

#include "gridshell/mesh/geometry.h"

namespace gridshell::fabrication {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Newell's vector area of a closed polygon (twice the area times the unit normal, halved).
Vec3 vector_area(const std::vector<Vec3>& p) {
  Vec3 a = Vec3::Zero();
  const std::size_t n = p.size();
  for (std::size_t k = 0; k < n; ++k) a += p[k].cross(p[(k + 1) % n]);
  return 0.5 * a;
}

/// Best-fit plane of points (PCA: the covariance's eigenvector of the smallest eigenvalue).
Plane best_fit_plane(const std::vector<Vec3>& p) {
  Plane pl;
  for (const Vec3& x : p) pl.point += x;
  pl.point /= static_cast<double>(std::max<std::size_t>(1, p.size()));
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const Vec3& x : p) C += (x - pl.point) * (x - pl.point).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
  pl.normal = es.eigenvectors().col(0).normalized();
  return pl;
}

double max_edge_error(const std::vector<Vec2>& q, const std::vector<double>& L) {
  double e = 0;
  const std::size_t n = q.size();
  for (std::size_t k = 0; k < n; ++k)
    if (L[k] > 0) e = std::max(e, std::abs((q[(k + 1) % n] - q[k]).norm() - L[k]) / L[k]);
  return e;
}

/// Rotates and translates the outline: vertex centroid at the origin, first edge along +x.
void normalise_outline(std::vector<Vec2>& q) {
  Vec2 c = Vec2::Zero();
  for (const Vec2& x : q) c += x;
  c /= static_cast<double>(q.size());
  const Vec2 d = q.size() > 1 ? Vec2(q[1] - q[0]) : Vec2(1, 0);
  const double phi = d.norm() > 0 ? std::atan2(d.y(), d.x()) : 0.0;
  const double cs = std::cos(-phi), sn = std::sin(-phi);
  for (Vec2& x : q) {
    const Vec2 y = x - c;
    x = Vec2(cs * y.x() - sn * y.y(), sn * y.x() + cs * y.y());
  }
}

}  // namespace

double panel_planarity(const std::vector<Vec3>& p) {
  if (p.size() < 4) return 0;
  const Plane pl = best_fit_plane(p);
  double dist = 0, perimeter = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    dist += std::abs(pl.signed_distance(p[k]));
    perimeter += (p[(k + 1) % p.size()] - p[k]).norm();
  }
  dist /= static_cast<double>(p.size());
  return perimeter > 0 ? dist / (0.5 * perimeter) : 0;
}

FlatPanel flatten_panel(const std::vector<Vec3>& p, int iterations) {
  FlatPanel f;
  const int n = static_cast<int>(p.size());
  if (n == 0) return f;
  Plane pl = best_fit_plane(p);
  if (pl.normal.dot(vector_area(p)) < 0) pl.normal = -pl.normal;
  // In-plane axes: x along the first edge's projection (or any direction in the plane).
  Vec3 ex = n > 1 ? Vec3(p[1] - p[0]) : Vec3::UnitX();
  ex -= ex.dot(pl.normal) * pl.normal;
  if (ex.norm() < 1e-300) ex = pl.normal.unitOrthogonal();
  ex.normalize();
  const Vec3 ey = pl.normal.cross(ex);
  std::vector<Vec2> q(n);
  for (int k = 0; k < n; ++k) q[k] = Vec2((p[k] - pl.point).dot(ex), (p[k] - pl.point).dot(ey));
  std::vector<double> L(n);
  for (int k = 0; k < n; ++k) L[k] = (p[(k + 1) % n] - p[k]).norm();
  f.planarity = panel_planarity(p);
  for (const Vec3& x : p) f.out_of_plane = std::max(f.out_of_plane, std::abs(pl.signed_distance(x)));
  double err = max_edge_error(q, L);
  // Minimum-norm Gauss–Newton on r_k = |q_{k+1} − q_k| − L_k: restores the edge lengths with
  // the least movement of the projected corners. Only when the projection changed them.
  if (n >= 4 && err > 1e-12) {
    std::vector<Vec2> best = q;
    double best_err = err;
    for (int it = 0; it < iterations && best_err > 1e-13; ++it) {
      Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n, 2 * n);
      Eigen::VectorXd r(n);
      for (int k = 0; k < n; ++k) {
        const int k1 = (k + 1) % n;
        const Vec2 d = q[k1] - q[k];
        const double len = d.norm();
        if (!(len > 0)) break;
        const Vec2 u = d / len;
        r(k) = len - L[k];
        J.block<1, 2>(k, 2 * k1) += u.transpose();
        J.block<1, 2>(k, 2 * k) -= u.transpose();
      }
      const Eigen::VectorXd step = J.completeOrthogonalDecomposition().solve(r);
      for (int k = 0; k < n; ++k) q[k] -= step.segment<2>(2 * k);
      const double e = max_edge_error(q, L);
      if (!std::isfinite(e)) break;
      if (e < best_err) best = q, best_err = e;
    }
    q = best;
    err = best_err;
  }
  if (signed_area_2d(q) < 0) std::reverse(q.begin() + 1, q.end());  // never expected
  normalise_outline(q);
  f.outline = std::move(q);
  f.edge_length_error = err;
  return f;
}

Fabrication fabrication_parts(const PolyMesh& mesh, const Topology& t,
                              const std::vector<int>& supports, const FabricationOptions& o) {
  Fabrication fab;
  const int nv = mesh.num_vertices();
  // Beams, in topology edge order, and their length classes.
  std::vector<long long> key(t.edges.size());
  for (int e = 0; e < t.num_edges(); ++e) {
    Beam b;
    b.id = e;
    b.i = t.edges[e][0];
    b.j = t.edges[e][1];
    b.length = (mesh.vertex(b.j) - mesh.vertex(b.i)).norm();
    b.panels = t.edge_faces[e];
    key[e] = std::llround(b.length / o.length_resolution);
    fab.total_length += b.length;
    fab.beams.push_back(std::move(b));
  }
  std::vector<long long> distinct = key;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  fab.distinct_lengths = static_cast<int>(distinct.size());
  for (auto& b : fab.beams)
    b.length_class = static_cast<int>(
        std::lower_bound(distinct.begin(), distinct.end(), key[b.id]) - distinct.begin());

  // Panels.
  for (int f = 0; f < mesh.num_faces(); ++f) {
    Panel pn;
    pn.id = f;
    pn.joints = mesh.faces[f];
    std::vector<Vec3> c;
    for (int v : pn.joints) c.push_back(mesh.vertex(v));
    pn.area = vector_area(c).norm();
    pn.flat = flatten_panel(c, o.flatten_iterations);
    fab.panels.push_back(std::move(pn));
  }

  // Joints: beams sorted by their angle about the joint's normal.
  std::vector<std::vector<int>> incident(nv);
  for (const auto& b : fab.beams) incident[b.i].push_back(b.id), incident[b.j].push_back(b.id);
  std::vector<char> is_support(nv, 0);
  for (int s : supports)
    if (s >= 0 && s < nv) is_support[s] = 1;
  for (int v = 0; v < nv; ++v) {
    Joint jt;
    jt.id = v;
    jt.position = mesh.vertex(v);
    jt.support = is_support[v];
    jt.valence = static_cast<int>(incident[v].size());
    Vec3 normal = Vec3::Zero();
    for (int f : t.vertex_faces[v]) normal += vector_area([&] {
      std::vector<Vec3> c;
      for (int w : mesh.faces[f]) c.push_back(mesh.vertex(w));
      return c;
    }());
    if (!(normal.norm() > 0)) {
      std::vector<Vec3> pts{jt.position};
      for (int e : incident[v]) pts.push_back(mesh.vertex(fab.beams[e].i + fab.beams[e].j - v));
      normal = pts.size() >= 3 ? best_fit_plane(pts).normal : Vec3::UnitZ();
      if (normal.z() < 0) normal = -normal;
    }
    normal.normalize();
    std::vector<Vec3> dir;
    for (int e : incident[v]) {
      Vec3 d = mesh.vertex(fab.beams[e].i + fab.beams[e].j - v) - jt.position;
      d -= d.dot(normal) * normal;
      dir.push_back(d);
    }
    std::vector<std::pair<double, int>> order;
    if (!dir.empty()) {
      const Vec3 e1 = dir[0].norm() > 0 ? Vec3(dir[0].normalized()) : normal.unitOrthogonal();
      const Vec3 e2 = normal.cross(e1);
      for (std::size_t k = 0; k < dir.size(); ++k) {
        double a = std::atan2(dir[k].dot(e2), dir[k].dot(e1));
        if (a < 0) a += 2 * kPi;
        order.emplace_back(a, incident[v][k]);
      }
      std::sort(order.begin(), order.end());
    }
    for (std::size_t k = 0; k < order.size(); ++k) {
      jt.beams.push_back(order[k].second);
      const double next = k + 1 < order.size() ? order[k + 1].first : order[0].first + 2 * kPi;
      jt.angles_deg.push_back((next - order[k].first) * 180 / kPi);
    }
    fab.joints.push_back(std::move(jt));
  }
  return fab;
}

}  // namespace gridshell::fabrication
