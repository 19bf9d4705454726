// The eurocode snow arrangements, EN 1990 combinations and file load cases of
// analysis/load_cases.h against hand computations: plan areas × shape factors, the combination
// factors of (6.10) / (6.14b) with Table A1.1's ψ0, pressure fields whose integral is known; and
// the unfavourable imperfection sign on a shallow arch (analysis/frame_analysis.h).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include <tbb/global_control.h>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/analysis/load_cases.h"
#include "gridshell/core/error.h"
#include "test_support.h"

using namespace gridshell;
using namespace gridshell::analysis;

namespace {

/// A grid of nx × ny quads over [x0, x0 + w] × [0, l], z = height(x, y).
template <class F>
PolyMesh quad_grid(int nx, int ny, double x0, double w, double l, F height) {
  PolyMesh m;
  m.V.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double x = x0 + w * i / nx, y = l * j / ny;
      m.V.row(j * (nx + 1) + i) << x, y, height(x, y);
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i;
      m.faces.push_back({a, a + 1, a + nx + 2, a + nx + 1});
    }
  return m;
}

double total_z(const std::vector<Vec3>& F) {
  double s = 0;
  for (const Vec3& f : F) s += f.z();
  return s;
}

std::map<std::string, double> factors(const LoadCombination& c) {
  return {c.factors.begin(), c.factors.end()};
}

std::string write_file(const std::string& name, const std::string& text) {
  const auto path = test::temp_dir("snow_arrangements") / name;
  std::ofstream(path) << text;
  return path.string();
}

}  // namespace

TEST(SnowArrangements, FlatPlanHalvesCarryMu1AndHalfOfIt) {
  const PolyMesh m = quad_grid(10, 6, 0, 10, 6, [](double, double) { return 0.0; });
  const double s_k = 1.5, plan = 60;
  // Undrifted: s_k · 0.8 · plan area.
  EXPECT_NEAR(total_z(snow_forces(m, snow_shape_factors(m, -1, 0), s_k)), -s_k * 1e3 * 0.8 * plan,
              1e-6);
  for (int axis = 0; axis < 2; ++axis)
    for (int side : {-1, 1}) {
      bool cylindrical = true;
      const std::vector<double> mu = snow_shape_factors(m, axis, side, &cylindrical);
      EXPECT_FALSE(cylindrical);  // no rise: the pitched-roof arrangement of Figure 5.3
      // Half the plan at μ1 = 0.8, the other half at 0.4.
      EXPECT_NEAR(total_z(snow_forces(m, mu, s_k)), -s_k * 1e3 * (0.8 + 0.4) * plan / 2, 1e-6);
      for (int f = 0; f < m.num_faces(); ++f) {
        Vec3 c = Vec3::Zero();
        for (int v : m.faces[f]) c += m.vertex(v);
        const double x = c(axis) / 4, centre = axis == 0 ? 5 : 3;
        EXPECT_DOUBLE_EQ(mu[f], (x - centre) * side > 0 ? 0.8 : 0.4) << f;
      }
    }
}

TEST(SnowArrangements, BarrelVaultTakesMu3AcrossItsGenerators) {
  // A circular barrel: radius 20 m, width 16 m (rise 20 − √336 = 1.670 m), generators along y.
  const double R = 20, b = 16, L = 12;
  const PolyMesh m = quad_grid(8, 4, -b / 2, b, L,
                               [&](double x, double) { return std::sqrt(R * R - x * x); });
  const double h = R - std::sqrt(R * R - b * b / 4);
  const double mu3 = 0.2 + 10 * h / b;  // EN 1991-1-3 (5.5): 1.244
  EXPECT_NEAR(cylindrical_snow_factor(h, b), mu3, 1e-12);
  EXPECT_DOUBLE_EQ(cylindrical_snow_factor(5, 10), 2.0);  // capped
  bool cylindrical = false;
  const std::vector<double> mu = snow_shape_factors(m, 0, +1, &cylindrical);
  EXPECT_TRUE(cylindrical);
  const double s_k = 1.0;
  // The quads are planar (between two generators): plan = b L; μ3 on x > 0, μ3 / 2 on x < 0.
  EXPECT_NEAR(total_z(snow_forces(m, mu, s_k)), -s_k * 1e3 * 0.75 * mu3 * b * L, 1e-6);
  // Along the generators the roof does not rise: Figure 5.3's μ1 (slopes below 30°: 0.8).
  const std::vector<double> along = snow_shape_factors(m, 1, -1, &cylindrical);
  EXPECT_FALSE(cylindrical);
  EXPECT_NEAR(total_z(snow_forces(m, along, s_k)), -s_k * 1e3 * 0.75 * 0.8 * b * L, 1e-6);
}

TEST(SnowArrangements, CombinationsFollowEn1990WithPsiFactors) {
  const PolyMesh m = quad_grid(4, 4, 0, 4, 4, [](double, double) { return 0.0; });
  GridshellFrameOptions o;
  o.loads = LoadModel::eurocode;
  FileLoadCase wind = read_load_case_file(
      "W=" + write_file("wind_up.csv", "panel,pressure_kN_m2\n0,-2\n1,-2\n"));
  wind.given = FileLoadCase::Given::panel;
  o.load_cases = {wind};
  // The bars' weight per metre as gridshell_frame takes it (40 bars in the 4 × 4 grid).
  const double w = o.density * o.g * fem::circle_section(o.diameter).A;
  const std::vector<LoadCase> cases = eurocode_cases(m, std::vector<double>(40, w), o);
  ASSERT_EQ(cases.size(), 8u);  // G1 G2 S S_x- S_x+ S_y- S_y+ W
  const std::vector<LoadCombination> combos = eurocode_combinations(cases);
  std::map<std::string, LoadCombination> by;
  for (const auto& c : combos) by[c.name] = c;
  EXPECT_EQ(combos.front().name, "ULS");
  // 5 snow + 1 wind (+ the suction one with γG,inf) ULS, 5 + 1 SLS.
  EXPECT_EQ(combos.size(), 13u);
  using F = std::map<std::string, double>;
  EXPECT_EQ(factors(by.at("ULS")), (F{{"G1", 1.35}, {"G2", 1.35}, {"S", 1.5}, {"W", 1.5 * 0.6}}));
  EXPECT_EQ(factors(by.at("ULS_S_x+")),
            (F{{"G1", 1.35}, {"G2", 1.35}, {"S_x+", 1.5}, {"W", 1.5 * 0.6}}));
  EXPECT_EQ(factors(by.at("ULS_W")), (F{{"G1", 1.35}, {"G2", 1.35}, {"W", 1.5}, {"S", 0.75}}));
  EXPECT_EQ(factors(by.at("ULS_W_Ginf")), (F{{"G1", 1.0}, {"G2", 1.0}, {"W", 1.5}, {"S", 0.75}}));
  EXPECT_EQ(factors(by.at("SLS_W")), (F{{"G1", 1.0}, {"G2", 1.0}, {"W", 1.0}, {"S", 0.5}}));
  EXPECT_EQ(factors(by.at("SLS_S_y-")), (F{{"G1", 1.0}, {"G2", 1.0}, {"S_y-", 1.0}, {"W", 0.6}}));
  EXPECT_FALSE(by.at("SLS").uls);
  // The frame carries the named combination: Σ factor × case.
  o.combination_name = "ULS_W";
  const fem::FrameModel model = gridshell_frame(m, {0, 4, 20, 24}, o);
  double expect = 0;
  for (const auto& [name, f] : by.at("ULS_W").factors)
    for (const LoadCase& c : cases)
      if (c.name == name) expect += f * total_z(c.F);
  EXPECT_NEAR(fem::total_load(model).z(), expect, 1e-9 * std::abs(expect));
  // Suction on panels 0 and 1 (1 m² each): 2 kN/m² up.
  for (const LoadCase& c : cases) {
    if (c.name == "W") {
      EXPECT_NEAR(total_z(c.F), 2 * 2e3, 1e-9);
    }
  }
}

TEST(FileLoadCases, UniformAndLinearPressuresIntegrateExactly) {
  // The input surface: a plane z = 0.5 x triangulated finely; the grid: coarser quads on it.
  const auto plane = [](double x, double) { return 0.5 * x; };
  const PolyMesh fine = quad_grid(12, 6, 0, 4, 2, plane);
  TriMesh surface;
  surface.V = fine.V;
  surface.F.resize(2 * fine.num_faces(), 3);
  for (int f = 0; f < fine.num_faces(); ++f) {
    const auto& q = fine.faces[f];
    surface.F.row(2 * f) << q[0], q[1], q[2];
    surface.F.row(2 * f + 1) << q[0], q[2], q[3];
  }
  const PolyMesh grid = quad_grid(5, 3, 0, 4, 2, plane);
  const double cos_a = 1 / std::sqrt(1.25);  // the plane's normal (−0.5, 0, 1) / √1.25
  std::string uniform = "vertex,pressure_kN_m2\n", linear = uniform;
  for (int v = 0; v < surface.num_vertices(); ++v) {
    const double x = surface.V(v, 0), y = surface.V(v, 1);
    uniform += std::to_string(v) + ",1.5\n";
    linear += std::to_string(v) + "," + std::to_string(1 + 0.5 * x + 0.25 * y) + "\n";
  }
  FileLoadCase u = read_load_case_file("U=" + write_file("uniform.csv", uniform));
  attach_surface(u, surface);
  const std::vector<Vec3> Fu = load_case_forces(grid, u);
  Vec3 total = Vec3::Zero();
  for (const Vec3& f : Fu) total += f;
  const double area = 4 * 2 / cos_a;  // sloped area of the plan 4 × 2
  // p × area along −n: down and towards +x (pushing onto the roof).
  EXPECT_NEAR(total.z(), -1.5e3 * area * cos_a, 1e-6);
  EXPECT_NEAR(total.x(), 1.5e3 * area * 0.5 * cos_a, 1e-6);
  EXPECT_NEAR(total.y(), 0, 1e-6);
  // Linear p = 1 + 0.5 x + 0.25 y: the centroid rule integrates it exactly, ∫p dA_plan = 18.
  FileLoadCase l = read_load_case_file("L=" + write_file("linear.csv", linear));
  attach_surface(l, surface);
  double fz = 0;
  for (const Vec3& f : load_case_forces(grid, l)) fz += f.z();
  EXPECT_NEAR(fz, -18e3, 1e-3);
  // A surface stored facing down gives the same forces (orientation is taken facing up).
  TriMesh flipped = surface;
  flipped.F.col(1).swap(flipped.F.col(2));
  attach_surface(l, flipped);
  fz = 0;
  for (const Vec3& f : load_case_forces(grid, l)) fz += f.z();
  EXPECT_NEAR(fz, -18e3, 1e-3);
}

TEST(FileLoadCases, BadFilesAreOneLineErrors) {
  const auto bad = [](const std::string& name, const std::string& text) {
    try {
      read_load_case_file("X=" + write_file(name, text));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(bad("cols.csv", "vertex,pressure\n0,1\n").find("header"), std::string::npos);
  EXPECT_NE(bad("nan.csv", "vertex,pressure_kN_m2\n0,nan\n").find("finite"), std::string::npos);
  EXPECT_NE(bad("dup.csv", "vertex,pressure_kN_m2\n0,1\n0,2\n").find("again"), std::string::npos);
  EXPECT_NE(bad("empty.csv", "").find("empty"), std::string::npos);
  EXPECT_NE(bad("rows.csv", "vertex,pressure_kN_m2\n").find("no rows"), std::string::npos);
  EXPECT_NE(bad("short.csv", "joint,fx_kN,fy_kN,fz_kN\n0,1,2\n").find("columns"),
            std::string::npos);
  EXPECT_NE(bad("word.csv", "panel,pressure_kN_m2\n0,abc\n").find("not a number"),
            std::string::npos);
  EXPECT_THROW(read_load_case_file("noequals"), Error);
  EXPECT_THROW(read_load_case_file("S=x.csv"), Error);  // a built-in case's name
  EXPECT_THROW(read_load_case_file("A:odd=x.csv"), Error);
  const FileLoadCase p = read_load_case_file(
      "glass:permanent=" + write_file("perm.csv", "vertex,pressure_kN_m2\n0,1\n"));
  EXPECT_TRUE(p.permanent);
  EXPECT_EQ(p.name, "glass");
  // Unknown ids: a vertex the input surface lacks, a panel the grid lacks.
  TriMesh t;
  t.V.resize(3, 3);
  t.V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  t.F.resize(1, 3);
  t.F << 0, 1, 2;
  FileLoadCase far = read_load_case_file(
      "F=" + write_file("far.csv", "vertex,pressure_kN_m2\n0,1\n1,1\n7,1\n"));
  EXPECT_THROW(attach_surface(far, t), Error);
  FileLoadCase panel =
      read_load_case_file("P=" + write_file("panel.csv", "panel,pressure_kN_m2\n9,1\n"));
  EXPECT_THROW(load_case_forces(quad_grid(2, 2, 0, 1, 1, [](double, double) { return 0.0; }),
                                panel),
               Error);
}

namespace {
// A shallow circular arch (span 10 m, rise 0.2 m, Ø100 mm) of 20 segments in the xz plane,
// pinned at its ends, held out of plane and at the crown horizontally (which rules out the
// antisymmetric modes), under equal vertical loads at its joints.
constexpr double kArchSpan = 10;
fem::FrameModel shallow_arch() {
  const int n = 20;
  const double span = kArchSpan, rise = 0.2, R = (span * span / 4 + rise * rise) / (2 * rise);
  fem::FrameModel m;
  m.nodes.resize(n + 1, 3);
  for (int k = 0; k <= n; ++k) {
    const double x = -span / 2 + span * k / n;
    m.nodes.row(k) << x, 0, std::sqrt(R * R - x * x) - (R - rise);
  }
  m.sections = {fem::circle_section(0.1, "bar")};
  m.materials = {{"steel", 210e9, 0.3, 0, 0}};
  for (int k = 0; k < n; ++k) {
    fem::FrameMember mb;
    mb.i = k;
    mb.j = k + 1;
    mb.elements = 2;
    m.members.push_back(mb);
  }
  for (int k = 0; k <= n; ++k) {
    const bool end = k == 0 || k == n, crown = k == n / 2;
    m.supports.push_back({k, {end || crown, true, end, true, false, true}});
    if (!end) m.loads.push_back({k, Vec3(0, 0, -1e3), Vec3::Zero()});
  }
  return m;
}
}  // namespace

TEST(Imperfection, TheUnfavourableSignOfASymmetricModeGoverns) {
  // The shallow arch's first buckling mode is the symmetric snap-through, and the imperfection
  // that flattens the arch lowers the limit load (measured: 2.15 against 2.87 for the other
  // sign; λ_perfect 4.58, λ_LBA 7.42).
  const int n = 20;
  const double span = kArchSpan;
  const fem::FrameModel m = shallow_arch();
  FrameAnalysisOptions o;
  o.stability = true;
  o.imperfection_amplitude = span / 300;
  o.imperfection_max_modes = 1;
  o.imperfection_full_paths = true;  // both signs to their critical points
  const FrameResult r = analyze_frame(m, o);
  ASSERT_EQ(r.imperfections_tried.size(), 2u);
  ASSERT_TRUE(r.imperfections_tried[0].lambda && r.imperfections_tried[1].lambda);
  const double lp = *r.imperfections_tried[0].lambda, lm = *r.imperfections_tried[1].lambda;
  EXPECT_GT(std::abs(lp - lm), 0.01 * std::min(lp, lm));  // the sign matters here
  ASSERT_TRUE(r.lambda_imperfect && r.lambda_perfect);
  EXPECT_DOUBLE_EQ(*r.lambda_imperfect, std::min(lp, lm));
  EXPECT_LE(*r.lambda_imperfect, *r.lambda_perfect);
  // The chosen sign moves the crown down (flattens the arch).
  const Points& mode = r.buckling_modes.front();
  EXPECT_LT(r.imperfection_sign * mode(n / 2, 2), 0);
}

TEST(Imperfection, ACandidateAboveTheLowestEndsThereTheSameWhateverTheThreads) {
  // The candidates are followed together and the one that passes the lower one's limit load
  // (2.15) without a critical point of its own (its own lies at 2.87) is ended there: λ_imperfect
  // and the governing sign are those of following both to their ends, and the other candidate
  // reports the first λ of its path above 2.15 instead of a λ it never reached — the same on one
  // thread as on two.
  FrameAnalysisOptions o;
  o.stability = true;
  o.imperfection_amplitude = kArchSpan / 300;
  o.imperfection_max_modes = 1;
  FrameAnalysisOptions full = o;
  full.imperfection_full_paths = true;
  const FrameResult all = analyze_frame(shallow_arch(), full);
  const FrameResult r = analyze_frame(shallow_arch(), o);
  FrameResult one;
  {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
    one = analyze_frame(shallow_arch(), o);
  }
  ASSERT_TRUE(all.lambda_imperfect && r.lambda_imperfect && one.lambda_imperfect);
  EXPECT_EQ(*r.lambda_imperfect, *all.lambda_imperfect);
  EXPECT_EQ(r.imperfection_sign, all.imperfection_sign);
  ASSERT_EQ(r.imperfections_tried.size(), 2u);
  const int low = r.imperfections_tried[0].lambda ? 0 : 1;
  const auto& lowest = r.imperfections_tried[low];
  const auto& other = r.imperfections_tried[1 - low];
  ASSERT_TRUE(lowest.lambda);
  EXPECT_EQ(*lowest.lambda, *r.lambda_imperfect);
  EXPECT_FALSE(lowest.lambda_above);
  EXPECT_FALSE(other.lambda);
  ASSERT_TRUE(other.lambda_above);
  ASSERT_TRUE(all.imperfections_tried[1 - low].lambda);
  EXPECT_GT(*other.lambda_above, *r.lambda_imperfect);
  EXPECT_LT(*other.lambda_above, *all.imperfections_tried[1 - low].lambda);
  // The first point above the lowest λ: the full path's points below it are the same.
  EXPECT_GT(*all.imperfections_tried[1 - low].lambda, 1.2 * *r.lambda_imperfect);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(one.imperfections_tried[k].lambda, r.imperfections_tried[k].lambda);
    EXPECT_EQ(one.imperfections_tried[k].lambda_above, r.imperfections_tried[k].lambda_above);
  }
  EXPECT_EQ(*one.lambda_imperfect, *r.lambda_imperfect);
  EXPECT_EQ(*one.lambda_perfect, *r.lambda_perfect);
}
