// Built-in surfaces: valid meshes with the expected topology and supports; the funicular shell is
// a true force-density equilibrium.

#include <gtest/gtest.h>

#include "gridshell/mesh/topology.h"
#include "gridshell/surfaces/builtin.h"
#include "gridshell/surfaces/force_density.h"
#include "gridshell/surfaces/load.h"
#include "test_support.h"

using namespace gridshell;

namespace {
struct Expect {
  const char* spec;
  int loops;
  int euler;
};
}  // namespace

TEST(Builtin, EveryBuiltinIsAValidSurface) {
  const Expect cases[] = {{"paraboloid", 1, 1},
                          {"dome", 1, 1},
                          {"barrel", 1, 1},
                          {"court", 2, 0},
                          {"funicular", 1, 1},
                          {"dome:span=30,rise=4,res=10", 1, 1},
                          {"court:res=16,hole=3", 2, 0}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.spec);
    Surface s = make_builtin(std::string(c.spec));
    PolyMesh p = to_poly(s.mesh);
    MeshProblems problems = check_mesh(p);
    EXPECT_TRUE(problems.ok()) << (problems.describe().empty() ? "" : problems.describe()[0]);
    Topology t = build_topology(p);
    EXPECT_EQ(static_cast<int>(t.boundary_loops.size()), c.loops);
    EXPECT_EQ(euler_characteristic(p, t), c.euler);
    EXPECT_FALSE(s.supports.empty());
    // Faces are oriented with normals up (roofs).
    for (int f = 0; f < s.mesh.num_faces(); ++f) {
      Vec3 a = s.mesh.vertex(s.mesh.F(f, 0)), b = s.mesh.vertex(s.mesh.F(f, 1)),
           cc = s.mesh.vertex(s.mesh.F(f, 2));
      ASSERT_GT((b - a).cross(cc - a).z(), 0) << "face " << f;
    }
  }
}

TEST(Builtin, ShapesMatchTheirDefinitions) {
  // Dome: every vertex on the sphere through the rim and the crown.
  BuiltinOptions o;
  o.span = 20;
  o.rise = 5;
  Surface dome = make_builtin("dome", o);
  const double R = (100.0 + 25.0) / 10.0;  // (a² + h²) / 2h
  for (int v = 0; v < dome.mesh.num_vertices(); ++v) {
    Vec3 p = dome.mesh.vertex(v);
    EXPECT_NEAR((p - Vec3(0, 0, 5 - R)).norm(), R, 1e-9);
  }
  EXPECT_NEAR(dome.mesh.V.col(2).maxCoeff(), 5.0, 1e-12);
  // Paraboloid: z = rise (1 − (x² + y²)/(2h²)).
  Surface par = make_builtin("paraboloid", o);
  for (int v = 0; v < par.mesh.num_vertices(); ++v) {
    Vec3 p = par.mesh.vertex(v);
    EXPECT_NEAR(p.z(), 5 * (1 - (p.x() * p.x() + p.y() * p.y()) / 200.0), 1e-12);
  }
  // Barrel: supports are exactly the ground vertices (z = 0).
  Surface barrel = make_builtin("barrel", o);
  for (int v : barrel.supports) EXPECT_NEAR(barrel.mesh.V(v, 2), 0.0, 1e-9);
  int ground = 0;
  for (int v = 0; v < barrel.mesh.num_vertices(); ++v)
    ground += std::abs(barrel.mesh.V(v, 2)) < 1e-9;
  EXPECT_EQ(ground, static_cast<int>(barrel.supports.size()));
  // Court: both boundaries at z = 0, all boundary vertices supported.
  Surface court = make_builtin("court", o);
  Topology t = build_topology(court.mesh);
  int nb = 0;
  for (int v = 0; v < court.mesh.num_vertices(); ++v)
    if (t.on_boundary[v]) {
      ++nb;
      EXPECT_NEAR(court.mesh.V(v, 2), 0.0, 1e-12);
    }
  EXPECT_EQ(nb, static_cast<int>(court.supports.size()));
}

TEST(Builtin, SymmetricAboutBothMidPlanes) {
  for (const char* name : {"paraboloid", "funicular", "court", "barrel"}) {
    SCOPED_TRACE(name);
    Surface s = make_builtin(std::string(name));
    for (int axis : {0, 1}) {
      // Every vertex's mirror image is a vertex.
      for (int v = 0; v < s.mesh.num_vertices(); ++v) {
        Vec3 m = s.mesh.vertex(v);
        m[axis] = -m[axis];
        double best = 1e300;
        for (int w = 0; w < s.mesh.num_vertices(); ++w)
          best = std::min(best, (s.mesh.vertex(w) - m).norm());
        ASSERT_LT(best, 1e-9) << "axis " << axis << " vertex " << v;
      }
    }
  }
}

TEST(Funicular, ForceDensityEquilibrium) {
  FunicularResult f = make_funicular({});
  EXPECT_LT(f.residual, 1e-8);
  EXPECT_NEAR(f.surface.mesh.V.col(2).maxCoeff(), 5.0, 1e-9);  // default rise
  // A real form-found net: the free edges pull inwards (not a square any more), the supports are
  // few and at the corners only, and the shell is not a paraboloid: z differs from the best
  // paraboloid fit.
  const double h = 10;
  EXPECT_LT(std::abs(f.surface.mesh.V.col(0).maxCoeff()), h + 1e-9);
  EXPECT_LE(f.surface.supports.size() * 20,
            static_cast<std::size_t>(f.surface.mesh.num_vertices()));
  for (int v : f.surface.supports) {
    Vec3 p = f.surface.mesh.vertex(v);
    EXPECT_NEAR(p.z(), 0, 1e-12);
    EXPECT_GT(std::max(std::abs(p.x()), std::abs(p.y())), h - 1e-9);
  }
  // The mid-edge boundary vertex is pulled inwards by the edge cable.
  double ymin_mid = 1e300;
  for (int v = 0; v < f.surface.mesh.num_vertices(); ++v)
    if (std::abs(f.surface.mesh.V(v, 0)) < 1e-9)
      ymin_mid = std::min(ymin_mid, f.surface.mesh.V(v, 1));
  EXPECT_GT(ymin_mid, -h + 0.2);
}

TEST(Funicular, ResidualDetectsAPerturbation) {
  // The residual function is an independent check: perturbing one free node breaks equilibrium.
  ForceDensityProblem pb;
  pb.X.resize(3, 3);
  pb.X << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  pb.edges = {{0, 1}, {1, 2}};
  pb.q = {1.0, 1.0};
  pb.fixed = {1, 0, 1};
  pb.loads = Points::Zero(3, 3);
  pb.loads(1, 2) = 1.0;
  ForceDensityResult r = solve_force_density(pb);
  EXPECT_NEAR(r.X(1, 2), 0.5, 1e-14);  // 2 q z = p
  EXPECT_LT(r.residual, 1e-14);
  Points X = r.X;
  X(1, 2) += 0.1;
  EXPECT_NEAR(force_density_residual(pb, X), 0.2, 1e-12);
}

TEST(Builtin, InfoReportsNoProblems) {
  for (const auto& name : builtin_names()) {
    test::RunResult r = test::run_gridshell("info builtin:" + name + " --json");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("\"valid\": true"), std::string::npos) << name;
    EXPECT_NE(r.out.find("\"problems\": []"), std::string::npos) << name;
  }
}

TEST(Info, JsonHasTheContractKeys) {
  SKIP_WITHOUT_SHARED_DATA();
  test::RunResult r = test::run_gridshell(
      "info " + test::shared_file("surfaces/aquadom_Vouga.ply").string() + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"vertices\": 4005"), std::string::npos);
  EXPECT_NE(r.out.find("\"faces\": 7742"), std::string::npos);
  EXPECT_NE(r.out.find("\"boundary_loops\": 3"), std::string::npos);
  EXPECT_NE(r.out.find("\"supports\": 252"), std::string::npos);
}
