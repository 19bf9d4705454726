// design --objective: the search's reference is the isotropic Voronoi baseline, and the choice
// obeys each objective's rule over the candidates it reports.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <tbb/task_arena.h>

#include <cmath>

#include "gridshell/core/error.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/objective.h"
#include "gridshell/pipeline/objective_search.h"
#include "gridshell/surfaces/load.h"

using namespace gridshell;

namespace {

DesignOptions small_design() {
  DesignOptions o;
  o.tessellation.cells = 90;
  o.tessellation.seed = 5;
  o.analyze = analysis::AnalysisLevel::buckling;
  return o;
}

}  // namespace

TEST(Objective, ReferenceIsTheIsotropicBaselineAndTheChoiceFollowsTheRule) {
  const Surface surface = load_surface("builtin:funicular:res=24", {});
  const DesignOptions base = small_design();

  // The reference: the same as an isotropic design (baseline --kind voronoi-iso) of that size.
  DesignOptions iso = base;
  iso.field = FieldInput::uniform;
  iso.field_options.D = iso.field_options.A = 1;
  const DesignResult plain = run_design(surface, iso);
  ASSERT_TRUE(plain.structure && plain.structure->lambda_linear_buckling);

  for (Objective objective : {Objective::lambda, Objective::delta, Objective::balanced}) {
    ObjectiveOptions oo;
    oo.objective = objective;
    std::mutex m;
    std::vector<std::pair<double, std::string>> told;  // the progress listener's calls
    oo.progress = [&](std::string_view stage, double fraction, std::string_view detail) {
      const std::lock_guard lock(m);
      EXPECT_EQ(stage, "objective search");
      told.emplace_back(fraction, std::string(detail));
    };
    const ObjectiveResult r = design_for_objective(surface, base, oo);
    ASSERT_GE(r.candidates.size(), 6u);
    // Progress: a start, one call per candidate designed, and the end with the count.
    ASSERT_EQ(told.size(), r.candidates.size() + 2);
    EXPECT_EQ(told.front().first, 0.0);
    for (std::size_t k = 1; k + 1 < told.size(); ++k) EXPECT_LT(told[k].first, 1.0);
    EXPECT_EQ(told.back(), std::make_pair(1.0, fmt::format("{} designs", r.candidates.size())));
    const Candidate& ref = r.candidates.front();
    EXPECT_EQ(ref.setting.source, FieldSource::uniform);
    EXPECT_DOUBLE_EQ(ref.lambda, *plain.structure->lambda_linear_buckling);
    EXPECT_DOUBLE_EQ(ref.delta, plain.structure->delta_max_m);
    EXPECT_DOUBLE_EQ(ref.length, plain.metrics.total_length);
    // Every other candidate was designed at the reference's length (±5 %).
    int ok = 0;
    for (const Candidate& c : r.candidates) {
      if (!c.ok) continue;
      ++ok;
      EXPECT_NEAR(c.length / ref.length, 1.0, 0.05) << c.setting.label();
    }
    EXPECT_GE(ok, 5);
    const Candidate& chosen = r.candidates[r.chosen];
    ASSERT_TRUE(chosen.ok);
    for (const Candidate& c : r.candidates) {
      if (!c.ok) continue;
      if (objective == Objective::lambda) {
        EXPECT_GE(chosen.lambda, c.lambda) << c.setting.label();
      }
      if (objective == Objective::delta) {
        EXPECT_LE(chosen.delta, c.delta) << c.setting.label();
      }
    }
    if (objective == Objective::balanced) {
      EXPECT_GE(chosen.lambda, (1 - oo.tolerance) * ref.lambda);
      EXPECT_LE(chosen.delta, ref.delta * (1 + oo.tolerance));
    }
    // The design handed back is the chosen one.
    EXPECT_EQ(r.design.mesh.num_faces(), chosen.cells);
    ASSERT_TRUE(r.design.structure);
    EXPECT_DOUBLE_EQ(r.design.structure->delta_max_m, chosen.delta);
    // Candidates look for the first buckling mode only; the chosen design has the options' five,
    // and the first of them is the candidate's λ₁ to the eigensolver's round-off.
    ASSERT_EQ(r.design.structure->buckling_lambdas.size(),
              static_cast<std::size_t>(base.frame_analysis.buckling_modes));
    EXPECT_NEAR(r.design.structure->buckling_lambdas.front() / chosen.lambda, 1.0, 1e-10);
    const auto j = r.report();
    EXPECT_EQ(j.at("candidates").size(), r.candidates.size());
    EXPECT_EQ(j.at("chosen").get<int>(), r.chosen);
  }
}

TEST(Objective, WordsAndBadOptions) {
  EXPECT_EQ(parse_objective("delta"), Objective::delta);
  EXPECT_STREQ(to_string(Objective::balanced), "balanced");
  EXPECT_THROW(parse_objective("strongest"), Error);
  ObjectiveOptions bad;
  bad.tolerance = -1;
  const Surface surface = load_surface("builtin:funicular:res=12", {});
  EXPECT_THROW(design_for_objective(surface, small_design(), bad), Error);
}

TEST(Objective, AStopRequestEndsTheSearchBeforeItsNextCandidate) {
  const Surface surface = load_surface("builtin:funicular:res=24", {});
  ObjectiveOptions oo;
  std::atomic<int> designed{0};
  oo.progress = [&](std::string_view, double fraction, std::string_view) {
    if (fraction > 0 && fraction < 1) ++designed;
  };
  // Stop once two candidates are done: candidates already running finish, no new one starts.
  oo.stop = [&] { return designed >= 2; };
  EXPECT_THROW(design_for_objective(surface, small_design(), oo), Stopped);
  const int running_at_most = tbb::this_task_arena::max_concurrency();
  EXPECT_GE(designed, 2);
  // (On two cores at most 4 of the search's ≥ 7 candidates: the test above.)
  EXPECT_LE(designed, 2 + running_at_most) << "the search went on after the stop request";
}

// The paraboloid is in compression everywhere, so a tension-driven field is the same for every
// D and A: the search's variations of such a setting are the same design, taken over from the
// first instead of made again. Made anew from scratch, each is that design bit for bit.
TEST(Objective, ACandidateWithAnEarlierCandidatesFieldTakesItsDesign) {
  const Surface surface = load_surface("builtin:paraboloid", {});
  DesignOptions base = small_design();
  base.tessellation.cells = 200;  // (at 90 cells no tension-driven candidate is varied)
  const ObjectiveResult r = design_for_objective(surface, base, ObjectiveOptions{});
  const double length = r.candidates.front().length;
  int twins = 0;
  for (const Candidate& c : r.candidates) {
    if (c.same_as.empty()) continue;
    ++twins;
    EXPECT_EQ(c.setting.measure, StressMeasure::tension) << c.setting.label();
    const auto original =
        std::find_if(r.candidates.begin(), r.candidates.end(),
                     [&](const Candidate& o) { return o.setting.label() == c.same_as; });
    ASSERT_NE(original, r.candidates.end()) << c.same_as;
    EXPECT_TRUE(original->same_as.empty());
    EXPECT_EQ(c.lambda, original->lambda);
    EXPECT_EQ(c.delta, original->delta);
    const DesignResult made =
        run_design(surface, objective_detail::candidate_options(base, c.setting, length));
    ASSERT_TRUE(made.structure && made.structure->lambda_linear_buckling);
    EXPECT_EQ(*made.structure->lambda_linear_buckling, c.lambda) << c.setting.label();
    EXPECT_EQ(made.structure->delta_max_m, c.delta) << c.setting.label();
    EXPECT_EQ(made.metrics.total_length, c.length) << c.setting.label();
    EXPECT_EQ(made.mesh.num_faces(), c.cells) << c.setting.label();
  }
  EXPECT_GE(twins, 1);
  EXPECT_EQ(r.report().at("candidates").at(r.candidates.size() - 1).contains("same_design_as"),
            !r.candidates.back().same_as.empty());
}
