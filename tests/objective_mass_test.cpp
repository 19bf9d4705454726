// design --objective mass: every candidate sized, the lightest sized one chosen and sized again at
// the full level; report.json's objective block agrees with the design's own sizing, the
// isotropic candidate agrees with a plain sized isotropic design, and the search repeats itself.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "gridshell/core/error.h"
#include "gridshell/pipeline/objective.h"
#include "gridshell/surfaces/load.h"
#include "test_support.h"

using gridshell::test::read_json;
using gridshell::test::run_gridshell;
using gridshell::test::temp_dir;
using nlohmann::json;

namespace {

// A small dome (30 cells): 11 sized candidates and one non-linear sizing in a few seconds.
const std::string kSearch = "design builtin:dome --cells 30 --seed 3 --objective mass --quiet "
                            "--figures none ";

json run_search(const std::string& name, int threads) {
  const auto dir = temp_dir(name);
  const auto r = run_gridshell(kSearch + "--threads " + std::to_string(threads) + " -o " +
                               dir.string());
  EXPECT_EQ(r.status, 0) << r.err;
  return read_json(dir / "report.json");
}

/// The blocks with the measured seconds taken out (they are the only thing allowed to differ).
json without_seconds(json j) {
  if (j.is_object()) {
    j.erase("seconds");
    for (auto& [k, v] : j.items()) v = without_seconds(v);
  } else if (j.is_array()) {
    for (auto& v : j) v = without_seconds(v);
  }
  return j;
}

}  // namespace

TEST(ObjectiveMass, ChoosesTheLightestSizedCandidateAndReportsItsFinalSizing) {
  const json report = run_search("objective_mass_a", 2);
  const json& o = report.at("objective");
  ASSERT_EQ(o.at("objective"), "mass");
  EXPECT_EQ(o.at("search_level"), "buckling");
  // --objective mass implies --size and the eurocode loads.
  EXPECT_EQ(report.at("structure").at("loads"), "eurocode");
  const json& cands = o.at("candidates");
  ASSERT_EQ(cands.size(), 11u);
  EXPECT_EQ(o.at("designs"), 11);

  // The isotropic design at the requested size is the first candidate; three sizes are tried.
  EXPECT_EQ(cands[0].at("source"), "uniform");
  EXPECT_EQ(cands[0].at("size"), 1.0);
  EXPECT_EQ(cands[0].at("cells"), 30);
  int uniform = 0;
  for (const json& c : cands) uniform += c.at("source") == "uniform";
  EXPECT_EQ(uniform, 3);

  // The invariant: the chosen candidate is the lightest of the sized ones that also passes its
  // sizing at the user's level (the ones lighter than it carry why they failed there, at most
  // three are tried); the isotropic best is the lightest sized isotropic one; the saving is
  // measured between those two at the search level.
  double lightest = std::numeric_limits<double>::infinity();
  double lightest_iso = lightest, heaviest_failed = 0;
  int sized = 0, failed = 0;
  for (const json& c : cands) {
    if (!c.at("ok").get<bool>()) continue;
    ++sized;
    EXPECT_TRUE(c.at("sized").get<bool>());
    EXPECT_LE(c.at("governing").at("ratio").get<double>(), 1.0 + 1e-9);
    if (c.contains("final_failure")) {
      ++failed;
      heaviest_failed = std::max(heaviest_failed, c.at("mass_kg").get<double>());
    } else {
      lightest = std::min(lightest, c.at("mass_kg").get<double>());
    }
    if (c.at("source") == "uniform")
      lightest_iso = std::min(lightest_iso, c.at("mass_kg").get<double>());
  }
  ASSERT_GE(sized, 3);
  EXPECT_LE(failed, 2);
  EXPECT_LE(heaviest_failed, lightest);
  const json& chosen = cands.at(o.at("chosen").get<int>());
  EXPECT_TRUE(chosen.at("ok").get<bool>());
  EXPECT_EQ(chosen.at("mass_kg").get<double>(), lightest);
  EXPECT_EQ(o.at("chosen_search_mass_kg").get<double>(), lightest);
  const json& iso = cands.at(o.at("isotropic_best").get<int>());
  EXPECT_EQ(iso.at("source"), "uniform");
  EXPECT_EQ(iso.at("mass_kg").get<double>(), lightest_iso);
  EXPECT_NEAR(o.at("mass_saving_vs_isotropic").get<double>(), 1 - lightest / lightest_iso, 1e-12);
  EXPECT_GE(o.at("mass_saving_vs_isotropic").get<double>(), 0.0);

  // The final sizing at the user's level (nonlinear) is the design's: objective.mass_kg is
  // report.json sizing.mass_kg, and the non-linear check can only keep or add steel.
  const json& s = report.at("sizing");
  ASSERT_TRUE(s.at("sized").get<bool>()) << s.dump();
  EXPECT_NEAR(o.at("mass_kg").get<double>(), s.at("mass_kg").get<double>(),
              1e-9 * s.at("mass_kg").get<double>());
  EXPECT_GE(s.at("mass_kg").get<double>(), lightest * (1 - 1e-9));
  bool verified = false;
  for (const json& h : s.at("history")) verified = verified || h.at("phase") == "verify";
  EXPECT_TRUE(verified) << "the chosen design was not sized at the non-linear level";

  // The isotropic candidate is the plain sized isotropic design of that size (independent run).
  const auto dir = temp_dir("objective_mass_iso");
  const auto r = run_gridshell("design builtin:dome --cells 30 --seed 3 --field uniform -D 1 -A 1 "
                               "--size --analyze buckling --quiet --figures none -o " +
                               dir.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const json plain = read_json(dir / "report.json").at("sizing");
  EXPECT_NEAR(cands[0].at("mass_kg").get<double>(), plain.at("mass_kg").get<double>(),
              1e-9 * plain.at("mass_kg").get<double>());

  // Deterministic for a seed whatever the thread count.
  const json again = run_search("objective_mass_b", 1);
  EXPECT_EQ(without_seconds(o), without_seconds(again.at("objective")));
  EXPECT_EQ(without_seconds(s), without_seconds(again.at("sizing")));
}

TEST(ObjectiveMass, ParsesAndNeedsAnAnalysis) {
  EXPECT_EQ(gridshell::parse_objective("mass"), gridshell::Objective::mass);
  EXPECT_STREQ(gridshell::to_string(gridshell::Objective::mass), "mass");
  const gridshell::Surface surface = gridshell::load_surface("builtin:dome", {});
  gridshell::DesignOptions base;
  base.tessellation.cells = 30;
  base.analyze = gridshell::analysis::AnalysisLevel::none;
  gridshell::ObjectiveOptions oo;
  oo.objective = gridshell::Objective::mass;
  EXPECT_THROW(gridshell::design_for_objective(surface, base, oo), gridshell::Error);
  // On the command line: one line, exit 2.
  const auto r = run_gridshell("design builtin:dome --cells 30 --objective mass --analyze none "
                               "--quiet -o " + temp_dir("objective_mass_none").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--objective"), std::string::npos) << r.err;
}
