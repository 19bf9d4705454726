#include "gridshell/pipeline/objective.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <deque>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "gridshell/core/enum_words.h"
#include "gridshell/core/error.h"
#include "gridshell/field/frame_response.h"
#include "gridshell/pipeline/objective_search.h"
#include "gridshell/pipeline/structure.h"

namespace gridshell {

namespace objective_detail {

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// A field candidate is judged by λ₁ and δ alone, so its buckling analysis looks for the first
/// mode only (the Lanczos iteration converges in fewer steps than for five); the chosen design is
/// analysed again as the options ask. The isotropic design keeps the options' modes: its mode
/// energy (the modes within 10 % of λ₁) is the frame-mode candidates' field.
constexpr int kCandidateModes = 1;

DesignOptions candidate_options(const DesignOptions& base, const FieldSetting& s, double length) {
  DesignOptions o = base;
  if (s.source != FieldSource::uniform) o.frame_analysis.buckling_modes = kCandidateModes;
  o.field_options.D = s.D;
  o.field_options.A = s.A;
  o.field = s.source == FieldSource::uniform ? FieldInput::uniform : FieldInput::stress;
  o.field_options.measure = s.measure;
  o.field_options.stretch = s.stretch;
  o.field_options.density = s.density;
  o.analyze = analysis::AnalysisLevel::buckling;
  o.sizing = sizing::MemberSizing::given;  // judged at the given section; the choice is sized
  o.field_on_input = false;  // the chosen design's field is carried to the input in the end
  if (length > 0) {
    o.tessellation.length = length;
    o.tessellation.cells = 0;
    o.tessellation.radius = 0;
  }
  return o;
}

/// Round 1's shell-stress settings: the four conventions at D = A = 2.
std::vector<FieldSetting> shell_settings() {
  // (Across + falling, and frame-response fields with A = 2, were tried too and never came out
  // best on the surfaces of docs/field.md: left out to keep the search affordable.)
  struct Convention {
    StressMeasure measure;
    StretchAxis stretch;
    DensityTrend density;
  };
  std::vector<FieldSetting> out;
  for (const Convention& c :
       {Convention{StressMeasure::magnitude, StretchAxis::along, DensityTrend::rising},
        Convention{StressMeasure::magnitude, StretchAxis::along, DensityTrend::falling},
        Convention{StressMeasure::magnitude, StretchAxis::across, DensityTrend::rising},
        Convention{StressMeasure::tension, StretchAxis::along, DensityTrend::rising}}) {
    FieldSetting s;
    s.source = FieldSource::shell_stress;
    s.D = s.A = 2;
    s.measure = c.measure;
    s.stretch = c.stretch;
    s.density = c.density;
    out.push_back(s);
  }
  return out;
}

const std::vector<double>* response_values(const DesignResult& r, FieldSource source) {
  if (!r.structure) return nullptr;
  const auto& v =
      source == FieldSource::frame_mode ? r.structure->mode_energy : r.structure->strain_energy;
  return v.empty() ? nullptr : &v;
}

void SearchProgress::one_more() {
  const int n = ++designed;
  report_progress(options.progress, "objective search",
                  std::min(0.99, static_cast<double>(n) / options.max_designs),
                  fmt::format("{} designs", n));
}

nlohmann::json candidate_entry(const Candidate& c) {
  nlohmann::json e = {{"label", c.setting.label()}, {"source", to_string(c.setting.source)},
                      {"D", c.setting.D},           {"A", c.setting.A},
                      {"round", c.round},           {"ok", c.ok},
                      {"seconds", c.seconds}};
  if (c.setting.source == FieldSource::shell_stress) {
    e["stress_measure"] = to_string(c.setting.measure);
    e["stretch"] = to_string(c.setting.stretch);
    e["density"] = to_string(c.setting.density);
  }
  if (c.setting.feedback > 0) e["feedback"] = c.setting.feedback;
  if (!c.same_as.empty()) e["same_design_as"] = c.same_as;
  return e;
}

Evaluated evaluate_candidate(const CandidateRun& run, const CandidateJudge& how) {
  const auto t = Clock::now();
  Evaluated ev;
  ev.field = run.stress;
  ev.candidate.setting = run.setting;
  ev.candidate.round = run.round;
  try {
    const DesignOptions o = how.options();
    const FieldSource source = run.setting.source;
    const bool response = source == FieldSource::frame_mode || source == FieldSource::frame_energy;
    DesignResult r = response ? run_design(run.surface, o, *run.stress, run.cache)
                              : run_design(run.surface, o, run.cache);
    ev.candidate.length = r.metrics.total_length;
    ev.candidate.cells = r.mesh.num_faces();
    how.judge(o, r, ev.candidate);
    ev.design = std::move(r);
  } catch (const Error& e) {
    if (run.rethrow) throw;
    ev.candidate.error = e.message();
  }
  ev.candidate.seconds = seconds_since(t);
  spdlog::info("[objective] {}: {}", run.setting.label(),
               ev.candidate.ok ? how.summary(ev.candidate)
                               : fmt::format("{}: {}", how.failed, ev.candidate.error));
  return ev;
}

}  // namespace objective_detail

namespace {

using namespace objective_detail;

/// Designs and judges one candidate at equal length (λ_LBA and δ); the reference rethrows.
/// Shell-stress and uniform candidates share the analysis surface, the shell stress, their
/// fields and M′ through `cache`; a frame response is a stress per input triangle.
Evaluated evaluate(const Surface& surface, const DesignOptions& base, const FieldSetting& s,
                   const GivenStress* stress, DesignCache& cache, double length, int round,
                   bool rethrow = false) {
  CandidateJudge how;
  how.options = [&] { return candidate_options(base, s, length); };
  how.judge = [&](const DesignOptions&, const DesignResult& r, Candidate& c) {
    if (r.structure) {
      c.delta = r.structure->delta_max_m;
      c.lambda = r.structure->lambda_linear_buckling.value_or(0.0);
      c.ok = c.delta > 0 && std::isfinite(c.delta);
    }
    if (!c.ok) c.error = "no frame result";
    // Judged only at the same steel: a candidate whose total length missed the target by more
    // than --length's tolerance is not comparable.
    const double off = length > 0 ? c.length / length - 1 : 0.0;
    if (c.ok && std::abs(off) > base.tessellation.length_tolerance) {
      c.ok = false;
      c.error = fmt::format("total length {:.1f} m is {:+.1f} % off the target", c.length,
                            100 * off);
    }
  };
  how.summary = [](const Candidate& c) {
    return fmt::format("lambda_LBA = {:.4g}, delta = {:.4g} m, {:.1f} m", c.lambda, c.delta,
                       c.length);
  };
  return evaluate_candidate({surface, s, stress, cache, round, rethrow}, how);
}

/// Relative gains over the reference: positive = better.
double lambda_gain(const Candidate& c, const Candidate& ref) {
  return ref.lambda > 0 ? c.lambda / ref.lambda - 1 : 0.0;
}
double delta_gain(const Candidate& c, const Candidate& ref) {  // the share of δ taken away
  return ref.delta > 0 ? 1 - c.delta / ref.delta : 0.0;
}

/// Score of a candidate under the objective; -inf when it is not admissible.
double score(const Candidate& c, const Candidate& ref, const ObjectiveOptions& o) {
  if (!c.ok) return -HUGE_VAL;
  const double gl = lambda_gain(c, ref), gd = delta_gain(c, ref);
  switch (o.objective) {
    case Objective::lambda:
      return c.lambda > 0 ? gl : -HUGE_VAL;
    case Objective::delta:
      return gd;
    case Objective::balanced:
      // Both figures within the tolerance of the reference; then the larger gain, and of two
      // equal larger gains the one with the better other figure.
      if (gl < -o.tolerance || gd < -o.tolerance) return -HUGE_VAL;
      return std::max(gl, gd) + 0.25 * std::min(gl, gd);
    case Objective::mass:  // judged by objective_mass.cpp, never here
      return -HUGE_VAL;
  }
  return -HUGE_VAL;
}

int best_index(const std::vector<Evaluated>& all, const ObjectiveOptions& o) {
  int best = 0;
  double best_score = score(all[0].candidate, all[0].candidate, o);
  for (int i = 1; i < static_cast<int>(all.size()); ++i) {
    const double s = score(all[i].candidate, all[0].candidate, o);
    if (s > best_score) best = i, best_score = s;
  }
  return best;
}

/// The isotropic reference (its failure is the user's: thrown), with what round 1's shell-stress
/// candidates share computed meanwhile on the other thread (prepare_design_cache: the stress,
/// their four fields, the input surface's projector and maps), which the reference, needing no
/// stress, would otherwise leave idle for most of its time.
Evaluated reference_beside_warm_up(const Surface& surface, const DesignOptions& base,
                                   DesignCache& cache) {
  tbb::task_group group;
  group.run([&] {
    // A failure here is met again, and judged, by the candidate that needs the value (the
    // cache keeps no failed value).
    try {
      for (const FieldSetting& s : shell_settings())
        prepare_design_cache(surface, candidate_options(base, s, 0), cache);
    } catch (...) {
    }
  });
  std::optional<Evaluated> reference;
  try {
    reference = evaluate(surface, base, FieldSetting{}, nullptr, cache, 0, 1, true);
  } catch (...) {
    group.wait();
    throw;
  }
  group.wait();
  return std::move(*reference);
}

std::vector<Evaluated> evaluate_all(
    const Surface& surface, const DesignOptions& base,
    const std::vector<std::pair<FieldSetting, const GivenStress*>>& settings, DesignCache& cache,
    double length, int round, SearchProgress& progress) {
  std::vector<Evaluated> out(settings.size());
  tbb::parallel_for(0, static_cast<int>(settings.size()), [&](int i) {
    if (stop_requested(progress.options.stop)) return;
    out[i] = evaluate(surface, base, settings[i].first, settings[i].second, cache, length, round);
    progress.one_more();
  });
  if (stop_requested(progress.options.stop)) throw Stopped{};
  return out;
}

}  // namespace

namespace {
constexpr EnumWords<Objective, 4> kObjectiveWords{{{"lambda", Objective::lambda},
                                                   {"delta", Objective::delta},
                                                   {"balanced", Objective::balanced},
                                                   {"mass", Objective::mass}}};
constexpr EnumWords<FieldSource, 4> kFieldSourceWords{
    {{"uniform", FieldSource::uniform},
     {"shell-stress", FieldSource::shell_stress},
     {"frame-mode", FieldSource::frame_mode},
     {"frame-energy", FieldSource::frame_energy}}};
}  // namespace

Objective parse_objective(const std::string& w) {
  return parse_word(w, "--objective", kObjectiveWords);
}

const char* to_string(Objective o) {
  return word_of(o, kObjectiveWords);
}

const char* to_string(FieldSource s) {
  return word_of(s, kFieldSourceWords);
}

std::string FieldSetting::label() const {
  if (source == FieldSource::uniform)
    return size != 1 ? fmt::format("isotropic cells x{:g}", size) : "isotropic";
  std::string s = fmt::format("{} D={:g} A={:g}", to_string(source), D, A);
  if (source == FieldSource::shell_stress)
    s += fmt::format(" {}/{}/{}", to_string(measure), to_string(stretch), to_string(density));
  else
    s += fmt::format(" feedback {}", feedback);
  if (size != 1) s += fmt::format(" cells x{:g}", size);
  return s;
}

nlohmann::json ObjectiveResult::report() const {
  if (objective == Objective::mass) return objective_detail::mass_report(*this);
  nlohmann::json j;
  const Candidate& ref = candidates.front();
  j["objective"] = to_string(objective);
  j["chosen"] = chosen;
  j["chosen_label"] = candidates[chosen].setting.label();
  j["reason"] = reason;
  j["seconds"] = seconds;
  j["lambda_gain"] = lambda_gain(candidates[chosen], ref);
  j["delta_gain"] = delta_gain(candidates[chosen], ref);
  nlohmann::json list = nlohmann::json::array();
  for (const Candidate& c : candidates) {
    nlohmann::json e = candidate_entry(c);
    if (c.ok) {
      e["lambda_linear_buckling"] = c.lambda;
      e["delta_max_m"] = c.delta;
      e["total_length_m"] = c.length;
      e["cells"] = c.cells;
      e["lambda_ratio"] = ref.lambda > 0 ? c.lambda / ref.lambda : 0.0;
      e["delta_ratio"] = ref.delta > 0 ? c.delta / ref.delta : 0.0;
    } else {
      e["error"] = c.error;
    }
    list.push_back(e);
  }
  j["candidates"] = list;
  nlohmann::json by = nlohmann::json::object();
  for (Objective o : {Objective::lambda, Objective::delta, Objective::balanced})
    by[to_string(o)] = choice[static_cast<int>(o)];
  j["choice_by_objective"] = by;
  return j;
}

std::optional<FieldSource> parse_frame_source(const std::string& word) {
  if (word == "frame-mode") return FieldSource::frame_mode;
  if (word == "frame-energy") return FieldSource::frame_energy;
  return std::nullopt;
}

DesignResult design_from_frame_response(const Surface& surface, const DesignOptions& options,
                                        FieldSource source) {
  if (source != FieldSource::frame_mode && source != FieldSource::frame_energy)
    throw Error("--field", "a frame response is frame-mode or frame-energy");
  const DesignResult iso = run_design(surface, candidate_options(options, FieldSetting{}, 0));
  const std::vector<double>* values = response_values(iso, source);
  if (!values) throw Error("--field", "the isotropic design has no buckling mode to follow");
  GivenStress response{frame_response_field(surface.mesh, iso.mesh, *values), {}};
  DesignOptions o = options;
  o.field = FieldInput::stress;
  if (!(o.tessellation.length > 0)) {
    o.tessellation.length = iso.metrics.total_length;
    o.tessellation.cells = 0;
    o.tessellation.radius = 0;
  }
  DesignResult r = run_design(surface, o, response);
  r.details["field"]["kind"] = to_string(source);
  r.details["field"]["reference_length_m"] = iso.metrics.total_length;
  return r;
}

void objective_detail::add_response_candidates(
    const Surface& surface, const DesignResult& reference, const DesignOptions& options,
    DesignCache& cache, std::deque<GivenStress>& responses,
    std::vector<std::pair<FieldSetting, const GivenStress*>>& round) {
  const std::vector<int> at = given_stress_faces(surface, options, cache);  // empty: all
  for (FieldSource src : {FieldSource::frame_mode, FieldSource::frame_energy}) {
    const std::vector<double>* values = response_values(reference, src);
    if (!values) continue;
    responses.push_back({at.empty()
                             ? frame_response_field(surface.mesh, reference.mesh, *values)
                             : frame_response_field(surface.mesh, at, reference.mesh, *values),
                         at});
    FieldSetting s;
    s.source = src;
    s.D = 2;
    s.A = 1;
    s.feedback = 1;
    round.emplace_back(s, &responses.back());
  }
}

namespace {

using Pending = std::vector<std::pair<FieldSetting, const GivenStress*>>;

/// Round 1: the shell stress in four conventions, and the reference's two frame responses (kept
/// in `responses`, whose addresses the settings point to).
Pending first_round(const Surface& surface, const DesignResult& reference, const GivenStress& shell,
                    const DesignOptions& base, DesignCache& cache,
                    std::deque<GivenStress>& responses) {
  Pending round;
  for (const FieldSetting& s : shell_settings()) round.emplace_back(s, &shell);
  add_response_candidates(surface, reference, base, cache, responses, round);
  return round;
}

/// A local round, the same for every objective (so that each objective's choice is the best of
/// one common pool: `lambda` never finds less λ than `delta` happened to): the neighbours of the
/// best-λ and the best-δ candidates not varied yet (`explored`) — D one up and half down, A one
/// up, and half their contrast (a gain in one figure often costs the other less than
/// proportionally less) — that were not tried, within `max_designs`.
Pending local_round(const std::vector<Evaluated>& all, const ObjectiveOptions& options,
                    std::vector<std::string>& explored) {
  Pending round;
  auto known = [&](const std::string& label) {
    for (const Evaluated& e : all)
      if (e.candidate.setting.label() == label) return true;
    for (const auto& [t, f] : round)
      if (t.label() == label) return true;
    return false;
  };
  for (Objective one : {Objective::lambda, Objective::delta}) {
    const int i = best_index(all, ObjectiveOptions{one, options.tolerance});
    const FieldSetting b = all[i].candidate.setting;
    if (i == 0 || std::find(explored.begin(), explored.end(), b.label()) != explored.end())
      continue;
    explored.push_back(b.label());
    // (A second feedback step — the response of the winner's own frame — was worse than the
    // first on all four surfaces where a frame-response field won: not tried.)
    for (const std::array<double, 2>& DA :
         {std::array<double, 2>{b.D + 1, b.A}, std::array<double, 2>{b.D, b.A + 1},
          std::array<double, 2>{std::max(1.0, b.D - 0.5), b.A},
          std::array<double, 2>{1 + 0.5 * (b.D - 1), 1 + 0.5 * (b.A - 1)}}) {
      FieldSetting s = b;
      s.D = std::min(DA[0], kMaxRatio);
      s.A = std::min(DA[1], kMaxRatio);
      if ((s.D != b.D || s.A != b.A) && !known(s.label()) &&
          static_cast<int>(all.size() + round.size()) < options.max_designs)
        round.emplace_back(s, all[i].field);
    }
  }
  return round;
}

/// Whether an earlier candidate's design was made on its field at full contrast (not softened
/// after a failed extraction): a candidate with the same field gets the same design.
bool designed_at_full_contrast(const Evaluated& e) {
  if (!e.candidate.ok || !e.design) return false;
  const nlohmann::json& d = e.design->details;
  return !(d.contains("field") && d["field"].contains("softened_from"));
}

/// Per setting of `round`: the index in `all` of an earlier shell-stress candidate whose field
/// equals its own bit for bit (a stress-free measure, e.g. tension on a shell in compression
/// everywhere, gives the same field for every D and A), else −1. The round's fields are computed
/// into the cache in parallel, as its designs would.
std::vector<int> twins(const Surface& surface, const DesignOptions& base, const Pending& round,
                       const std::vector<Evaluated>& all, DesignCache& cache, double length) {
  auto field_of = [&](const FieldSetting& s) -> const Field* {
    if (s.source != FieldSource::shell_stress) return nullptr;
    try {
      return shared_design_field(surface, candidate_options(base, s, length), cache);
    } catch (const Error&) {
      return nullptr;  // the candidate meets the error again when it is designed
    }
  };
  std::vector<const Field*> fresh(round.size());
  tbb::parallel_for(std::size_t{0}, round.size(),
                    [&](std::size_t i) { fresh[i] = field_of(round[i].first); });
  std::vector<int> out(round.size(), -1);
  for (std::size_t i = 0; i < round.size(); ++i)
    for (std::size_t j = 0; fresh[i] && j < all.size() && out[i] < 0; ++j) {
      if (!designed_at_full_contrast(all[j])) continue;
      const Field* f = field_of(all[j].candidate.setting);
      if (f && identical(*f, *fresh[i])) out[i] = static_cast<int>(j);
    }
  return out;
}

/// A round after the first: a setting whose field equals an earlier candidate's (twins) takes
/// that candidate's design and figures — the same metric, seed and length give the same design
/// bit for bit — instead of making it again; the others are designed as evaluate_all does. The
/// results are in the round's order.
std::vector<Evaluated> evaluate_round(const Surface& surface, const DesignOptions& base,
                                      const Pending& round, const std::vector<Evaluated>& all,
                                      DesignCache& cache, double length, int number,
                                      SearchProgress& progress) {
  const std::vector<int> twin = twins(surface, base, round, all, cache, length);
  Pending rest;
  for (std::size_t i = 0; i < round.size(); ++i)
    if (twin[i] < 0) rest.push_back(round[i]);
  std::vector<Evaluated> made = evaluate_all(surface, base, rest, cache, length, number, progress);
  std::vector<Evaluated> out;
  std::size_t k = 0;
  for (std::size_t i = 0; i < round.size(); ++i) {
    if (twin[i] < 0) {
      out.push_back(std::move(made[k++]));
      continue;
    }
    Evaluated e = all[twin[i]];
    e.candidate.setting = round[i].first;
    e.candidate.round = number;
    e.candidate.seconds = 0;
    e.candidate.same_as = all[twin[i]].candidate.setting.label();
    spdlog::info("[objective] {}: the same field as {}, so the same design (not made again)",
                 e.candidate.setting.label(), e.candidate.same_as);
    progress.one_more();
    out.push_back(std::move(e));
  }
  return out;
}

/// The choice among all candidates, why, and the chosen design analysed as `base` asks.
ObjectiveResult choose(const Surface& surface, std::vector<Evaluated>& all,
                       const DesignOptions& base, const ObjectiveOptions& options,
                       DesignCache& cache) {
  const int best = best_index(all, options);
  ObjectiveResult res;
  res.objective = options.objective;
  for (const Evaluated& e : all) res.candidates.push_back(e.candidate);
  res.chosen = best;
  for (Objective o : {Objective::lambda, Objective::delta, Objective::balanced})
    res.choice[static_cast<int>(o)] = best_index(all, ObjectiveOptions{o, options.tolerance});
  const Candidate& c = res.candidates[best];
  const Candidate& ref = res.candidates.front();
  if (best == 0) {
    res.reason = options.objective == Objective::balanced
                     ? "no candidate improved lambda_LBA or delta without making the other more "
                       "than the tolerance worse than the isotropic design's"
                     : "no candidate beat the isotropic design";
  } else {
    res.reason = fmt::format(
        "{} gives lambda_LBA {:+.1f} % and delta {:+.1f} % against the isotropic design at the "
        "same length, the best {} of {} candidates",
        c.setting.label(), 100 * (c.lambda / ref.lambda - 1), 100 * (c.delta / ref.delta - 1),
        options.objective == Objective::lambda  ? "lambda_LBA"
        : options.objective == Objective::delta ? "delta"
                                                : "admissible gain",
        res.candidates.size());
  }
  res.design = std::move(*all[best].design);
  carry_field_to_input(surface, res.design, cache);
  if (base.analyze == analysis::AnalysisLevel::none) {
    res.design.structure.reset();
  } else if (base.analyze != analysis::AnalysisLevel::buckling ||
             base.sizing == sizing::MemberSizing::sized ||
             (c.setting.source != FieldSource::uniform &&
              base.frame_analysis.buckling_modes != kCandidateModes)) {
    GridshellStructure s =
        analyze_structure(res.design.mesh, res.design.supports, base.frame, base.frame_analysis,
                          {base.analyze, base.sizing, base.sizing_options});
    res.design.structure = std::move(s.result);
    res.design.sizing = std::move(s.sizing);
  }
  spdlog::info("[objective] chose {} ({})", c.setting.label(), res.reason);
  return res;
}

}  // namespace

ObjectiveResult design_for_objective(const Surface& surface, const DesignOptions& base,
                                     const ObjectiveOptions& options) {
  const auto t0 = Clock::now();
  if (!(options.tolerance >= 0 && options.tolerance < 1))
    throw Error("objective", "tolerance must be in [0, 1)");
  check_design_options(base);
  if (options.objective == Objective::mass)
    return objective_detail::design_for_mass(surface, base, options);
  SearchProgress progress{options};
  report_progress(options.progress, "objective search", 0, "the isotropic reference");
  std::vector<Evaluated> all;
  DesignCache cache;
  all.push_back(reference_beside_warm_up(surface, base, cache));
  progress.one_more();
  if (stop_requested(options.stop)) throw Stopped{};
  const double length =
      base.tessellation.length > 0 ? base.tessellation.length : all[0].candidate.length;
  const GivenStress shell;  // stands for the shell stress, which `cache` computes once
  std::deque<GivenStress> responses;
  for (Evaluated& e : evaluate_all(
           surface, base, first_round(surface, *all[0].design, shell, base, cache, responses),
           cache, length, 1, progress))
    all.push_back(std::move(e));
  std::vector<std::string> explored;
  for (int round = 2; round <= options.rounds; ++round) {
    const Pending next = local_round(all, options, explored);
    if (next.empty()) break;
    for (Evaluated& e : evaluate_round(surface, base, next, all, cache, length, round, progress))
      all.push_back(std::move(e));
  }
  report_progress(options.progress, "objective search", 1, fmt::format("{} designs", all.size()));
  if (stop_requested(options.stop)) throw Stopped{};
  ObjectiveResult res = choose(surface, all, base, options, cache);
  res.seconds = seconds_since(t0);
  return res;
}

}  // namespace gridshell
