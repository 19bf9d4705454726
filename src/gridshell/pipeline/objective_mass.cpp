// `design --objective mass` (objective.h): every candidate's members sized at the cheap level
// (λ_LBA), the lightest sized one sized again at the user's level.

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "gridshell/core/error.h"
#include "gridshell/field/frame_response.h"
#include "gridshell/pipeline/objective_search.h"
#include "gridshell/pipeline/structure.h"

namespace gridshell::objective_detail {

namespace {

/// The cell sizes tried, as factors of the requested cell count (round 1: the isotropic design
/// at all three, every field at 1; round 2: the lightest field at the other two).
constexpr std::array<double, 3> kSizes{0.75, 1.0, 1.33};

/// `t` at `factor` × its cell count: cells × factor, radius ÷ √factor, length × √factor (the
/// total beam length of a tessellation grows as the square root of its cell count).
void scale_size(TessellationOptions& t, double factor) {
  if (factor == 1) return;
  if (t.cells > 0)
    t.cells = std::max(1, static_cast<int>(std::lround(t.cells * factor)));
  else if (t.radius > 0)
    t.radius /= std::sqrt(factor);
  else if (t.length > 0)
    t.length *= std::sqrt(factor);
  else
    t.cells = std::max(1, static_cast<int>(std::lround(t.default_cells * factor)));
}

/// What every candidate shares: the sizing at the search level.
struct MassSearch {
  const Surface& surface;
  const DesignOptions& base;
  sizing::SizingOptions sizing;
  analysis::AnalysisLevel level = analysis::AnalysisLevel::buckling;
  DesignCache cache;
};

DesignOptions mass_options(const MassSearch& m, const FieldSetting& s) {
  DesignOptions o = candidate_options(m.base, s, 0);
  o.frame_analysis.buckling_modes = m.base.frame_analysis.buckling_modes;  // the sizing's LBA
  o.analyze = m.level;
  o.sizing = sizing::MemberSizing::sized;
  o.sizing_options = m.sizing;
  scale_size(o.tessellation, s.size);
  return o;
}

/// The check closest to its limit in the sizing's last iteration: member checks (EN 1993-1-1
/// §6.2/§6.3, largest utilisation), deflection (SLS δ / limit) or stability (λ_min / λ).
void governing_check(const sizing::SizingResult& s, double lambda_min, Candidate& c) {
  if (s.history.empty()) return;
  const sizing::SizingStep& h = s.history.back();
  const std::array<std::pair<const char*, double>, 3> ratios{
      {{"member", h.utilisation_max},
       {"deflection", h.delta_ratio},
       {"stability", h.lambda > 0 ? lambda_min / h.lambda : 0.0}}};
  for (const auto& [name, ratio] : ratios)
    if (ratio > c.governing_ratio) c.governing = name, c.governing_ratio = ratio;
}

/// Designs and sizes one candidate. A failure marks it failed, unless `rethrow` (the reference:
/// its failure is the user's).
Evaluated evaluate_mass(MassSearch& m, const FieldSetting& s, const GivenStress* stress, int round,
                        bool rethrow = false) {
  CandidateJudge how;
  how.options = [&] { return mass_options(m, s); };
  how.judge = [&](const DesignOptions& o, const DesignResult& r, Candidate& c) {
    if (r.structure) {
      c.delta = r.structure->delta_max_m;
      c.lambda = r.structure->lambda_linear_buckling.value_or(0.0);
    }
    if (!r.sizing) {
      c.error = "no sizing";
      return;
    }
    c.sized = r.sizing->sized;
    c.mass_kg = sizing::steel_mass(r.mesh, analysed_frame(o, r));
    governing_check(*r.sizing, m.sizing.lambda_min, c);
    c.ok = c.sized && std::isfinite(c.mass_kg) && c.mass_kg > 0;
    if (!c.sized) c.error = r.sizing->failure;
  };
  how.summary = [](const Candidate& c) {
    return fmt::format("{:.0f} kg, {} cells, governed by {} ({:.2f})", c.mass_kg, c.cells,
                       c.governing, c.governing_ratio);
  };
  how.failed = "not sized";
  return evaluate_candidate({m.surface, s, stress, m.cache, round, rethrow}, how);
}

/// The reference (isotropic, requested size) with the shell-stress candidates' shared values
/// (stress, fields, M′) computed meanwhile on the other thread.
Evaluated reference_beside_warm_up(MassSearch& m) {
  tbb::task_group group;
  group.run([&] {
    try {  // a failure is met again, and judged, by the candidate that needs the value
      for (const FieldSetting& s : shell_settings())
        prepare_design_cache(m.surface, mass_options(m, s), m.cache);
    } catch (...) {
    }
  });
  std::optional<Evaluated> reference;
  try {
    reference = evaluate_mass(m, FieldSetting{}, nullptr, 1, true);
  } catch (...) {
    group.wait();
    throw;
  }
  group.wait();
  return std::move(*reference);
}

using Pending = std::vector<std::pair<FieldSetting, const GivenStress*>>;

void evaluate_round(MassSearch& m, const Pending& pending, int round, SearchProgress& progress,
                    std::vector<Evaluated>& all) {
  std::vector<Evaluated> out(pending.size());
  tbb::parallel_for(0, static_cast<int>(pending.size()), [&](int i) {
    if (stop_requested(progress.options.stop)) return;
    out[i] = evaluate_mass(m, pending[i].first, pending[i].second, round);
    progress.one_more();
  });
  if (stop_requested(progress.options.stop)) throw Stopped{};
  for (Evaluated& e : out) all.push_back(std::move(e));
}

/// Round 1: the isotropic design at the other sizes, the four shell-stress conventions and the
/// reference's two frame responses (kept in `responses`), within `max_designs` in all.
Pending first_round(MassSearch& m, const DesignResult& reference, const GivenStress& shell,
                    std::deque<GivenStress>& responses, int max_designs) {
  Pending round;
  for (double f : kSizes) {
    if (f == 1) continue;
    FieldSetting s;
    s.size = f;
    round.emplace_back(s, nullptr);
  }
  for (const FieldSetting& s : shell_settings()) round.emplace_back(s, &shell);
  add_response_candidates(m.surface, reference, mass_options(m, FieldSetting{}), m.cache, responses,
                          round);
  if (static_cast<int>(round.size()) > max_designs - 1)
    round.resize(static_cast<std::size_t>(std::max(0, max_designs - 1)));
  return round;
}

/// The lightest sized candidate whose source `keep` accepts (-1: none); ties to the first.
template <class Keep>
int lightest(const std::vector<Evaluated>& all, Keep keep) {
  int best = -1;
  for (int i = 0; i < static_cast<int>(all.size()); ++i) {
    const Candidate& c = all[i].candidate;
    if (c.ok && keep(c.setting) && (best < 0 || c.mass_kg < all[best].candidate.mass_kg)) best = i;
  }
  return best;
}

/// Round 2: the lightest field candidate of round 1 at the other sizes.
Pending second_round(const std::vector<Evaluated>& all, int max_designs) {
  Pending round;
  const int best =
      lightest(all, [](const FieldSetting& s) { return s.source != FieldSource::uniform; });
  if (best < 0) return round;
  for (double f : kSizes) {
    if (f == 1 || static_cast<int>(all.size() + round.size()) >= max_designs) continue;
    FieldSetting s = all[best].candidate.setting;
    s.size = f;
    round.emplace_back(s, all[best].field);
  }
  return round;
}

/// The sized candidates, lightest first (ties: the first); the reference alone when none is.
std::vector<int> by_mass(const std::vector<Evaluated>& all) {
  std::vector<int> order;
  for (int i = 0; i < static_cast<int>(all.size()); ++i)
    if (all[i].candidate.ok) order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&all](int a, int b) {
    return all[a].candidate.mass_kg < all[b].candidate.mass_kg;
  });
  if (order.empty()) order.push_back(0);
  return order;
}

/// How many candidates, lightest first, are sized at the user's level before the lightest is
/// kept even though it fails there: each is a full sizing with non-linear paths.
constexpr std::size_t kFinalTries = 3;

/// Why the chosen candidate was kept, and which lighter ones failed at the user's level.
std::string mass_reason(const ObjectiveResult& res, const MassSearch& m, bool any_sized) {
  if (!any_sized) {
    return fmt::format(
        "no candidate could be sized at analysis level {}: the isotropic design at the "
        "requested size is kept, and its sizing at the full level says what fails",
        to_string(m.level));
  }
  const Candidate& c = res.candidates[res.chosen];
  std::string failed;
  int tried = 0;
  for (const Candidate& e : res.candidates) {
    if (e.final_failure.empty()) continue;
    ++tried;
    failed += fmt::format("{}{}: {}", failed.empty() ? "" : "; ", e.setting.label(),
                          e.final_failure);
  }
  const auto sized = std::count_if(res.candidates.begin(), res.candidates.end(),
                                   [](const Candidate& e) { return e.ok; });
  const std::string which =
      failed.empty() ? fmt::format("the lightest of the {} sized candidates", sized)
      : c.final_failure.empty()
          ? fmt::format("the lightest of the {} sized candidates that also passes at level {} "
                        "(lighter, failing there: {})",
                        sized, to_string(m.base.analyze), failed)
          : fmt::format("the lightest of the {} sized candidates, kept although none of the {} "
                        "lightest passes at level {} ({})",
                        sized, tried, to_string(m.base.analyze), failed);
  if (res.isotropic_best < 0) {
    return fmt::format("{} is {} ({:.0f} kg at level {}); no isotropic design could be sized",
                       c.setting.label(), which, c.mass_kg, to_string(m.level));
  }
  const Candidate& iso = res.candidates[res.isotropic_best];
  return fmt::format("{} is {} ({:.0f} kg at level {}), {:.1f} % lighter than the lightest "
                     "isotropic design ({}, {:.0f} kg)",
                     c.setting.label(), which, c.mass_kg, to_string(m.level),
                     100 * res.mass_saving_vs_isotropic, iso.setting.label(), iso.mass_kg);
}

/// The lightest sized candidate that also passes when sized again at the user's level (the
/// lightest, then the next ones, kFinalTries at most; the lightest when none passes), and why.
ObjectiveResult choose_lightest(std::vector<Evaluated>& all, MassSearch& m,
                                const ObjectiveOptions& options) {
  ObjectiveResult res;
  res.objective = Objective::mass;
  res.search_level = m.level;
  for (const Evaluated& e : all) res.candidates.push_back(e.candidate);
  res.isotropic_best =
      lightest(all, [](const FieldSetting& s) { return s.source == FieldSource::uniform; });
  const std::vector<int> order = by_mass(all);
  DesignResult lightest_design;
  for (std::size_t k = 0; k < order.size() && k < kFinalTries; ++k) {
    if (stop_requested(options.stop)) throw Stopped{};
    const int i = order[k];
    DesignResult d = std::move(*all[i].design);
    carry_field_to_input(m.surface, d, m.cache);
    if (m.base.analyze != m.level) {
      GridshellStructure s =
          analyze_structure(d.mesh, d.supports, m.base.frame, m.base.frame_analysis,
                            {m.base.analyze, sizing::MemberSizing::sized, m.sizing});
      d.structure = std::move(s.result);
      d.sizing = std::move(s.sizing);
    }
    const bool passes = m.base.analyze == m.level || !d.sizing || d.sizing->sized;
    if (passes || !all[i].candidate.ok) {
      res.chosen = i;
      res.design = std::move(d);
      break;
    }
    res.candidates[static_cast<std::size_t>(i)].final_failure = d.sizing->failure;
    spdlog::info("[objective] {} fails at level {} ({}); trying the next lightest",
                 all[i].candidate.setting.label(), to_string(m.base.analyze), d.sizing->failure);
    if (k == 0) lightest_design = std::move(d);
    if (k + 1 == order.size() || k + 1 == kFinalTries) {
      res.chosen = order[0];
      res.design = std::move(lightest_design);
    }
  }
  const Candidate& c = res.candidates[res.chosen];
  if (res.isotropic_best >= 0 && c.ok)
    res.mass_saving_vs_isotropic = 1 - c.mass_kg / res.candidates[res.isotropic_best].mass_kg;
  res.reason = mass_reason(res, m, all[order[0]].candidate.ok);
  res.mass_kg = sizing::steel_mass(res.design.mesh, analysed_frame(m.base, res.design));
  spdlog::info("[objective] chose {} ({}); sized at level {}: {:.0f} kg, {}", c.setting.label(),
               res.reason, to_string(m.base.analyze), res.mass_kg,
               res.design.sizing && res.design.sizing->sized ? "passes every check" : "NOT sized");
  return res;
}

}  // namespace

ObjectiveResult design_for_mass(const Surface& surface, const DesignOptions& base,
                                const ObjectiveOptions& options) {
  const auto t0 = Clock::now();
  if (base.analyze == analysis::AnalysisLevel::none)
    throw Error("--objective",
                "mass sizes the members: it needs --analyze linear, buckling or "
                "nonlinear");
  if (options.max_designs < 1) throw Error("objective", "max_designs must be at least 1");
  MassSearch m{surface, base, base.sizing_options, analysis::AnalysisLevel::buckling, {}};
  if (m.sizing.catalogue.empty()) m.sizing.catalogue = sizing::parse_section_list("chs");
  // The search's λ check is the cheap one (λ_LBA); a linear-only request skips it.
  m.level = base.analyze == analysis::AnalysisLevel::linear ? analysis::AnalysisLevel::linear
                                                            : analysis::AnalysisLevel::buckling;
  ObjectiveOptions bounded = options;
  bounded.max_designs = std::min(options.max_designs, 11);
  SearchProgress progress{bounded};
  report_progress(options.progress, "objective search", 0, "the isotropic reference");
  std::vector<Evaluated> all;
  all.push_back(reference_beside_warm_up(m));
  progress.one_more();
  if (stop_requested(options.stop)) throw Stopped{};
  const GivenStress shell;  // stands for the shell stress, which the cache computes once
  std::deque<GivenStress> responses;
  if (all[0].design)
    evaluate_round(m, first_round(m, *all[0].design, shell, responses, bounded.max_designs), 1,
                   progress, all);
  if (options.rounds >= 2)
    evaluate_round(m, second_round(all, bounded.max_designs), 2, progress, all);
  report_progress(options.progress, "objective search", 1, fmt::format("{} designs", all.size()));
  ObjectiveResult res = choose_lightest(all, m, options);
  res.seconds = seconds_since(t0);
  return res;
}

nlohmann::json mass_report(const ObjectiveResult& r) {
  nlohmann::json j;
  j["objective"] = to_string(r.objective);
  j["search_level"] = to_string(r.search_level);
  j["chosen"] = r.chosen;
  j["chosen_label"] = r.candidates[r.chosen].setting.label();
  j["reason"] = r.reason;
  j["seconds"] = r.seconds;
  j["designs"] = r.candidates.size();
  j["chosen_search_mass_kg"] = r.candidates[r.chosen].mass_kg;
  j["mass_kg"] = r.mass_kg;  // after the final sizing at the user's level
  if (r.isotropic_best >= 0) {
    j["isotropic_best"] = r.isotropic_best;
    j["isotropic_best_label"] = r.candidates[r.isotropic_best].setting.label();
    j["isotropic_mass_kg"] = r.candidates[r.isotropic_best].mass_kg;
    j["mass_saving_vs_isotropic"] = r.mass_saving_vs_isotropic;
  } else {
    j["isotropic_best"] = nullptr;
    j["mass_saving_vs_isotropic"] = nullptr;
  }
  nlohmann::json list = nlohmann::json::array();
  for (const Candidate& c : r.candidates) {
    nlohmann::json e = candidate_entry(c);
    e["size"] = c.setting.size;
    e["sized"] = c.sized;
    if (c.cells > 0) {
      e["cells"] = c.cells;
      e["total_length_m"] = c.length;
      e["mass_kg"] = c.mass_kg;
    }
    if (!c.governing.empty())
      e["governing"] = {{"check", c.governing}, {"ratio", c.governing_ratio}};
    if (c.lambda > 0) e["lambda_linear_buckling"] = c.lambda;
    if (c.delta > 0) e["delta_max_m"] = c.delta;
    if (!c.error.empty()) e["failure"] = c.error;
    if (!c.final_failure.empty()) e["final_failure"] = c.final_failure;
    list.push_back(e);
  }
  j["candidates"] = list;
  return j;
}

}  // namespace gridshell::objective_detail
