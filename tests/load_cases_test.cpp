// Eurocode load cases and combinations of a grid-shell frame (analysis/gridshell_frame.h):
// the snow shape factor of EN 1991-1-3 Table 5.2, case totals on panels whose area and plan
// area are known by hand, and the EN 1990 combinations' totals.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <nlohmann/json.hpp>

#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/core/error.h"
#include "gridshell/fem/frame_model.h"
#include "gridshell/pipeline/design.h"
#include "test_support.h"

using namespace gridshell;
using namespace gridshell::analysis;

namespace {
double sum(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s;
}

/// Two unit squares sharing an edge along y: one flat (z = 0), one rising at `slope_deg`
/// (plan 1 × 1, surface 1 / cos α).
PolyMesh flat_and_sloped(double slope_deg) {
  const double h = std::tan(slope_deg * std::numbers::pi / 180);
  PolyMesh m;
  m.V.resize(6, 3);
  m.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 0, h, 2, 1, h;
  m.faces = {{0, 1, 2, 3}, {1, 4, 5, 2}};
  return m;
}
}  // namespace

TEST(LoadCases, SnowShapeFactorFollowsTable52) {
  EXPECT_DOUBLE_EQ(snow_shape_factor(0), 0.8);
  EXPECT_DOUBLE_EQ(snow_shape_factor(30), 0.8);
  EXPECT_DOUBLE_EQ(snow_shape_factor(45), 0.4);
  EXPECT_DOUBLE_EQ(snow_shape_factor(60), 0.0);
  EXPECT_DOUBLE_EQ(snow_shape_factor(75), 0.0);
}

TEST(LoadCases, CaseTotalsMatchHandComputedAreas) {
  const double alpha = 45;  // the sloped panel: surface √2, plan 1, μ1 = 0.4
  const PolyMesh m = flat_and_sloped(alpha);
  GridshellFrameOptions o;
  o.glass_kN_m2 = 0.5;
  o.snow_kN_m2 = 2.0;
  const double w = 100;  // N per m of bar
  const LoadCases c = eurocode_load_cases(m, std::vector<double>(7, w), o);
  // Edges: the flat square's 4 (length 1); the sloped square adds two of length √2 and one of 1.
  const double length = 5 + 2 * std::sqrt(2.0);
  EXPECT_NEAR(sum(c.G1), -w * length, 1e-9);
  EXPECT_NEAR(sum(c.G2), -0.5e3 * (1 + std::sqrt(2.0)), 1e-9);
  EXPECT_NEAR(sum(c.Q), -2.0e3 * (0.8 * 1 + 0.4 * 1), 1e-9);
  // A corner of the flat panel only (vertex 0) takes a quarter of that panel.
  EXPECT_NEAR(c.Q[0], -2.0e3 * 0.8 / 4, 1e-9);
  EXPECT_NEAR(c.G2[4], -0.5e3 * std::sqrt(2.0) / 4, 1e-9);
}

TEST(LoadCases, CombinationsScaleTheCases) {
  const PolyMesh m = flat_and_sloped(20);
  GridshellFrameOptions o;
  o.loads = LoadModel::eurocode;
  o.glass_kN_m2 = 0.4;
  o.snow_kN_m2 = 1.0;
  const fem::FrameModel ref = gridshell_frame(m, {0, 3}, o);
  const double w = o.density * o.g * ref.sections[0].A;
  const LoadCases c = eurocode_load_cases(m, std::vector<double>(ref.members.size(), w), o);
  const double G = sum(c.G1) + sum(c.G2), Q = sum(c.Q);
  EXPECT_LT(Q, 0);
  EXPECT_NEAR(fem::total_load(ref).z(), 1.35 * G + 1.5 * Q, 1e-9 * std::abs(G + Q));
  o.combination = Combination::sls;
  EXPECT_NEAR(fem::total_load(gridshell_frame(m, {0, 3}, o)).z(), G + Q, 1e-9 * std::abs(G + Q));
  // The paper's load is unchanged by the new options.
  GridshellFrameOptions paper;
  paper.glass_kN_m2 = 9;
  paper.snow_kN_m2 = 9;
  const double weight = paper.density * paper.g * ref.sections[0].A * fem::total_length(ref);
  EXPECT_NEAR(fem::total_load(gridshell_frame(m, {0, 3}, paper)).z(), -weight, 1e-9 * weight);
}

TEST(LoadCases, WordsAndBadValues) {
  EXPECT_EQ(parse_load_model("eurocode"), LoadModel::eurocode);
  EXPECT_STREQ(to_string(LoadModel::paper), "paper");
  EXPECT_THROW(parse_load_model("wind"), Error);
  EXPECT_EQ(partial_factors(Combination::uls), std::make_pair(1.35, 1.5));
  GridshellFrameOptions o;
  o.loads = LoadModel::eurocode;
  o.snow_kN_m2 = -1;
  EXPECT_THROW(gridshell_frame(flat_and_sloped(10), {0}, o), Error);
  o.snow_kN_m2 = 1;
  o.area_load_kN_m2 = 1;
  EXPECT_THROW(gridshell_frame(flat_and_sloped(10), {0}, o), Error);
}

TEST(LoadCases, CommandLineWritesOneBlockPerCombination) {
  namespace fs = std::filesystem;
  const fs::path d = test::temp_dir("load_cases_design");
  const auto r = test::run_gridshell(
      "design builtin:dome --cells 40 --seed 2 --field uniform --analyze none --quiet -o " +
      d.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const fs::path a = test::temp_dir("load_cases_analyze");
  const auto ra = test::run_gridshell("analyze " + (d / "gridshell.obj").string() +
                                      " --loads eurocode --analyze buckling --quiet -o " +
                                      a.string());
  ASSERT_EQ(ra.status, 0) << ra.err;
  std::ifstream in(a / "report.json");
  const auto report = nlohmann::json::parse(in);
  const auto& st = report.at("structure");
  EXPECT_EQ(st.at("loads"), "eurocode");
  const auto& uls = st.at("combinations").at("ULS");
  const auto& sls = st.at("combinations").at("SLS");
  EXPECT_DOUBLE_EQ(uls.at("gamma_G").get<double>(), 1.35);
  EXPECT_DOUBLE_EQ(sls.at("gamma_Q").get<double>(), 1.0);
  // The structure block is the ULS analysis; SLS (smaller factors, same cases) deflects less.
  EXPECT_DOUBLE_EQ(uls.at("delta_max_m").get<double>(), st.at("delta_max_m").get<double>());
  EXPECT_LT(sls.at("delta_max_m").get<double>(), uls.at("delta_max_m").get<double>());
  EXPECT_GT(sls.at("delta_max_m").get<double>(), uls.at("delta_max_m").get<double>() / 1.5);
  EXPECT_EQ(sls.at("delta_pass").get<bool>(),
            sls.at("delta_max_m").get<double>() <= sls.at("delta_limit_m").get<double>());
  EXPECT_TRUE(uls.at("lambda_lba").is_number());
  EXPECT_TRUE(sls.at("lambda_lba").is_null());  // SLS: linear only
  EXPECT_TRUE(fs::exists(a / "modes.csv"));

  // Options are checked before any work.
  const auto bad = test::run_gridshell("design builtin:dome --loads eurocode --area-load 1 -o " +
                                       a.string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--area-load"), std::string::npos) << bad.err;
  const auto wind = test::run_gridshell("design builtin:dome --loads wind -o " + a.string());
  EXPECT_EQ(wind.status, 2);
  EXPECT_NE(wind.err.find("--loads"), std::string::npos) << wind.err;
}

// `baseline` takes design's load and check options (registered once, app/common.h): with the
// same grid and loads, utilisation scales with 1/fy (S235 against S355), the eurocode blocks
// are there, and a bad word or value exits 2.
TEST(LoadCases, BaselineTakesTheLoadAndSteelOptions) {
  namespace fs = std::filesystem;
  const auto run = [](const std::string& steel) {
    const fs::path d = test::temp_dir("load_cases_baseline_" + steel);
    const auto r = test::run_gridshell(
        "baseline builtin:dome --kind quad --spacing 2 --analyze linear --loads eurocode "
        "--snow 0.8 --glass 0.5 --deflection-limit 200 --figures none --quiet --steel " +
        steel + " -o " + d.string());
    EXPECT_EQ(r.status, 0) << r.err;
    std::ifstream in(d / "report.json");
    return nlohmann::json::parse(in).at("structure");
  };
  const auto s235 = run("S235"), s355 = run("S355");
  EXPECT_EQ(s235.at("steel"), "S235");
  EXPECT_EQ(s235.at("loads"), "eurocode");
  const auto& uls = s235.at("combinations").at("ULS");
  EXPECT_NEAR(uls.at("utilisation_max").get<double>() /
                  s355.at("combinations").at("ULS").at("utilisation_max").get<double>(),
              355.0 / 235.0, 1e-9);
  EXPECT_NEAR(uls.at("delta_limit_m").get<double>(), s235.at("span_m").get<double>() / 200, 1e-12);
  EXPECT_LT(s235.at("combinations").at("SLS").at("delta_max_m").get<double>(),
            uls.at("delta_max_m").get<double>());
  for (const char* bad : {"--steel S999", "--loads wind", "--snow -1", "--glass nan"}) {
    const auto r = test::run_gridshell(std::string("baseline builtin:dome --kind quad --spacing 2 "
                                                   "--quiet -o ") +
                                       test::temp_dir("load_cases_bad").string() + " " + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find(std::string(bad).substr(0, std::string(bad).find(' '))), std::string::npos)
        << r.err;
  }
}

TEST(LoadCases, GoverningPicksTheWorstCombinationAndJudgesIt) {
  // Three combinations written by hand: the drifted ULS one has the smaller λ and the larger
  // utilisation, the drifted SLS one the larger δ — over its limit, so the design fails on δ
  // although the primary combinations pass everything.
  const nlohmann::json combinations = {
      {"ULS", {{"uls", true}, {"lambda", 2.5}, {"utilisation_max", 0.4}, {"delta_max_m", 0.05},
               {"delta_limit_m", 0.0667}}},
      {"ULS_S_x+", {{"uls", true}, {"lambda", 1.6}, {"utilisation_max", 0.9},
                    {"delta_max_m", 0.12}, {"delta_limit_m", 0.0667}}},
      {"SLS", {{"uls", false}, {"delta_max_m", 0.03}, {"delta_limit_m", 0.0667}}},
      {"SLS_S_x+", {{"uls", false}, {"delta_max_m", 0.09}, {"delta_limit_m", 0.0667}}}};
  const nlohmann::json g = governing_block(combinations);
  EXPECT_EQ(g.at("lambda"), "ULS_S_x+");
  EXPECT_DOUBLE_EQ(g.at("lambda_value").get<double>(), 1.6);
  EXPECT_TRUE(g.at("lambda_pass").get<bool>());
  EXPECT_EQ(g.at("utilisation"), "ULS_S_x+");
  EXPECT_TRUE(g.at("utilisation_pass").get<bool>());
  EXPECT_EQ(g.at("delta"), "SLS_S_x+");  // SLS combinations govern δ, not the factored ULS
  EXPECT_FALSE(g.at("delta_pass").get<bool>());
  EXPECT_FALSE(g.at("pass").get<bool>());
  // With the drifted SLS δ within its limit and λ below 1, λ alone fails the design.
  nlohmann::json c2 = combinations;
  c2["SLS_S_x+"]["delta_max_m"] = 0.06;
  c2["ULS_S_x+"]["lambda"] = 0.8;
  const nlohmann::json g2 = governing_block(c2);
  EXPECT_TRUE(g2.at("delta_pass").get<bool>());
  EXPECT_FALSE(g2.at("lambda_pass").get<bool>());
  EXPECT_FALSE(g2.at("pass").get<bool>());
  c2["ULS_S_x+"]["lambda"] = 1.2;
  EXPECT_TRUE(governing_block(c2).at("pass").get<bool>());
}
