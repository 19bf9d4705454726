#include "gridshell/pipeline/design.h"

#include <chrono>
#include <cmath>
#include <numbers>

#include <spdlog/spdlog.h>
#include <Eigen/Eigenvalues>

#include "gridshell/core/error.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

FaceMetrics face_metrics(const PolyMesh& mesh) {
  FaceMetrics m;
  int counted = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto& face = mesh.faces[f];
    const int n = static_cast<int>(face.size());
    if (n < 3) continue;
    Vec3 c = Vec3::Zero();
    for (int v : face) c += mesh.vertex(v);
    c /= n;
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    double perimeter = 0;
    for (int k = 0; k < n; ++k) {
      const Vec3 d = mesh.vertex(face[k]) - c;
      C += d * d.transpose();
      perimeter += (mesh.vertex(face[(k + 1) % n]) - mesh.vertex(face[k])).norm();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
    const Vec3 normal = es.eigenvectors().col(0);
    // Orient the in-plane frame so that the face runs counter-clockwise around the normal.
    Vec3 e1 = es.eigenvectors().col(2);
    Vec3 area_vec = Vec3::Zero();
    for (int k = 0; k < n; ++k)
      area_vec += mesh.vertex(face[k]).cross(mesh.vertex(face[(k + 1) % n]));
    Vec3 nz = area_vec.dot(normal) >= 0 ? normal : Vec3(-normal);
    Vec3 e2 = nz.cross(e1);
    double dist = 0;
    std::vector<Eigen::Vector2d> q(n);
    for (int k = 0; k < n; ++k) {
      const Vec3 d = mesh.vertex(face[k]) - c;
      dist += std::abs(d.dot(nz));
      q[k] = {d.dot(e1), d.dot(e2)};
    }
    if (perimeter <= 0) continue;
    m.planarity_mean += (dist / n) / (0.5 * perimeter);
    // Regular n-gon of the same perimeter, best rotation over the n cyclic correspondences.
    const double rho = perimeter / (2 * n * std::sin(std::numbers::pi / n));
    double best = std::numeric_limits<double>::infinity();
    double qq = 0;
    for (const auto& p : q) qq += p.squaredNorm();
    for (int s = 0; s < n; ++s) {
      double dot = 0, crs = 0;
      for (int k = 0; k < n; ++k) {
        const double a = 2 * std::numbers::pi * ((k + s) % n) / n;
        const Eigen::Vector2d t(rho * std::cos(a), rho * std::sin(a));
        dot += t.dot(q[k]);
        crs += t.x() * q[k].y() - t.y() * q[k].x();
      }
      // min over rotations of Σ|q − R t|² = Σ|q|² + n ρ² − 2 |(dot, crs)|.
      best = std::min(best, qq + n * rho * rho - 2 * std::hypot(dot, crs));
    }
    const double area = 0.5 * area_vec.norm();
    if (area > 0) m.regularity_mean += std::max(0.0, best) / area;
    ++counted;
  }
  if (counted > 0) {
    m.planarity_mean /= counted;
    m.regularity_mean /= counted;
  }
  return m;
}

DesignResult run_design(const Surface& surface, const DesignOptions& o) {
  if (o.field == "stress")
    throw Error("--field",
                "stress is not available yet (it comes with the stress-field stage); use --field "
                "uniform");
  if (o.field != "uniform") throw Error("--field", "unknown field '" + o.field + "' (uniform)");
  if (o.D != 1) throw Error("-D", "only 1 is allowed until the stress-field stage lands");
  if (o.A != 1) throw Error("-A", "only 1 is allowed until the stress-field stage lands");
  if (o.analyze != "none")
    throw Error("--analyze", "'" + o.analyze + "' is not available yet (only none)");
  DesignResult r;
  using clock = std::chrono::steady_clock;
  auto t0 = clock::now();
  // Field: uniform, so the deformed surface M' is M itself.
  const TriMesh& deformed = surface.mesh;
  r.timings.emplace_back("field", std::chrono::duration<double>(clock::now() - t0).count());
  spdlog::info("design: tessellating ({} triangles, {} supports)", surface.mesh.num_faces(),
               surface.supports.size());
  t0 = clock::now();
  r.raw = tessellate(surface.mesh, deformed, surface.supports, o.tessellation);
  r.timings.emplace_back("tessellation", std::chrono::duration<double>(clock::now() - t0).count());
  spdlog::info("design: {} cells, {} joints, R = {:.4g} m, {} Lloyd iterations{}, hexagons {:.1f}%",
               r.raw.mesh.num_faces(), r.raw.mesh.num_vertices(), r.raw.radius, r.raw.iterations,
               r.raw.converged ? "" : " (not converged)", 100 * r.raw.quality.hex_share_interior);
  t0 = clock::now();
  r.mesh = r.raw.mesh;  // regularization lands with the optimize module
  r.supports = r.raw.supports;
  r.d_target.assign(r.mesh.num_faces(), 1.0);
  r.a_target.assign(r.mesh.num_faces(), 1.0);
  r.metrics = face_metrics(r.mesh);
  r.timings.emplace_back("regularization",
                         std::chrono::duration<double>(clock::now() - t0).count());
  return r;
}

}  // namespace gridshell
