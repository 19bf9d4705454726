#pragma once
/// \file objective_search.h
/// Internal to the objective search (objective.cpp: lambda / delta / balanced at equal length;
/// objective_mass.cpp: `mass`, every candidate sized): what both searches share.

#include <atomic>
#include <chrono>
#include <deque>
#include <functional>
#include <string>
#include <optional>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "gridshell/pipeline/objective.h"

namespace gridshell::objective_detail {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t);

/// D and A beyond ~4 fold the deformed surface (docs/field.md): the search stays below.
constexpr double kMaxRatio = 4;

/// A candidate and, when it could be designed, its design.
struct Evaluated {
  Candidate candidate;
  std::optional<DesignResult> design;
  const GivenStress* field = nullptr;  ///< the stress it was designed from (null: isotropic)
};

/// report.json's entry of a candidate in either search: its setting, round, verdict and seconds
/// (each search adds its figures).
nlohmann::json candidate_entry(const Candidate& c);

/// One candidate of either search: where and from what it is designed.
struct CandidateRun {
  const Surface& surface;
  const FieldSetting& setting;
  const GivenStress* stress;  ///< a frame response's stress (null: the setting's own field)
  DesignCache& cache;
  int round = 0;
  bool rethrow = false;  ///< the reference: its failure is the user's (a bad size or surface)
};
/// How a search designs and judges a candidate: its options, the reading of its design into the
/// Candidate (`ok`, the figures, `error`), the log line of one that passed.
struct CandidateJudge {
  std::function<DesignOptions()> options;
  std::function<void(const DesignOptions&, const DesignResult&, Candidate&)> judge;
  std::function<std::string(const Candidate&)> summary;
  const char* failed = "failed";  ///< the log's word for one that did not pass
};
/// Designs `run`'s candidate with `how`, times it and logs it; a candidate's Error marks it
/// failed (its message in `error`) unless `run.rethrow`.
Evaluated evaluate_candidate(const CandidateRun& run, const CandidateJudge& how);

/// Candidates designed so far, told to the progress listener (from any thread).
struct SearchProgress {
  const ObjectiveOptions& options;
  std::atomic<int> designed{0};
  void one_more();
};

/// `base` with the setting's field, analysis `buckling`, the given section and, when
/// `length` > 0, that total length instead of base's size.
DesignOptions candidate_options(const DesignOptions& base, const FieldSetting& s, double length);

/// Round 1's shell-stress settings: the four conventions at D = A = 2.
std::vector<FieldSetting> shell_settings();

/// The energies a frame-response setting reads from an analysed design (null when missing).
const std::vector<double>* response_values(const DesignResult& r, FieldSource source);

/// The reference's two frame-response fields (D = 2, A = 1), kept in `responses` (whose
/// addresses the settings point to), appended to `round`: computed only at the input triangles
/// the candidates read (given_stress_faces of `cache`, for designs with `options`).
void add_response_candidates(const Surface& surface, const DesignResult& reference,
                             const DesignOptions& options, DesignCache& cache,
                             std::deque<GivenStress>& responses,
                             std::vector<std::pair<FieldSetting, const GivenStress*>>& round);

/// `design --objective mass` (objective.h); `base` is checked already.
ObjectiveResult design_for_mass(const Surface& surface, const DesignOptions& base,
                                const ObjectiveOptions& options);
/// report.json's "objective" block of a mass search.
nlohmann::json mass_report(const ObjectiveResult& r);

}  // namespace gridshell::objective_detail
