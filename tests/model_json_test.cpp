// MODEL.json's analysis stop rule, materials' fy, load cases and combinations: what the reader
// makes of them, the errors it gives, and `gridshell analyze` end to end against closed forms.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/io/frame_model_json.h"
#include "test_support.h"

using namespace gridshell;
using nlohmann::json;

namespace {
// A steel cantilever along x, 2 m, solid Ø100 mm, clamped at node 0; `extra` is merged in.
json cantilever(const json& extra) {
  json m = json::parse(R"({
    "nodes": [[0, 0, 0], [2, 0, 0]],
    "sections": {"bar": {"shape": "circle", "diameter": 0.1}},
    "materials": {"steel": {"E": 210e9, "fy": 235e6}},
    "members": [{"nodes": [0, 1], "elements": 4}],
    "supports": [{"node": 0, "fix": ["ux", "uy", "uz", "rx", "ry", "rz"]}]
  })");
  m.update(extra);
  return m;
}

const json kCases = json::parse(R"({"load_cases": {
    "G": {"type": "permanent", "loads": [{"node": 1, "force": [0, 0, -1000]}]},
    "Q": {"type": "variable", "loads": [{"node": 1, "force": [0, 0, -2000]}]}}})");

std::string parse_error(const json& m) {
  try {
    io::parse_frame_model(m.dump(), "model.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(ModelJson, StopRuleKeys) {
  json m = cantilever(kCases);
  m["analysis"] = {{"stop_displacement", 0.5}, {"stop_lambda", 40}, {"max_steps", 25}};
  const io::FrameModelFile f = io::parse_frame_model(m.dump(), "model.json");
  EXPECT_EQ(f.analysis.stop_displacement, 0.5);
  EXPECT_EQ(f.analysis.stop_lambda, 40);
  EXPECT_EQ(f.analysis.max_steps, 25);
  for (const auto& [key, value, says] :
       {std::tuple{"stop_displacement", json(0), "analysis.stop_displacement must be > 0"},
        std::tuple{"stop_lambda", json(-1), "analysis.stop_lambda must be > 0"},
        std::tuple{"stop_lambda", json("big"), "analysis.stop_lambda must be a number"},
        std::tuple{"max_steps", json(0), "analysis.max_steps must be in 1..100000"},
        std::tuple{"max_steps", json(2.5), "analysis.max_steps must be an integer"}}) {
    json bad = cantilever(kCases);
    bad["analysis"] = {{key, value}};
    EXPECT_NE(parse_error(bad).find(says), std::string::npos) << key << ": " << parse_error(bad);
  }
}

TEST(ModelJson, MaterialYieldStrength) {
  const io::FrameModelFile f = io::parse_frame_model(cantilever(kCases).dump(), "m");
  EXPECT_EQ(f.model.materials[0].fy, 235e6);
  json bad = cantilever(kCases);
  bad["materials"]["steel"]["fy"] = 0;
  EXPECT_NE(parse_error(bad).find("materials.steel.fy must be a yield strength > 0"),
            std::string::npos);
}

// Without "combinations": ULS = 1.35 G + 1.5 Q (the primary, first) and SLS = G + Q.
TEST(ModelJson, LoadCasesAndDefaultCombinations) {
  const io::FrameModelFile f = io::parse_frame_model(cantilever(kCases).dump(), "m");
  ASSERT_EQ(f.combinations.size(), 2u);
  EXPECT_EQ(f.combinations[0].name, "ULS");
  EXPECT_EQ(f.combinations[1].name, "SLS");
  ASSERT_EQ(f.model.loads.size(), 1u);
  EXPECT_DOUBLE_EQ(f.model.loads[0].force.z(), -(1.35 * 1000 + 1.5 * 2000));
  EXPECT_DOUBLE_EQ(f.combinations[1].loads[0].force.z(), -3000);
  ASSERT_EQ(f.load_cases.size(), 2u);
  EXPECT_EQ(f.load_cases[0].type, "permanent");
  json given = cantilever(kCases);
  given["combinations"] = {{"accidental", {{"G", 1.0}, {"Q", 0.5}}}};
  const io::FrameModelFile g = io::parse_frame_model(given.dump(), "m");
  ASSERT_EQ(g.combinations.size(), 1u);
  EXPECT_DOUBLE_EQ(g.model.loads[0].force.z(), -2000);
}

TEST(ModelJson, LoadCaseErrors) {
  json both = cantilever(kCases);
  both["loads"] = json::array();
  EXPECT_NE(parse_error(both).find("either 'loads' or 'load_cases'"), std::string::npos);
  json orphan = cantilever(json::object());
  orphan["combinations"] = {{"ULS", {{"G", 1}}}};
  EXPECT_NE(parse_error(orphan).find("'combinations' need 'load_cases'"), std::string::npos);
  json type = cantilever(kCases);
  type["load_cases"]["Q"]["type"] = "wind";
  EXPECT_NE(parse_error(type).find("load_cases.Q.type must be 'permanent' or 'variable'"),
            std::string::npos);
  json unknown = cantilever(kCases);
  unknown["combinations"] = {{"ULS", {{"S", 1.5}}}};
  EXPECT_NE(parse_error(unknown).find("combinations.ULS: unknown load case 'S'"),
            std::string::npos);
  json negative = cantilever(kCases);
  negative["combinations"] = {{"ULS", {{"G", -1}}}};
  EXPECT_NE(parse_error(negative).find("combinations.ULS.G must be >= 0"), std::string::npos);
  json node = cantilever(kCases);
  node["load_cases"]["G"]["loads"][0]["node"] = 7;
  EXPECT_NE(parse_error(node).find("a load refers to node 7"), std::string::npos);
}

// The cantilever's combinations in report.json against the closed forms: tip load P, moment
// P L at the clamp, u = P L / (W fy) with W = π d³ / 32; SLS tip deflection P L³ / (3 E I).
TEST(ModelJsonCli, CombinationsMatchClosedForms) {
  const auto dir = test::temp_dir("model_combinations");
  io::write_file_atomic(dir / "m.json", cantilever(kCases).dump());
  const auto r =
      test::run_gridshell(fmt::format("analyze '{}' -o '{}' --quiet --figures none",
                                      (dir / "m.json").string(), (dir / "out").string()));
  ASSERT_EQ(r.status, 0) << r.err;
  const json s = json::parse(io::read_file(dir / "out" / "report.json"))["structure"];
  const double L = 2, d = 0.1, fy = 235e6, E = 210e9, pi = std::numbers::pi;
  const double W = pi * d * d * d / 32, I = pi * std::pow(d, 4) / 64;
  const json& c = s["combinations"];
  EXPECT_EQ(s["loads"], "load_cases");
  EXPECT_EQ(c["ULS"]["factors"]["G"], 1.35);
  EXPECT_EQ(c["ULS"]["factors"]["Q"], 1.5);
  EXPECT_NEAR(c["ULS"]["utilisation_max"].get<double>() / (4350 * L / (W * fy)), 1, 0.005);
  EXPECT_NEAR(c["SLS"]["utilisation_max"].get<double>() / (3000 * L / (W * fy)), 1, 0.005);
  EXPECT_NEAR(c["SLS"]["delta_max_m"].get<double>() / (3000 * L * L * L / (3 * E * I)), 1, 0.005);
  EXPECT_EQ(c["SLS"]["delta_pass"], false);  // 7.8 mm > 2 m / 300
  EXPECT_NEAR(s["utilisation_max"].get<double>(), c["ULS"]["utilisation_max"].get<double>(), 1e-12);
}

// The stop rule from MODEL.json's analysis keys and from the command line (which wins).
TEST(ModelJsonCli, StopRuleEndsThePath) {
  const auto dir = test::temp_dir("model_stop");
  json m = cantilever(kCases);
  m["analysis"] = {{"nonlinear", true}, {"stop_lambda", 2}};
  io::write_file_atomic(dir / "m.json", m.dump());
  const auto report = [&](const std::string& extra) {
    const auto r = test::run_gridshell(
        fmt::format("analyze '{}' -o '{}' --quiet --figures none --single-path {}",
                    (dir / "m.json").string(), (dir / "out").string(), extra));
    EXPECT_EQ(r.status, 0) << r.err;
    return json::parse(io::read_file(dir / "out" / "report.json"))["structure"];
  };
  json s = report("");
  EXPECT_EQ(s["nonlinear_stop_reason"], "maximum load factor reached");
  EXPECT_EQ(s["limit_type"], "none");
  EXPECT_GE(s["lambda_nonlinear"].get<double>(), 2);
  s = report("--stop-lambda 1e6 --stop-displacement 0.05");
  EXPECT_EQ(s["nonlinear_stop_reason"], "maximum displacement reached");
  s = report("--stop-lambda 1e6 --max-steps 3");
  EXPECT_EQ(s["nonlinear_stop_reason"], "maximum number of steps");
  for (const char* bad :
       {"--stop-lambda -1", "--stop-displacement nan", "--max-steps -2", "--area-load 1"}) {
    // (--area-load: the model has load cases, the area load belongs in one of them)
    const auto r = test::run_gridshell(fmt::format(
        "analyze '{}' -o '{}' --quiet {}", (dir / "m.json").string(), (dir / "bad").string(), bad));
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find(std::string(bad).substr(0, std::string(bad).find(' '))), std::string::npos)
        << r.err;
  }
}
