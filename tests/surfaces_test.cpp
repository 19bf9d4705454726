// Built-in surfaces: valid meshes with the expected topology and supports; the funicular shell is
// a true force-density equilibrium. Messy surface files: what the loader repairs, the one warning
// line it writes, and the support-colour rule.

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include "gridshell/core/error.h"
#include "gridshell/mesh/repair.h"
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

// The vertex cap (kMaxBuiltinVertices) admits the largest size it promises: a 1001 × 1001
// paraboloid (res=1000, 2 M triangles). The next sizes (and dome's past res=1155, 578 rings of
// 1 + 3·578·579 vertices) are refused in malformed_input_test.
TEST(Builtin, VertexCapAdmitsItsLargestSize) {
  const Surface par = make_builtin(std::string("paraboloid:res=1000"));
  EXPECT_EQ(par.mesh.num_vertices(), kMaxBuiltinVertices);
  EXPECT_EQ(par.mesh.num_faces(), 2 * 1000 * 1000);
  EXPECT_EQ(par.supports.size(), 4u * 1000u);
}

// The paraboloid's supports are its whole boundary, listed from the grid's rim without building
// the topology: the same list as the topology's boundary vertices.
TEST(Builtin, ParaboloidSupportsAreTheBoundary) {
  for (const char* spec : {"paraboloid", "paraboloid:res=2", "paraboloid:res=90"}) {
    SCOPED_TRACE(spec);
    const Surface s = make_builtin(std::string(spec));
    EXPECT_EQ(s.supports, boundary_vertices(build_topology(s.mesh)));
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
    EXPECT_NE(r.out.find("\"overlaps\": 0"), std::string::npos) << name;
  }
}

TEST(Info, CountsTheOverlapsOfAGrid) {
  // Two unit squares, the second shifted by half a side along x and y: two pairs of crossing
  // sides, and a corner of each inside the other (mesh/overlaps.h).
  const std::filesystem::path p = test::temp_dir("overlaps") / "stacked.obj";
  std::ofstream(p) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                      "v 0.5 0.5 0\nv 1.5 0.5 0\nv 1.5 1.5 0\nv 0.5 1.5 0\n"
                      "f 1 2 3 4\nf 5 6 7 8\n";
  const test::RunResult r = test::run_gridshell("info " + p.string() + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"overlaps\": 4"), std::string::npos) << r.out;
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

namespace {

namespace fs = std::filesystem;

/// Captures what spdlog writes while it lives (the default logger is restored after).
class LogCapture {
 public:
  LogCapture() : previous_(spdlog::default_logger()) {
    auto sink = std::make_shared<spdlog::sinks::ostream_sink_st>(out_);
    auto logger = std::make_shared<spdlog::logger>("capture", sink);
    logger->set_pattern("%v");
    logger->set_level(spdlog::level::warn);
    spdlog::set_default_logger(logger);
  }
  ~LogCapture() { spdlog::set_default_logger(previous_); }
  std::string text() const { return out_.str(); }
  long lines() const {
    const std::string t = text();
    return std::count(t.begin(), t.end(), '\n');
  }

 private:
  std::ostringstream out_;
  std::shared_ptr<spdlog::logger> previous_;
};

/// What loading the surface file `p` writes to the log (its warning line, or nothing).
std::string load_log(const fs::path& p, const SurfaceOptions& o = {}) {
  LogCapture log;
  load_surface(p.string(), o);
  return log.text();
}

/// The message of the Error load_surface throws on `p` ("" when it loads).
std::string load_error(const fs::path& p, const SurfaceOptions& o = {}) {
  try {
    load_surface(p.string(), o);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

/// An ascii PLY with per-vertex colours; `faces` as vertex id lists.
std::string colour_ply(const std::vector<std::array<double, 3>>& V,
                       const std::vector<std::array<int, 3>>& rgb,
                       const std::vector<std::vector<int>>& faces) {
  std::string s = fmt::format(
      "ply\nformat ascii 1.0\nelement vertex {}\nproperty double x\nproperty double y\n"
      "property double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
      "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
      V.size(), faces.size());
  for (std::size_t v = 0; v < V.size(); ++v)
    s += fmt::format("{} {} {} {} {} {}\n", V[v][0], V[v][1], V[v][2], rgb[v][0], rgb[v][1],
                     rgb[v][2]);
  for (const auto& f : faces) {
    s += fmt::format("{}", f.size());
    for (int v : f) s += fmt::format(" {}", v);
    s += "\n";
  }
  return s;
}

fs::path write(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

const std::array<int, 3> kRed{255, 0, 0}, kGrey{192, 192, 192};

}  // namespace

TEST(MessySurface, UnreferencedVerticesAreDroppedAndSupportsFollow) {
  // A unit square as two triangles (vertices 1..4), with an unreferenced red construction point
  // first and an unreferenced grey one last; supports red at 2 and 4.
  const fs::path p =
      write(test::temp_dir("messy") / "unref.ply",
            colour_ply({{9, 9, 9}, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {5, 5, 5}},
                       {kRed, kGrey, kRed, kGrey, kRed, kGrey}, {{1, 2, 3}, {1, 3, 4}}));
  LogCapture log;
  const Surface s = load_surface(p.string());
  EXPECT_EQ(s.mesh.num_vertices(), 4);
  EXPECT_DOUBLE_EQ(s.mesh.V(0, 0), 0.0);  // old vertex 1 is now 0
  EXPECT_EQ(s.mesh.F.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(s.supports, (std::vector<int>{1, 3}));  // old 2 and 4; the red point is gone
  EXPECT_EQ(log.lines(), 1) << log.text();
  EXPECT_NE(log.text().find("dropped 2 unreferenced vertices"), std::string::npos) << log.text();
  EXPECT_NE(log.text().find("1 of the dropped vertices was red"), std::string::npos);

  // A supports file names the file's ids: 0 (dropped, with a warning) and 3 (now 2).
  SurfaceOptions o;
  o.supports = write(p.parent_path() / "s.json", "[0, 3]").string();
  EXPECT_EQ(load_surface(p.string(), o).supports, (std::vector<int>{2}));
}

TEST(MessySurface, ExactDuplicateVerticesAreMerged) {
  // Two triangles that share the diagonal 0–2 only by position (vertices 3 and 4 repeat 0 and 2);
  // the red colour sits on the copy. Merged, the square is one piece with one boundary loop.
  const fs::path p =
      write(test::temp_dir("messy") / "dup.ply",
            colour_ply({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}},
                       {kGrey, kGrey, kGrey, kRed, kGrey, kGrey}, {{0, 1, 2}, {3, 4, 5}}));
  LogCapture log;
  const Surface s = load_surface(p.string());
  EXPECT_EQ(s.mesh.num_vertices(), 4);
  EXPECT_EQ(s.mesh.F.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(build_topology(s.mesh).boundary_loops.size(), 1u);
  EXPECT_EQ(s.supports, (std::vector<int>{0}));
  EXPECT_EQ(log.lines(), 1);
  EXPECT_NE(log.text().find("merged 2 duplicate vertices"), std::string::npos) << log.text();
}

TEST(MessySurface, NearlyCoincidentVerticesAreMergedWithinTheTolerance) {
  // A 10 m square meshed as two patches, each with its own copy of the seam x = 5: the copies
  // are 2e-6 m apart (2e-7 of the 14.1 m diagonal, as single-precision rounding leaves them).
  // Merged: one piece with one boundary loop, on which the seam's middle vertex no longer lies.
  // 2e-4 m apart (1.4e-5 of the diagonal): a gap the loader keeps.
  auto two_patches = [](double gap) {
    return fmt::format(
        "v 0 0 0\nv 5 0 0\nv 5 5 0\nv 5 10 0\nv 0 10 0\n"
        "v {0} 0 0\nv 10 0 0\nv 10 10 0\nv {0} 10 0\nv {0} 5 0\n"
        "f 1 2 3\nf 1 3 5\nf 3 4 5\nf 6 7 10\nf 7 8 10\nf 8 9 10\n",
        5 + gap);
  };
  const fs::path p = write(test::temp_dir("messy") / "patches.obj", two_patches(2e-6));
  LogCapture log;
  const Surface s = load_surface(p.string());
  EXPECT_EQ(s.mesh.num_vertices(), 7);
  const Topology topo = build_topology(s.mesh);
  EXPECT_EQ(topo.boundary_loops.size(), 1u);
  EXPECT_EQ(std::count(topo.on_boundary.begin(), topo.on_boundary.end(), 1), 6);  // not (5, 5)
  EXPECT_DOUBLE_EQ(s.mesh.V(1, 0), 5.0);  // merged into the lowest id: the first patch's
  EXPECT_NE(log.text().find("merged 3 duplicate vertices (3 within 1e-06 of the size, not at the "
                            "same position)"),
            std::string::npos)
      << log.text();

  write(p, two_patches(2e-4));
  const Surface apart = load_surface(p.string());
  EXPECT_EQ(apart.mesh.num_vertices(), 10);
  EXPECT_EQ(build_topology(apart.mesh).boundary_loops.size(), 2u);
}

TEST(MessySurface, TJunctionSeamsAreStitched) {
  // A 10 × 10 m roof arched along y (z = sin(π y / 10)) meshed as two patches that meet at
  // x = 5 (+ gap): the left one with a seam vertex at y = 5, the right one with its own at
  // y = 10/3 and 20/3, each on the arch (so 0.13–0.2 m off the other side's chords).
  auto two_patches = [](double gap) {
    std::string obj;
    auto v = [&](double x, double y) {
      obj += fmt::format("v {} {} {}\n", x, y, std::sin(3.14159265358979323846 * y / 10));
    };
    for (auto [x, y] :
         {std::pair{0.0, 0.0}, {5.0, 0.0}, {5.0, 5.0}, {5.0, 10.0}, {0.0, 10.0}, {0.0, 5.0}})
      v(x, y);
    for (auto [x, y] : {std::pair{5.0, 0.0},
                        {10.0, 0.0},
                        {10.0, 10.0},
                        {5.0, 10.0},
                        {5.0, 10.0 / 3},
                        {5.0, 20.0 / 3},
                        {10.0, 5.0}})
      v(x + (x == 5.0 ? gap : 0.0), y);
    return obj +
           "f 1 2 3\nf 1 3 6\nf 6 3 4\nf 6 4 5\n"
           "f 7 8 13\nf 7 13 11\nf 11 13 12\nf 12 13 9\nf 12 9 10\n";
  };
  const fs::path p = write(test::temp_dir("messy") / "seam.obj", two_patches(0));
  LogCapture log;
  const Surface s = load_surface(p.string());
  EXPECT_EQ(s.mesh.num_vertices(), 11);
  EXPECT_EQ(s.mesh.num_faces(), 12);  // 9 triangles, 3 of them now with a fourth corner
  const Topology topo = build_topology(s.mesh);
  EXPECT_EQ(topo.boundary_loops.size(), 1u);
  EXPECT_EQ(s.supports.size(), 8u);  // the outline only, not the seam
  EXPECT_TRUE(check_mesh(to_poly(s.mesh)).ok());
  EXPECT_EQ(count_slivers(s.mesh), 0);
  EXPECT_NE(log.text().find("stitched 3 T-junctions"), std::string::npos) << log.text();

  // The right patch 0.5 m away: a gap (beyond 6 % of the edges), not a seam.
  write(p, two_patches(0.5));
  const Surface apart = load_surface(p.string());
  EXPECT_EQ(build_topology(apart.mesh).boundary_loops.size(), 2u);
}

TEST(MessySurface, FacesWithoutAreaAreDroppedOrShortened) {
  // A quad with a repeated corner (a triangle really) and a triangle that uses a vertex twice.
  const fs::path p = write(test::temp_dir("messy") / "rep.obj",
                           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 2 3\nf 1 3 4\nf 4 4 1\n");
  LogCapture log;
  const Surface s = load_surface(p.string());
  EXPECT_EQ(s.mesh.num_faces(), 2);
  EXPECT_EQ(s.mesh.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(log.lines(), 1);
  EXPECT_NE(log.text().find("removed a repeated corner from 1 face, dropped 1 face without area"),
            std::string::npos)
      << log.text();
  // Nothing with an area left: an Error, not an empty surface.
  const fs::path bad = write(p.parent_path() / "bad.obj", "v 0 0 0\nv 1 0 0\nf 1 1 2\n");
  EXPECT_THROW(load_surface(bad.string()), Error);
}

namespace {

/// An n × n grid of unit squares in the plane z = 0 as OBJ text, two triangles per square, all
/// counter-clockwise seen from +z except those whose index `reversed` says.
std::string grid_obj(int n, const std::function<bool(int)>& reversed) {
  std::string s;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s += fmt::format("v {} {} 0\n", i, j);
  int t = 0;
  auto face = [&](int a, int b, int c) {
    s += reversed(t++) ? fmt::format("f {} {} {}\n", c + 1, b + 1, a + 1)
                       : fmt::format("f {} {} {}\n", a + 1, b + 1, c + 1);
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      face(a, b, c);
      face(a, c, d);
    }
  return s;
}

/// Per triangle, the sign of its normal's z component.
std::vector<int> normal_signs(const TriMesh& m) {
  std::vector<int> out;
  for (int f = 0; f < m.num_faces(); ++f) {
    const Vec3 n = (m.vertex(m.F(f, 1)) - m.vertex(m.F(f, 0)))
                       .cross(m.vertex(m.F(f, 2)) - m.vertex(m.F(f, 0)));
    out.push_back(n.z() > 0 ? 1 : -1);
  }
  return out;
}

}  // namespace

TEST(MessySurface, MixedFaceOrientationIsMadeConsistent) {
  // A 4 × 4 square as 32 triangles, every third one clockwise: 11 edges of the file are walked
  // the same way by both faces, which topology would count as 22 boundary edges (and `design`
  // refuses). Loaded, the 11 minority faces are reversed: one boundary loop, every normal +z.
  const fs::path dir = test::temp_dir("messy");
  const fs::path p = write(dir / "mixed.obj", grid_obj(4, [](int t) { return t % 3 == 1; }));
  EXPECT_GT(check_mesh(load_poly_surface(p.string()).mesh).inconsistent_orientation, 0);
  LogCapture log;
  const Surface s = load_surface(p.string());
  EXPECT_EQ(s.mesh.num_faces(), 32);
  EXPECT_EQ(build_topology(s.mesh).boundary_loops.size(), 1u);
  EXPECT_EQ(check_mesh(to_poly(s.mesh)).inconsistent_orientation, 0);
  EXPECT_EQ(normal_signs(s.mesh), std::vector<int>(32, 1));
  EXPECT_EQ(s.supports.size(), 16u);  // the boundary of the square, not of every triangle
  EXPECT_EQ(log.lines(), 1) << log.text();
  EXPECT_NE(log.text().find("reversed 11 faces to orient the surface consistently"),
            std::string::npos)
      << log.text();

  // The clockwise faces in the majority (by area): they keep their orientation, the others turn.
  write(p, grid_obj(4, [](int t) { return t % 3 != 1; }));
  const Surface flipped = load_surface(p.string());
  EXPECT_EQ(normal_signs(flipped.mesh), std::vector<int>(32, -1));

  // A consistently oriented file is not touched: no warning.
  write(p, grid_obj(4, [](int) { return false; }));
  LogCapture quiet;
  EXPECT_EQ(normal_signs(load_surface(p.string()).mesh), std::vector<int>(32, 1));
  EXPECT_EQ(quiet.lines(), 0) << quiet.text();
}

TEST(MessySurface, MoebiusStripIsReportedNotForced) {
  // A Möbius strip of 12 quads: no orientation makes every edge agree; the loader says so and
  // keeps the faces (one edge stays inconsistent), and `design`'s surface checks refuse it later.
  std::string obj;
  const int n = 12;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n, w = 0.3;
    for (int side : {-1, 1}) {
      const double r = 1 + side * w * std::cos(t / 2);
      obj +=
          fmt::format("v {} {} {}\n", r * std::cos(t), r * std::sin(t), side * w * std::sin(t / 2));
    }
  }
  for (int i = 0; i < n; ++i) {
    const int a = 2 * i, b = 2 * i + 1;
    const int c = i + 1 < n ? 2 * i + 3 : 0, d = i + 1 < n ? 2 * i + 2 : 1;  // the half twist
    obj += fmt::format("f {} {} {} {}\n", a + 1, b + 1, c + 1, d + 1);
  }
  const fs::path p = write(test::temp_dir("messy") / "moebius.obj", obj);
  LogCapture log;
  const Surface s = load_surface(p.string());
  EXPECT_EQ(s.mesh.num_faces(), 2 * n);
  EXPECT_NE(log.text().find("1 edge still inconsistently oriented (a non-orientable surface)"),
            std::string::npos)
      << log.text();
}

TEST(MessySurface, AClosedSurfaceWithoutSupportsIsRefused) {
  // A tetrahedron: no boundary, no colours, so no supports: refused when loaded (design would
  // otherwise fail later, in the shell analysis, on a mechanism).
  const fs::path p = write(test::temp_dir("messy") / "closed.obj",
                           "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                           "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
  const std::string error = load_error(p);
  EXPECT_NE(error.find("no supports: the surface has no boundary"), std::string::npos) << error;
  // With supports named, it loads.
  SurfaceOptions o;
  o.supports = write(p.parent_path() / "closed.json", "[0, 1]").string();
  EXPECT_EQ(load_surface(p.string(), o).supports, (std::vector<int>{0, 1}));
  o.supports = write(p.parent_path() / "none.json", "[]").string();
  EXPECT_THROW(load_surface(p.string(), o), Error);
}

TEST(MessySurface, AFinIsRefused) {
  // A square (two triangles) with a third triangle standing on its diagonal: the edge 1–3 has
  // three faces. No stage can analyse that; the loader says so instead of a later stage.
  const fs::path p = write(test::temp_dir("messy") / "fin.obj",
                           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n"
                           "f 1 2 3\nf 1 3 4\nf 1 3 5\n");
  const std::string error = load_error(p);
  EXPECT_NE(error.find("1 edge of three or more faces (a fin"), std::string::npos) << error;
  // Without the fin it loads.
  write(p, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n");
  EXPECT_EQ(load_surface(p.string()).mesh.num_faces(), 2);
}

TEST(MessySurface, PiecesTouchingAtASingleCornerAreRefused) {
  // Two squares that share only the corner (1, 1, 0): a bow-tie. The first stage that walks
  // that vertex's neighbourhood could not; the loader names it instead.
  const fs::path p = write(test::temp_dir("messy") / "bowtie.obj",
                           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 1 0\nv 2 2 0\nv 1 2 0\n"
                           "f 1 2 3 4\nf 3 5 6 7\n");
  const std::string error = load_error(p);
  EXPECT_NE(error.find("1 vertex where pieces of the surface touch at a single corner (the first "
                       "at 1 1 0, vertex 2 counting from 0)"),
            std::string::npos)
      << error;
  // Joined along an edge (the second square moved down to share the edge 2–3) it loads.
  write(p, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nf 1 2 3 4\nf 2 5 6 3\n");
  EXPECT_EQ(load_surface(p.string()).mesh.num_faces(), 4);
}

TEST(MessySurface, AConcavePolygonIsTriangulatedInsideItsOutline) {
  // A 2 × 2 square with a notch down to (1, 0.5) as one pentagon listed from the corner beside
  // the notch, and a square beside it: a fan from the first corner would fold the notch's
  // triangle over the others (5.5 m² of triangles for 2.5 m² of polygon).
  const fs::path p = write(test::temp_dir("messy") / "notch.obj",
                           "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 1 0.5 0\nv 0 2 0\nv 4 0 0\nv 4 2 0\n"
                           "f 3 4 5 1 2\nf 2 6 7 3\n");
  const Surface s = load_surface(p.string());
  ASSERT_EQ(s.mesh.num_faces(), 5);
  EXPECT_NEAR(surface_area(s.mesh), 2.5 + 4.0, 1e-12);
  EXPECT_TRUE(check_mesh(to_poly(s.mesh)).ok());
}

TEST(MessySurface, ASurfaceKilometresAcrossIsFlaggedAsMillimetres) {
  // The same square roof at 30 m and at 30 000 (a file in millimetres): only the second warns.
  auto square = [](double side) {
    return fmt::format("v 0 0 0\nv {0} 0 0\nv {0} {0} 0\nv 0 {0} 0\nf 1 2 3\nf 1 3 4\n", side);
  };
  const fs::path p = write(test::temp_dir("messy") / "units.obj", square(30));
  EXPECT_EQ(load_log(p), "");
  write(p, square(30000));
  EXPECT_NE(load_log(p).find("the surface is 42426 m across (its bounding box's diagonal): if "
                             "its coordinates are in millimetres, pass --scale 0.001"),
            std::string::npos)
      << load_log(p);
  SurfaceOptions o;
  o.scale = 0.001;
  EXPECT_EQ(load_log(p, o), "");
}

TEST(MessySurface, ASurfaceOnItsSideIsFlagged) {
  // A 20 × 10 m barrel 4 m high, written y-up: read as z-up it stands 10 m tall on a 4 m wide
  // plan (warned); with --up y it is a roof again (no warning).
  std::string obj;
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 4; ++j) {
      const double x = 20.0 * i / 8, s = 10.0 * j / 4 - 5;
      obj += fmt::format("v {} {} {}\n", x, 4 * (1 - s * s / 25), -s);  // y up, z towards you
    }
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 4; ++j) {
      const int a = i * 5 + j + 1, b = a + 5;
      obj += fmt::format("f {} {} {}\nf {} {} {}\n", a, b, b + 1, a, b + 1, a + 1);
    }
  const fs::path p = write(test::temp_dir("messy") / "yup.obj", obj);
  EXPECT_NE(load_log(p).find(
                "the surface is 10 m tall and 4 m wide: if its up axis is not z, pass --up y"),
            std::string::npos)
      << load_log(p);
  SurfaceOptions o;
  o.up = "y";
  EXPECT_EQ(load_log(p, o), "");
  const Surface s = load_surface(p.string(), o);
  EXPECT_NEAR(s.mesh.V.col(2).maxCoeff(), 4.0, 1e-12);
}

TEST(MessySurface, SliversAreKeptWithAWarning) {
  // A square fanned around a vertex (0.5, 0.5001): no sliver, no warning.
  const fs::path p = write(test::temp_dir("messy") / "sliver.off",
                           "OFF\n5 4 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5001 0\n"
                           "3 0 1 4\n3 1 2 4\n3 2 3 4\n3 3 0 4\n");
  {
    LogCapture log;
    const Surface s = load_surface(p.string());
    EXPECT_EQ(count_slivers(s.mesh), 0);
    EXPECT_EQ(log.lines(), 0) << log.text();
  }
  // The same vertex, but the triangle 0 4 2 between it and the diagonal: angles of 0.01°.
  write(p,
        "OFF\n5 4 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5001 0\n"
        "3 0 1 4\n3 1 2 4\n3 0 4 2\n3 0 2 3\n");
  LogCapture log;
  const Surface s = load_surface(p.string());
  EXPECT_EQ(s.mesh.num_faces(), 4);  // kept
  EXPECT_EQ(count_slivers(s.mesh), 1);
  EXPECT_EQ(log.lines(), 1);
  EXPECT_NE(log.text().find("kept 1 sliver triangle (an angle below 1 degree)"), std::string::npos)
      << log.text();
}

TEST(MessySurface, SupportColourRule) {
  EXPECT_TRUE(is_support_colour({255, 0, 0}));
  EXPECT_TRUE(is_support_colour({254, 0, 0}));
  EXPECT_TRUE(is_support_colour({255, 10, 10}));
  EXPECT_TRUE(is_support_colour({160, 20, 40}));     // dark red
  EXPECT_FALSE(is_support_colour({255, 128, 0}));    // orange
  EXPECT_FALSE(is_support_colour({255, 192, 203}));  // pink
  EXPECT_FALSE(is_support_colour({192, 192, 192}));  // our writer's grey
  EXPECT_FALSE(is_support_colour({100, 0, 0}));      // too dark to tell from black
  EXPECT_FALSE(is_support_colour({0, 0, 255}));

  const std::vector<std::array<double, 3>> V{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<std::vector<int>> F{{0, 1, 2}, {0, 2, 3}};
  const fs::path d = test::temp_dir("colour");
  // Another exporter's red: (254,0,0) and (255,10,10) are supports, with a warning.
  const fs::path near =
      write(d / "near.ply", colour_ply(V, {{254, 0, 0}, kGrey, {255, 10, 10}, kGrey}, F));
  LogCapture log;
  EXPECT_EQ(load_surface(near.string()).supports, (std::vector<int>{0, 2}));
  EXPECT_NE(log.text().find("2 of the 2 red support vertices are not pure"), std::string::npos)
      << log.text();
  // Supports in another colour (blue): the boundary, and the warning names the colours.
  const fs::path blue = write(d / "blue.ply", colour_ply(V, {{0, 0, 255}, kGrey, kGrey, kGrey}, F));
  LogCapture log2;
  EXPECT_EQ(load_surface(blue.string()).supports, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(log2.lines(), 1);
  EXPECT_NE(log2.text().find("no red vertices among the colours (0,0,255) x1, (192,192,192) x3"),
            std::string::npos)
      << log2.text();
  SurfaceOptions red;
  red.supports = "red";
  EXPECT_THROW(load_surface(blue.string(), red), Error);
}
