// Shell element and solver against closed forms and published benchmarks
// (../shared/reference/benchmarks.md). Meshes are the coarsest that meet the tolerances;
// convergence studies are in bench/shell_bench.cpp and docs/shell.md.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <thread>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "gridshell/core/error.h"
#include "gridshell/fem/shell_element.h"
#include "gridshell/fem/shell_solver.h"
#include "gridshell/field/field.h"
#include "gridshell/io/files.h"
#include "gridshell/io/shell_model_json.h"
#include "gridshell/surfaces/grid.h"
#include "gridshell/surfaces/load.h"
#include "test_support.h"

using namespace gridshell;
using namespace gridshell::fem;

namespace {

constexpr double kPi = std::numbers::pi;

// A structured grid of (nu+1) × (nv+1) nodes mapped by `map(s, t)`, s, t ∈ [0, 1], with each
// cell split into two triangles along alternating diagonals (a symmetric pattern).
template <class Map>
TriMesh grid(int nu, int nv, Map map) {
  return parametric_grid(nu, nv, [&map](double s, double t) { return Vec3(map(s, t)); });
}

int nearest(const TriMesh& m, const Vec3& p) {
  int best = 0;
  for (int v = 1; v < m.num_vertices(); ++v)
    if ((m.vertex(v) - p).norm() < (m.vertex(best) - p).norm()) best = v;
  return best;
}

ShellModel empty_model(const TriMesh& mesh, double E, double nu, double t) {
  ShellModel model;
  model.mesh = mesh;
  model.material.E = E;
  model.material.nu = nu;
  model.thickness = t;
  model.fixed.assign(mesh.num_vertices(), {false, false, false, false, false, false});
  return model;
}

// Scordelis–Lo roof, whole roof, N × N elements per quarter (2N × 2N cells, 2 triangles each).
double scordelis_lo(int N, ShellResult* out = nullptr) {
  const double R = 25, Lr = 50, phi = 40 * kPi / 180;
  TriMesh mesh = grid(2 * N, 2 * N, [&](double s, double t) {
    const double th = -phi + 2 * phi * s;
    return Vec3(R * std::sin(th), Lr * t, R * std::cos(th));
  });
  ShellModel model = empty_model(mesh, 4.32e8, 0.0, 0.25);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double y = mesh.V(v, 1);
    if (std::abs(y) < 1e-9 || std::abs(y - Lr) < 1e-9)
      model.fixed[v][kUx] = model.fixed[v][kUz] = true;
  }
  model.fixed[nearest(mesh, Vec3(0, 0, R))][kUy] = true;  // axial rigid motion only
  ShellLoad q;
  q.kind = ShellLoad::Kind::kSurface;
  q.q = Vec3(0, 0, -90);
  model.loads.push_back(q);
  ShellResult r = solve_shell(model);
  const int v = nearest(mesh, Vec3(R * std::sin(phi), Lr / 2, R * std::cos(phi)));
  if (out) *out = r;
  return -r.displacement(v, kUz);
}

}  // namespace

TEST(ShellElement, OptMembraneRigidModesAndConstantStrain) {
  const Eigen::Vector3d x(0.1, 2.3, 0.7), y(-0.2, 0.4, 1.9);
  const ShellSection s{2e11, 0.3, 0.01};
  const Mat9 K = membrane_opt_stiffness(x, y, s);
  // Rigid modes: translations and an in-plane rotation (with matching drilling rotation).
  Eigen::Matrix<double, 9, 3> rb = Eigen::Matrix<double, 9, 3>::Zero();
  for (int a = 0; a < 3; ++a) {
    rb(3 * a, 0) = 1;
    rb(3 * a + 1, 1) = 1;
    rb(3 * a, 2) = -y(a), rb(3 * a + 1, 2) = x(a), rb(3 * a + 2, 2) = 1;
  }
  EXPECT_LT((K * rb).norm(), 1e-6 * K.norm());
  Eigen::SelfAdjointEigenSolver<Mat9> es(K);
  EXPECT_GT(es.eigenvalues()(3), 1e-6 * es.eigenvalues()(8));  // rank 6
  // Constant strain u = (a x + b y, c x + d y) with drilling = the rigid rotation (c − b)/2:
  // energy = ½ V εᵀ C ε exactly, and the mean strain is recovered.
  const double a = 1e-3, b = 4e-4, c = -2e-4, d = 7e-4;
  Eigen::Matrix<double, 9, 1> u;
  for (int k = 0; k < 3; ++k)
    u.segment<3>(3 * k) << a * x(k) + b * y(k), c * x(k) + d * y(k), (c - b) / 2;
  const Eigen::Vector3d eps(a, d, b + c);
  const double area = 0.5 * ((x(1) - x(0)) * (y(2) - y(0)) - (x(2) - x(0)) * (y(1) - y(0)));
  const double exact = 0.5 * area * s.thickness * eps.dot(plane_stress_matrix(s.E, s.nu) * eps);
  EXPECT_NEAR(0.5 * u.dot(K * u), exact, 1e-10 * exact);
  EXPECT_LT((membrane_opt_mean_strain(x, y, u) - eps).norm(), 1e-12);
}

TEST(ShellElement, DktRigidModesAndConstantCurvature) {
  const Eigen::Vector3d x(0.1, 2.3, 0.7), y(-0.2, 0.4, 1.9);
  const ShellSection s{2e11, 0.3, 0.01};
  const Mat9 K = dkt_stiffness(x, y, s);
  // w = A + B x + C y with rx = ∂w/∂y, ry = −∂w/∂x: no energy.
  Eigen::Matrix<double, 9, 1> u;
  for (int k = 0; k < 3; ++k) u.segment<3>(3 * k) << 1 + 2 * x(k) - 3 * y(k), -3, -2;
  EXPECT_LT((K * u).norm(), 1e-8 * K.norm());
  // w = ½ a x² + b x y + ½ c y²: energy ½ A κᵀ D κ with κ = (a, c, 2b) (patch test).
  const double a = 0.3, b = -0.2, c = 0.5;
  for (int k = 0; k < 3; ++k)
    u.segment<3>(3 * k) << 0.5 * a * x(k) * x(k) + b * x(k) * y(k) + 0.5 * c * y(k) * y(k),
        b * x(k) + c * y(k), -(a * x(k) + b * y(k));
  const double Db = s.E * std::pow(s.thickness, 3) / (12 * (1 - s.nu * s.nu));
  const Eigen::Vector3d kap(a, c, 2 * b);
  Eigen::Matrix3d D;
  D << 1, s.nu, 0, s.nu, 1, 0, 0, 0, (1 - s.nu) / 2;
  const double area = 0.5 * ((x(1) - x(0)) * (y(2) - y(0)) - (x(2) - x(0)) * (y(1) - y(0)));
  const double exact = 0.5 * area * Db * kap.dot(D * kap);
  EXPECT_NEAR(0.5 * u.dot(K * u), exact, 1e-10 * exact);
}

TEST(ShellElement, GlobalStiffnessIsFrameInvariant) {
  // Rotating the facet rotates the stiffness: Q K(Rp) Qᵀ = K(p) for Q = blockdiag(Rᵀ).
  const Vec3 p0(0, 0, 0), p1(1.2, 0.1, 0.3), p2(0.3, 0.9, -0.2);
  const ShellSection s{3e10, 0.2, 0.1};
  const Eigen::Matrix3d Rot = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Mat18 K0 = shell_element_stiffness(p0, p1, p2, s);
  const Mat18 K1 = shell_element_stiffness(Rot * p0, Rot * p1, Rot * p2, s);
  Mat18 Q = Mat18::Zero();
  for (int k = 0; k < 6; ++k) Q.block<3, 3>(3 * k, 3 * k) = Rot;
  EXPECT_LT((Q.transpose() * K1 * Q - K0).norm(), 1e-9 * K0.norm());
}

TEST(ShellSolver, NavierPlate) {
  // Simply supported square plate, uniform load: w_max = 0.00406235 q a⁴ / D (series).
  const double a = 2, t = 0.02, E = 2e11, nu = 0.3, q = 1e3;
  const int N = 12;
  TriMesh mesh = grid(N, N, [&](double s, double u) { return Vec3(a * s, a * u, 0); });
  ShellModel model = empty_model(mesh, E, nu, t);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double x = mesh.V(v, 0), y = mesh.V(v, 1);
    if (x < 1e-9 || y < 1e-9 || x > a - 1e-9 || y > a - 1e-9) model.fixed[v][kUz] = true;
  }
  model.fixed[0][kUx] = model.fixed[0][kUy] = true;
  model.fixed[N][kUy] = true;
  ShellLoad L;
  L.kind = ShellLoad::Kind::kSurface;
  L.q = Vec3(0, 0, -q);
  model.loads.push_back(L);
  const ShellResult r = solve_shell(model);
  const double D = E * t * t * t / (12 * (1 - nu * nu));
  const double w_ref = 0.00406235 * q * std::pow(a, 4) / D;
  const double w = -r.displacement(nearest(mesh, Vec3(a / 2, a / 2, 0)), kUz);
  EXPECT_NEAR(w / w_ref, 1.0, 0.01) << "w = " << w << ", reference " << w_ref;
  std::printf("Navier 12x12: %.12g / %.6g\n", w, w_ref);
  // Equilibrium: the reactions carry the load.
  EXPECT_NEAR(r.reaction_force.z(), q * a * a, 1e-6 * q * a * a);
  EXPECT_NEAR(r.applied_force.z(), -q * a * a, 1e-9 * q * a * a);
}

TEST(ShellSolver, ScordelisLoRoof) {
  // Whole roof, 12 × 12 elements per quarter-equivalent (24 × 24 cells, 1152 triangles).
  ShellResult r;
  const double w = scordelis_lo(12, &r);
  EXPECT_NEAR(w / 0.3024, 1.0, 0.02) << "w = " << w;
  RecordProperty("w", std::to_string(w));
  std::printf("Scordelis-Lo 12x12: %.12g\n", w);
  // Equilibrium of the reactions with the total load 90 · area.
  const double total = 90 * 50 * 25 * (80 * kPi / 180);
  EXPECT_NEAR(-r.applied_force.z() / total, 1.0, 2e-3);  // facet area vs. the true cylinder
  EXPECT_NEAR(r.reaction_force.z(), -r.applied_force.z(), 1e-6 * total);
  EXPECT_NEAR(r.reaction_force.x(), 0, 1e-6 * total);
  EXPECT_NEAR(r.reaction_force.y(), 0, 1e-6 * total);
}

namespace {

// Hemisphere of radius R (z up) with a hole of half-angle `hole` at the pole: nlat × nlon cells
// between the hole and the equator, nlon a multiple of 4. Outward normals.
TriMesh hemisphere(double R, double hole, int nlat, int nlon) {
  return grid(nlon, nlat, [&](double s, double t) {
    const double th = 2 * kPi * s, ph = kPi / 2 - (kPi / 2 - hole) * t;  // ph: polar angle
    return Vec3(R * std::sin(ph) * std::cos(th), R * std::sin(ph) * std::sin(th), R * std::cos(ph));
  });
}

// Welds the seam of a grid that closes on itself in s (first and last columns coincide).
TriMesh weld(const TriMesh& m, double tol) {
  TriMesh out;
  std::vector<int> map(m.num_vertices());
  std::vector<Vec3> pts;
  for (int v = 0; v < m.num_vertices(); ++v) {
    int found = -1;
    for (int w = 0; w < static_cast<int>(pts.size()) && found < 0; ++w)
      if ((pts[w] - m.vertex(v)).norm() < tol) found = w;
    if (found < 0) {
      found = static_cast<int>(pts.size());
      pts.push_back(m.vertex(v));
    }
    map[v] = found;
  }
  out.V.resize(static_cast<int>(pts.size()), 3);
  for (int v = 0; v < static_cast<int>(pts.size()); ++v) out.V.row(v) = pts[v].transpose();
  out.F = m.F;
  for (int f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) out.F(f, k) = map[m.F(f, k)];
  return out;
}

// Spherical cap (radius R, half-angle `cap`) as rings around the apex: ring i has 6 i nodes.
TriMesh spherical_cap(double R, double cap, int rings) {
  std::vector<std::vector<int>> ring(rings + 1);
  std::vector<Vec3> pts{Vec3(0, 0, R)};
  ring[0] = {0};
  for (int i = 1; i <= rings; ++i) {
    const double ph = cap * i / rings;
    for (int j = 0; j < 6 * i; ++j) {
      const double th = 2 * kPi * j / (6 * i);
      ring[i].push_back(static_cast<int>(pts.size()));
      pts.emplace_back(R * std::sin(ph) * std::cos(th), R * std::sin(ph) * std::sin(th),
                       R * std::cos(ph));
    }
  }
  std::vector<std::array<int, 3>> tris;
  for (int i = 1; i <= rings; ++i) {
    // Stitch ring i−1 (m nodes) and ring i (k nodes) by advancing on the azimuth.
    const auto& A = ring[i - 1];
    const auto& B = ring[i];
    const int ma = static_cast<int>(A.size()), kb = static_cast<int>(B.size());
    if (ma == 1) {
      for (int j = 0; j < kb; ++j) tris.push_back({A[0], B[j], B[(j + 1) % kb]});
      continue;
    }
    int ia = 0, ib = 0;
    while (ia < ma || ib < kb) {
      const double ta = (ia + 1.0) / ma, tb = (ib + 1.0) / kb;
      if (ib < kb && (ia >= ma || tb <= ta)) {
        tris.push_back({A[ia % ma], B[ib], B[(ib + 1) % kb]});
        ++ib;
      } else {
        tris.push_back({A[ia], B[ib % kb], A[(ia + 1) % ma]});
        ++ia;
      }
    }
  }
  TriMesh m;
  m.V.resize(static_cast<int>(pts.size()), 3);
  for (int v = 0; v < static_cast<int>(pts.size()); ++v) m.V.row(v) = pts[v].transpose();
  m.F.resize(static_cast<int>(tris.size()), 3);
  for (int f = 0; f < static_cast<int>(tris.size()); ++f)
    m.F.row(f) << tris[f][0], tris[f][1], tris[f][2];
  return m;
}

}  // namespace

TEST(ShellSolver, PinchedHemisphere) {
  // Whole hemisphere, 18° hole, 24 × 24 elements per quarter (16 × 16 gives 0.0873); loads of 2
  // (the quarter-model 1.0 on each symmetry plane), outward on x, inward on y. Six statically
  // determinate restraints.
  const double R = 10;
  const int N = 24;
  TriMesh mesh = weld(hemisphere(R, 18 * kPi / 180, N, 4 * N), 1e-9);
  ShellModel model = empty_model(mesh, 6.825e7, 0.3, 0.04);
  const int A = nearest(mesh, Vec3(R, 0, 0)), B = nearest(mesh, Vec3(-R, 0, 0));
  const int C = nearest(mesh, Vec3(0, R, 0)), D = nearest(mesh, Vec3(0, -R, 0));
  model.fixed[A][kUy] = model.fixed[A][kUz] = true;
  model.fixed[B][kUy] = model.fixed[B][kUz] = true;
  model.fixed[C][kUx] = model.fixed[C][kUz] = true;
  auto force = [&](int v, Vec3 F) {
    ShellLoad L;
    L.node = v;
    L.force = F;
    model.loads.push_back(L);
  };
  force(A, Vec3(2, 0, 0));
  force(B, Vec3(-2, 0, 0));
  force(C, Vec3(0, -2, 0));
  force(D, Vec3(0, 2, 0));
  const ShellResult r = solve_shell(model);
  const double w = 0.5 * (r.displacement(A, kUx) - r.displacement(B, kUx));
  std::printf("Pinched hemisphere 24x24: %.12g\n", w);
  EXPECT_NEAR(w / 0.094, 1.0, 0.05) << "w = " << w;
  EXPECT_NEAR(0.5 * (r.displacement(D, kUy) - r.displacement(C, kUy)), w, 0.02 * w);  // symmetry
  EXPECT_LT(r.reaction.norm(), 1e-6);  // self-equilibrated load, determinate restraints
}

// Concurrent factorisations from several threads (a parallel design sweep) must give the bits
// of a serial run. This tests the BLAS that libblas.so.3 points to: Debian's serial OpenBLAS
// 0.3.21 is not thread-safe (built without USE_LOCKING) and fails here with false pivots or wrong
// digits; reference BLAS and BLIS pass.
namespace {

// Hemisphere (R = 10, 18° hole) pinned at its equator under a projected load: 4608 facets,
// 13 824 dofs, supernodes large enough for BLAS level 3.
ShellModel loaded_hemisphere() {
  const int N = 24;
  TriMesh mesh = weld(hemisphere(10, 18 * kPi / 180, N, 4 * N), 1e-9);
  ShellModel model = empty_model(mesh, 6.825e7, 0.3, 0.04);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (std::abs(mesh.V(v, 2)) < 1e-9) model.fixed[v] = {true, true, true, false, false, false};
  ShellLoad q;
  q.kind = ShellLoad::Kind::kProjected;
  q.q = Vec3(0, 0, -1e3);
  model.loads.push_back(q);
  return model;
}

}  // namespace

TEST(ShellSolver, ConcurrentSolvesAreIdenticalToASerialOne) {
  const ShellModel model = loaded_hemisphere();
  const Eigen::MatrixXd serial = solve_shell(model).displacement;
  ASSERT_GT(serial.cwiseAbs().maxCoeff(), 0);
  constexpr int kThreads = 4, kRepeats = 2;
  std::vector<std::string> errors(kThreads);
  std::vector<int> identical(kThreads, 0);
  std::vector<std::thread> pool;
  for (int t = 0; t < kThreads; ++t)
    pool.emplace_back([&, t] {
      for (int k = 0; k < kRepeats; ++k) try {
          identical[t] += solve_shell(model).displacement == serial ? 1 : 0;
        } catch (const std::exception& e) {
          errors[t] = e.what();
        }
    });
  for (auto& th : pool) th.join();
  for (int t = 0; t < kThreads; ++t) {
    EXPECT_EQ(errors[t], "") << "thread " << t;
    EXPECT_EQ(identical[t], kRepeats) << "thread " << t << ": solutions differ from the serial one";
  }
}

TEST(ShellSolver, SphericalCapMembraneState) {
  // Cap R = 10, half-angle 30°, t = 0.02, external pressure p: away from the pinned edge the
  // membrane state is isotropic, N = −p R / 2. 24 rings (3 456 facets); 16 rings miss by 2.7%.
  const double R = 10, t = 0.02, p = 1e3;
  TriMesh mesh = spherical_cap(R, 30 * kPi / 180, 24);
  ShellModel model = empty_model(mesh, 2e11, 0.3, t);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (mesh.V(v, 2) < R * std::cos(30 * kPi / 180) + 1e-9)
      for (int k = 0; k < 3; ++k) model.fixed[v][k] = true;
  ShellLoad L;
  L.kind = ShellLoad::Kind::kPressure;
  L.p = p;
  model.loads.push_back(L);
  const ShellResult r = solve_shell(model);
  const double ref = -p * R / (2 * t);
  int count = 0;
  double worst = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    Vec3 c = Vec3::Zero();
    for (int k = 0; k < 3; ++k) c += mesh.vertex(mesh.F(f, k)) / 3;
    if (std::acos(c.normalized().z()) > 12 * kPi / 180) continue;
    ++count;
    worst =
        std::max({worst, std::abs(r.stress[f].s1 / ref - 1), std::abs(r.stress[f].s2 / ref - 1)});
  }
  std::printf("Spherical cap: %d facets, worst relative error %.12g\n", count, worst);
  EXPECT_GT(count, 50);
  EXPECT_LT(worst, 0.01);
  // Equilibrium: vertical reactions = p × plan area of the cap.
  const double a = R * std::sin(30 * kPi / 180);
  EXPECT_NEAR(r.reaction_force.z() / (p * kPi * a * a), 1.0, 0.01);
  EXPECT_NEAR((r.reaction_force + r.applied_force).norm(), 0, 1e-8 * p * a * a);
}

TEST(ShellSolver, MechanismsAreRefusedWithTheFreeMotion) {
  TriMesh mesh = grid(4, 4, [](double s, double u) { return Vec3(s, u, 0.1 * s * u); });
  ShellModel model = empty_model(mesh, 1e9, 0.3, 0.01);
  ShellLoad L;
  L.kind = ShellLoad::Kind::kSurface;
  L.q = Vec3(0, 0, -1);
  model.loads.push_back(L);
  try {
    solve_shell(model);
    FAIL() << "no supports accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("translation along x"), std::string::npos) << e.what();
  }
  // Pinned along the edge y = 0 only: the plate rotates about that edge (axis along x).
  for (int i = 0; i <= 4; ++i)
    for (int k = 0; k < 3; ++k) model.fixed[i][k] = true;
  try {
    solve_shell(model);
    FAIL() << "hinge line accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("rotation about an axis along x through (0.5, 0,"),
              std::string::npos)
        << e.what();
  }
  // A second pinned edge makes it stable, and the answer is finite.
  for (int i = 20; i <= 24; ++i)
    for (int k = 0; k < 3; ++k) model.fixed[i][k] = true;
  const ShellResult r = solve_shell(model);
  EXPECT_TRUE(r.displacement.allFinite());
  EXPECT_GT(r.max_displacement, 0);
}

namespace {

// A 2 × 2 m plate MODEL.json (4 × 4 cells), simply supported, 1 kN/m² plan load.
nlohmann::json plate_model_json(bool supports) {
  const int N = 4;
  TriMesh m = grid(N, N, [](double s, double u) { return Vec3(2 * s, 2 * u, 0); });
  nlohmann::json j;
  for (int v = 0; v < m.num_vertices(); ++v)
    j["nodes"].push_back({m.V(v, 0), m.V(v, 1), m.V(v, 2)});
  for (int f = 0; f < m.num_faces(); ++f)
    j["triangles"].push_back({m.F(f, 0), m.F(f, 1), m.F(f, 2)});
  j["thickness"] = 0.02;
  j["materials"]["steel"] = {{"E", 2e11}, {"nu", 0.3}, {"density", 7850}};
  j["supports"] = nlohmann::json::array();
  if (supports)
    for (int v = 0; v < m.num_vertices(); ++v) {
      const double x = m.V(v, 0), y = m.V(v, 1);
      if (x < 1e-9 || y < 1e-9 || x > 2 - 1e-9 || y > 2 - 1e-9)
        j["supports"].push_back(
            {{"node", v}, {"fix", v == 0 ? nlohmann::json("pinned") : nlohmann::json({"uz"})}});
    }
  if (supports) j["supports"].push_back({{"node", N}, {"fix", {"uy"}}});
  j["loads"] = {{{"type", "projected"}, {"q", {0, 0, -1000}}},
                {{"node", 12}, {"force", {0, 0, -50}}}};
  return j;
}

}  // namespace

TEST(ShellCli, ModelJsonMatchesTheLibrary) {
  const auto dir = test::temp_dir("shell_model");
  const auto model_path = dir / "plate.json";
  std::ofstream(model_path) << plate_model_json(true).dump();
  const ShellModel model = io::read_shell_model(model_path);
  EXPECT_EQ(model.loads.size(), 2u);
  EXPECT_TRUE(model.fixed[0][kUx] && model.fixed[0][kUz] && !model.fixed[0][kRx]);
  const ShellResult r = solve_shell(model);
  EXPECT_NEAR(r.reaction_force.z(), 4000 + 50, 1e-6);
  const auto run = test::run_gridshell("stress '" + model_path.string() + "' -o '" +
                                       (dir / "out").string() + "' --quiet");
  ASSERT_EQ(run.status, 0) << run.err;
  const auto rep = nlohmann::json::parse(io::read_file(dir / "out" / "report.json"));
  EXPECT_NEAR(rep["shell"]["max_displacement_m"].get<double>(), r.max_displacement,
              1e-12 * r.max_displacement);
  EXPECT_EQ(rep["shell"]["max_displacement_vertex"].get<int>(), r.max_displacement_vertex);
  // The stages run one after the other (the ordering, beside the assembly, is not listed), so
  // they add up to no more than the total.
  const nlohmann::json& t = rep.at("timings_s");
  double stages = 0;
  for (const char* stage : {"read", "assemble", "factorize", "solve", "stress", "write"}) {
    ASSERT_TRUE(t.contains(stage)) << stage;
    EXPECT_GE(t.at(stage).get<double>(), 0) << stage;
    stages += t.at(stage).get<double>();
  }
  EXPECT_FALSE(t.contains("order"));
  EXPECT_LE(stages, t.at("total").get<double>());
  for (const char* f : {"displacements.csv", "stress.csv", "shell.vtp", "config.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / f)) << f;
  // stress.csv: header + one row per triangle, s1 ≥ s2.
  std::ifstream in(dir / "out" / "stress.csv");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "face,s1,s2,d1x,d1y,d1z,d2x,d2y,d2z");
  int rows = 0;
  while (std::getline(in, line)) {
    double s1 = 0, s2 = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%*d,%lf,%lf", &s1, &s2), 2) << line;
    EXPECT_GE(s1, s2);
    ++rows;
  }
  EXPECT_EQ(rows, model.mesh.num_faces());
}

TEST(ShellCli, MechanismAndBadModelExitTwo) {
  const auto dir = test::temp_dir("shell_bad");
  std::ofstream(dir / "free.json") << plate_model_json(false).dump();
  auto run = test::run_gridshell("stress '" + (dir / "free.json").string() + "' -o '" +
                                 (dir / "o1").string() + "' --quiet");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("mechanism"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("translation along x"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "o1" / "displacements.csv"));
  nlohmann::json j = plate_model_json(true);
  j["triangles"][3] = {0, 1, 999};
  std::ofstream(dir / "bad.json") << j.dump();
  run = test::run_gridshell("stress '" + (dir / "bad.json").string() + "' -o '" +
                            (dir / "o2").string() + "' --quiet");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("triangles[3]"), std::string::npos) << run.err;
}

TEST(ShellCli, SurfaceWithDefaults) {
  const auto dir = test::temp_dir("shell_surface");
  const auto run = test::run_gridshell("stress builtin:dome:res=10 -o '" + dir.string() +
                                       "' --quiet --thickness 0.08 --load 2");
  ASSERT_EQ(run.status, 0) << run.err;
  const auto rep = nlohmann::json::parse(io::read_file(dir / "report.json"));
  EXPECT_DOUBLE_EQ(rep["shell"]["thickness_m"].get<double>(), 0.08);
  // Equilibrium: the vertical reactions carry 2 kN/m² over the plan area.
  const double applied = rep["shell"]["applied_force_N"][2].get<double>();
  const double reacted = rep["shell"]["reaction_force_N"][2].get<double>();
  EXPECT_LT(applied, 0);
  EXPECT_NEAR(reacted, -applied, 1e-8 * std::abs(applied));
  // The load's size: 2 kN/m² times the plan area of the surface (its triangles projected on
  // the xy plane), computed here independently.
  const Surface dome = load_surface("builtin:dome:res=10");
  double plan = 0;
  for (int f = 0; f < dome.mesh.num_faces(); ++f) {
    const Vec3 a = dome.mesh.vertex(dome.mesh.F(f, 0)), b = dome.mesh.vertex(dome.mesh.F(f, 1)),
               c = dome.mesh.vertex(dome.mesh.F(f, 2));
    plan += 0.5 * std::abs((b - a).cross(c - a).z());
  }
  EXPECT_NEAR(applied, -2e3 * plan, 1e-9 * 2e3 * plan);
  const auto cfg = nlohmann::json::parse(io::read_file(dir / "config.json"));
  EXPECT_EQ(cfg["command"], "stress");
  // The run repeats from its config.json.
  const auto again = test::run_gridshell("stress --config '" + (dir / "config.json").string() +
                                         "' --out '" + (dir / "again").string() + "'");
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(io::read_file(dir / "stress.csv"), io::read_file(dir / "again" / "stress.csv"));
}

TEST(ShellCli, IdenticalOutputForAnyThreadCount) {
  const auto dir = test::temp_dir("shell_threads");
  for (int t : {1, 2}) {
    const auto run =
        test::run_gridshell(fmt::format("stress builtin:barrel:res=16 -o '{}' --quiet --threads {}",
                                        (dir / std::to_string(t)).string(), t));
    ASSERT_EQ(run.status, 0) << run.err;
  }
  for (const char* f : {"displacements.csv", "stress.csv"})
    EXPECT_EQ(io::read_file(dir / "1" / f), io::read_file(dir / "2" / f)) << f;
}

TEST(ShellSolver, ZeroPivotIsReportedWithItsDof) {
  // Without the rigid-body check, the factorisation itself names the singular dof.
  TriMesh mesh = grid(2, 2, [](double s, double u) { return Vec3(s, u, 0); });
  ShellModel model = empty_model(mesh, 1e9, 0.3, 0.01);
  ShellOptions options;
  options.check_mechanism = false;
  try {
    solve_shell(model, options);
    FAIL() << "singular model accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("singular at vertex"), std::string::npos) << e.what();
  }
  // An unreferenced vertex is held, not a mechanism.
  mesh.V.conservativeResize(mesh.num_vertices() + 1, 3);
  mesh.V.row(mesh.num_vertices() - 1) << 5, 5, 5;
  model = empty_model(mesh, 1e9, 0.3, 0.01);
  for (int v = 0; v < 9; ++v)
    if (mesh.V(v, 0) < 1e-9 || mesh.V(v, 0) > 1 - 1e-9)
      for (int k = 0; k < 6; ++k) model.fixed[v][k] = true;
  ShellLoad L;
  L.node = 4;
  L.force = Vec3(0, 0, -1);
  model.loads.push_back(L);
  const ShellResult r = solve_shell(model);
  EXPECT_EQ(r.displacement.row(9).norm(), 0.0);
  EXPECT_LT(r.displacement(4, kUz), 0);
}

TEST(ShellSolver, SplitFactorisationMatchesTheMonolithicOne) {
  // fem/split_cholesky.h: two halves and a dense separator, factorised on two threads. Same
  // hemisphere as the concurrency test, forced through the split path.
  const ShellModel model = loaded_hemisphere();
  ShellOptions mono;
  mono.split_min_dofs = 1 << 30;
  ShellOptions split;
  split.split_min_dofs = 0;
  const ShellResult a = solve_shell(model, mono);
  const ShellResult b = solve_shell(model, split);
  EXPECT_EQ(a.ordering, "metis-nodes");
  ASSERT_EQ(b.ordering, "split-metis-nodes");
  const double scale = a.displacement.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0);
  EXPECT_LT((a.displacement - b.displacement).cwiseAbs().maxCoeff(), 1e-9 * scale);
  EXPECT_NEAR(a.reaction_force.z(), b.reaction_force.z(), 1e-9 * std::abs(a.reaction_force.z()));
  // Same bits every time, whatever runs beside it.
  std::vector<Eigen::MatrixXd> again(2);
  std::thread t1([&] { again[0] = solve_shell(model, split).displacement; });
  std::thread t2([&] { again[1] = solve_shell(model, split).displacement; });
  t1.join();
  t2.join();
  EXPECT_EQ(again[0], b.displacement);
  EXPECT_EQ(again[1], b.displacement);
}

TEST(ShellSolver, SplitFactorisationReportsTheSingularDof) {
  // No supports at all and no rigid-body check: one of the halves (or the separator) meets the
  // zero pivot first; either way the error names a vertex and dof.
  TriMesh mesh = grid(24, 24, [](double s, double u) { return Vec3(s, u, 0.2 * s * u); });
  ShellModel model = empty_model(mesh, 1e9, 0.3, 0.01);
  ShellOptions options;
  options.check_mechanism = false;
  options.split_min_dofs = 0;
  try {
    solve_shell(model, options);
    FAIL() << "singular model accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("singular at vertex"), std::string::npos) << e.what();
  }
}

TEST(ShellSolver, SplitFactorisationOfTwoSeparatePieces) {
  // Two plates that do not touch: the node graph is disconnected, so the separator may be empty
  // (then the solver falls back to one factorisation) or cut one piece. Either way the answer is
  // the monolithic one.
  TriMesh a = grid(30, 30, [](double s, double u) { return Vec3(s, u, 0.1 * s * u); });
  TriMesh b = grid(20, 20, [](double s, double u) { return Vec3(s + 3, u, 0.1 * s * (1 - u)); });
  TriMesh mesh;
  mesh.V.resize(a.num_vertices() + b.num_vertices(), 3);
  mesh.V << a.V, b.V;
  mesh.F.resize(a.num_faces() + b.num_faces(), 3);
  mesh.F << a.F, (b.F.array() + a.num_vertices()).matrix();
  ShellModel model = empty_model(mesh, 2e11, 0.3, 0.01);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double x = mesh.V(v, 0);
    if (std::abs(x) < 1e-9 || std::abs(x - 3) < 1e-9)
      for (int k = 0; k < 6; ++k) model.fixed[v][k] = true;
  }
  ShellLoad q;
  q.kind = ShellLoad::Kind::kSurface;
  q.q = Vec3(0, 0, -1e3);
  model.loads.push_back(q);
  ShellOptions mono, split;
  mono.split_min_dofs = 1 << 30;
  split.split_min_dofs = 0;
  const ShellResult r1 = solve_shell(model, mono), r2 = solve_shell(model, split);
  std::printf("[figures] two separate plates, split path: %s\n", r2.ordering.c_str());
  const double scale = r1.displacement.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0);
  EXPECT_LT((r1.displacement - r2.displacement).cwiseAbs().maxCoeff(), 1e-9 * scale) << r2.ordering;
}

// A closed-ended cylinder under internal pressure p (radius R, wall t): away from its ends the
// membrane state is hoop σθ = pR/t and axial σz = pR/(2t) — the classic anisotropic closed form
// (hoop = 2 × axial). The ends: z = 0 held axially (three tangential fixities stop the rigid
// motions, radial growth stays free), the end cap's resultant p·πR² pulls the ring at z = L.
// The field stage reads it as u along the hoop and a raw anisotropy of 2.
TEST(ShellSolver, PressurisedCylinderHoopIsTwiceAxial) {
  const int nt = 64, nz = 32;
  const double R = 1.0, L = 4.0, t = 0.01, p = 1e5;
  ShellModel model;
  model.thickness = t;
  model.mesh.V.resize(nt * (nz + 1), 3);
  for (int j = 0; j <= nz; ++j)
    for (int i = 0; i < nt; ++i) {
      const double th = 2 * std::numbers::pi * i / nt;
      model.mesh.V.row(j * nt + i) << R * std::cos(th), R * std::sin(th), L * j / nz;
    }
  model.mesh.F.resize(2 * nt * nz, 3);
  for (int j = 0, f = 0; j < nz; ++j)
    for (int i = 0; i < nt; ++i) {
      const int a = j * nt + i, b = j * nt + (i + 1) % nt, c = a + nt, d = b + nt;
      model.mesh.F.row(f++) << a, b, d;  // outward normals (counter-clockwise seen from outside)
      model.mesh.F.row(f++) << a, d, c;
    }
  model.fixed.assign(model.mesh.num_vertices(), {false, false, false, false, false, false});
  for (int i = 0; i < nt; ++i) model.fixed[i][kUz] = true;
  model.fixed[0][kUy] = true;           // θ = 0
  model.fixed[nt / 4][kUx] = true;      // θ = 90°
  model.fixed[nt / 2][kUy] = true;      // θ = 180°
  ShellLoad pressure;
  pressure.kind = ShellLoad::Kind::kPressure;
  pressure.p = -p;  // force −p·n·area with outward n: outward for p < 0
  model.loads.push_back(pressure);
  for (int i = 0; i < nt; ++i) {
    ShellLoad cap;
    cap.node = nz * nt + i;
    cap.force = Vec3(0, 0, p * std::numbers::pi * R * R / nt);
    model.loads.push_back(cap);
  }
  const ShellResult r = solve_shell(model);
  int checked = 0;
  for (int f = 0; f < model.mesh.num_faces(); ++f) {
    const Vec3 c = test::centroid(model.mesh, f);
    if (c.z() < 1 || c.z() > L - 1) continue;
    ++checked;
    const PrincipalStress& s = r.stress[f];
    EXPECT_NEAR(s.s1 / (p * R / t), 1.0, 0.01) << f;
    EXPECT_NEAR(s.s2 / (p * R / (2 * t)), 1.0, 0.02) << f;
    EXPECT_LT(std::abs(s.d1.z()), 0.02) << f;  // the hoop direction
  }
  EXPECT_GT(checked, nt * nz / 3);
  FieldOptions fo;
  fo.coherence_exponent = 0;
  const Field fd = make_field(model.mesh, r.stress, fo);
  for (int f = 0; f < model.mesh.num_faces(); ++f) {
    const Vec3 c = test::centroid(model.mesh, f);
    if (c.z() < 1 || c.z() > L - 1) continue;
    EXPECT_NEAR(fd.a_raw[f], 2.0, 0.05) << f;
    EXPECT_LT(std::abs(fd.u_raw[f].z()), 0.02) << f;
  }
}
