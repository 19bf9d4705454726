#include "gridshell/sizing/sizing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <queue>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "gridshell/analysis/frame_loads.h"
#include "gridshell/checks/member_checks.h"
#include "gridshell/core/error.h"
#include "gridshell/mesh/topology.h"

namespace gridshell::sizing {

std::vector<analysis::LoadCombination> design_combinations(
    const PolyMesh& mesh, const analysis::GridshellFrameOptions& frame, std::size_t* primary) {
  std::vector<analysis::LoadCombination> out;
  if (frame.loads == analysis::LoadModel::paper) {
    out.push_back({"paper", true, "", {}});
  } else {
    const fem::FrameModel model = analysis::gridshell_frame(mesh, {}, frame);
    out = analysis::eurocode_combinations(
        analysis::eurocode_cases(mesh, analysis::bar_weights_per_m(model, frame), frame));
  }
  if (primary) {
    *primary = 0;
    for (std::size_t k = 0; k < out.size(); ++k)
      if (out[k].name == "ULS") *primary = k;
  }
  return out;
}

namespace {

analysis::FrameResult analyze_one(const PolyMesh& mesh, const std::vector<int>& supports,
                                  analysis::GridshellFrameOptions frame,
                                  const analysis::FrameAnalysisOptions& options,
                                  const analysis::LoadCombination& c,
                                  analysis::AnalysisLevel level) {
  if (frame.loads == analysis::LoadModel::eurocode) frame.combination_name = c.name;
  analysis::FrameAnalysisOptions o = analysis::at_level(options, level);
  if (o.subject == "model") o.subject = "sizing";
  return analysis::analyze_frame(analysis::gridshell_frame(mesh, supports, frame), o);
}

/// A combination whose δ is judged against the deflection limit: SLS, or the paper's load.
bool serviceability(const analysis::LoadCombination& c) {
  return !c.uls || c.name == "paper";
}

}  // namespace

namespace {

/// analyze_combinations with, when `known` is set, the result of combination `known_k` at the
/// non-linear level already in hand (the same frame, options and combination: the same
/// analysis), taken instead of analysing it again when the rule asks for it at that level.
analysis::CombinationRunsResult analyze_combinations_known(
    const PolyMesh& mesh, const std::vector<int>& supports,
    const analysis::GridshellFrameOptions& frame, const analysis::FrameAnalysisOptions& options,
    analysis::AnalysisLevel level, const std::vector<analysis::LoadCombination>& combinations,
    std::size_t primary, std::size_t known_k, const analysis::FrameResult* known) {
  const auto analyze = [&](std::size_t k, analysis::AnalysisLevel l) {
    if (known && k == known_k && l == analysis::AnalysisLevel::nonlinear) return *known;
    return analyze_one(mesh, supports, frame, options, combinations[k], l);
  };
  const analysis::FrameResult first = analyze(primary, level);
  std::vector<analysis::CombinationRun> runs;
  for (std::size_t k = 0; k < combinations.size(); ++k)
    runs.push_back({combinations[k].uls, k == primary});
  return analysis::run_combinations(runs, first, analyze);
}

}  // namespace

analysis::CombinationRunsResult analyze_combinations(
    const PolyMesh& mesh, const std::vector<int>& supports,
    const analysis::GridshellFrameOptions& frame, const analysis::FrameAnalysisOptions& options,
    analysis::AnalysisLevel level, const std::vector<analysis::LoadCombination>& combinations,
    std::size_t primary) {
  return analyze_combinations_known(mesh, supports, frame, options, level, combinations, primary,
                                    0, nullptr);
}

double steel_mass(const PolyMesh& mesh, const analysis::GridshellFrameOptions& frame) {
  const fem::FrameModel model = analysis::gridshell_frame(mesh, {}, frame);
  return fem::total_mass(model);
}

std::vector<sections::Section> read_section_list(const std::string& path) {
  std::ifstream in(path);
  if (!in)
    throw Error("--sections", "cannot read '" + path + "' (not a series word: chs, rhs, bar)");
  std::vector<sections::Section> out;
  std::string line;
  for (int n = 1; std::getline(in, line) && n <= 100000; ++n) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    const auto last = line.find_last_not_of(" \t\r");
    out.push_back(sections::parse_section(line.substr(first, last - first + 1),
                                          fmt::format("--sections {}:{}", path, n)));
  }
  if (out.empty()) throw Error("--sections", "'" + path + "' lists no section");
  return out;
}

std::vector<sections::Section> parse_section_list(const std::string& text) {
  for (const char* word : {"chs", "rhs", "bar", "chs cold", "rhs cold", "chs hot", "rhs hot"})
    if (text == word) return sections::parse_series(text, "--sections");
  return read_section_list(text);
}

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The catalogue sorted by mass, with what the iteration compares.
struct Entry {
  sections::Section section;
  fem::FrameSection frame;
  double mass = 0, A = 0, Imin = 0;
};

/// One iteration's analysis of a design.
struct Analysed {
  fem::FrameModel model;  ///< the primary's frame (lengths, materials)
  analysis::CombinationRunsResult runs;
  double mass = 0;
  double utilisation = 0;  ///< largest member check over the ULS combinations
  double delta_ratio = 0;  ///< largest SLS δ / limit
  std::size_t delta_combination = 0;
  double lambda_lba = std::numeric_limits<double>::infinity();  ///< smallest over ULS
  std::size_t lambda_combination = 0;
};

/// The first check the analysed combinations fail (empty when all pass): the member checks of
/// the ULS combinations, δ of the serviceability ones, λ ≥ lambda_min of the ULS ones (level ≥
/// buckling).
std::string final_failure(const std::vector<analysis::LoadCombination>& combos,
                          const analysis::CombinationRunsResult& runs,
                          analysis::AnalysisLevel level, double lambda_min) {
  for (std::size_t k = 0; k < combos.size() && k < runs.results.size(); ++k) {
    const analysis::FrameResult& r = runs.results[k];
    const std::string& name = combos[k].name;
    if (combos[k].uls) {
      const checks::MemberChecks& c = r.checks;
      if (c.section_max > 1)
        return fmt::format("member {}: {} utilisation {:.3g} under {}", c.section_worst,
                           c.section_governing, c.section_max, name);
      if (c.buckling_max > 1)
        return fmt::format("member {}: {} utilisation {:.3g} under {}", c.buckling_worst,
                           c.buckling_governing, c.buckling_max, name);
      const auto [lambda, source] = analysis::combination_lambda(r);
      if (level != analysis::AnalysisLevel::linear && lambda && *lambda < lambda_min)
        return fmt::format("{} {:.4g} < {:.4g} under {}", source, *lambda, lambda_min, name);
    }
    if (serviceability(combos[k]) && !r.delta_pass)
      return fmt::format("deflection {:.1f} mm > span/{:.0f} = {:.1f} mm under {} (joint {})",
                         r.delta_max_m * 1e3, r.span_m / r.delta_limit_m, r.delta_limit_m * 1e3,
                         name, r.delta_node);
  }
  return {};
}

class Sizer {
 public:
  Sizer(const PolyMesh& mesh, const std::vector<int>& supports,
        const analysis::GridshellFrameOptions& frame,
        const analysis::FrameAnalysisOptions& analysis, analysis::AnalysisLevel level,
        const SizingOptions& options);
  SizingResult run();

 private:
  Analysed analyse(const std::vector<int>& design, analysis::AnalysisLevel level) const;
  /// Every combination at `level` ≤ buckling by the rule of analysis/combination_runs.h, all on
  /// one factorisation of K (analysis/frame_loads.h); `model` is the frame of `f`.
  analysis::CombinationRunsResult analyze_cheap(const fem::FrameModel& model,
                                                const analysis::GridshellFrameOptions& f,
                                                analysis::AnalysisLevel level) const;
  bool passes(const Analysed& a, int m, int s) const;
  bool meets_floor(int m, int s) const {
    return cat_[s].A >= floor_A_[m] * (1 - 1e-12) && cat_[s].Imin >= floor_I_[m] * (1 - 1e-12);
  }
  /// The lightest section passing member m's checks and floor, or −1.
  int lightest_passing(const Analysed& a, int m) const;
  std::vector<int> group(const Analysed& a, std::vector<int> need) const;
  bool raise_for_stiffness(const Analysed& a, const std::vector<int>& design);
  /// Raises the λ_LBA target to what the measured knock-down needs.
  void raise_target(double lambda, const Analysed& a);
  /// Step 4's probe; true when it raised the target (the iteration resumes).
  bool probe(const Analysed& a, const std::vector<int>& design, int& iteration, SizingResult& out);
  /// Step 4's full analysis into out.final; true when done (passed, or no round left).
  bool verify(const Analysed& a, const std::vector<int>& design, int& iteration, bool last,
              SizingResult& out);
  std::string strength_failure(const Analysed& a, int m) const;
  analysis::GridshellFrameOptions frame_of(const std::vector<int>& design) const;

  const PolyMesh& mesh_;
  const std::vector<int>& supports_;
  analysis::GridshellFrameOptions frame_;
  const analysis::FrameAnalysisOptions& analysis_;
  analysis::AnalysisLevel level_;
  const SizingOptions& o_;
  std::vector<Entry> cat_;
  std::vector<double> length_;
  std::vector<double> floor_A_, floor_I_;
  double lba_target_ = 0;
  std::vector<analysis::LoadCombination> combos_;
  std::size_t primary_ = 0;
  std::string failure_;
  /// The last probe's analysis (its combination, of `probed_design_`): the verification of the
  /// same design takes it instead of following the same paths again.
  std::unique_ptr<analysis::FrameResult> probed_;
  std::size_t probed_combination_ = 0;
  std::vector<int> probed_design_;
};

Sizer::Sizer(const PolyMesh& mesh, const std::vector<int>& supports,
             const analysis::GridshellFrameOptions& frame,
             const analysis::FrameAnalysisOptions& analysis, analysis::AnalysisLevel level,
             const SizingOptions& options)
    : mesh_(mesh),
      supports_(supports),
      frame_(frame),
      analysis_(analysis),
      level_(level),
      o_(options) {
  if (o_.catalogue.empty()) throw Error("--sections", "the section list is empty");
  if (o_.groups < 0) throw Error("--section-groups", "must be >= 0 (0: every member its own)");
  if (!(o_.lambda_min > 0) || !std::isfinite(o_.lambda_min))
    throw Error("--lambda-min", "must be a load factor > 0");
  for (const sections::Section& s : o_.catalogue) {
    const sections::SectionProperties p = sections::properties(s);
    cat_.push_back({s, fem::profile_section(s), p.mass, p.A, std::min(p.Iy, p.Iz)});
  }
  std::stable_sort(cat_.begin(), cat_.end(),
                   [](const Entry& a, const Entry& b) { return a.mass < b.mass; });
  frame_.member_sections.clear();
  const Topology topo = build_topology(mesh_);
  for (const auto& e : topo.edges)
    length_.push_back((mesh_.vertex(e[1]) - mesh_.vertex(e[0])).norm());
  floor_A_.assign(length_.size(), 0.0);
  floor_I_.assign(length_.size(), 0.0);
  combos_ = design_combinations(mesh_, frame_, &primary_);
  lba_target_ = o_.lambda_min;
}

analysis::GridshellFrameOptions Sizer::frame_of(const std::vector<int>& design) const {
  analysis::GridshellFrameOptions f = frame_;
  if (design.empty()) return f;  // the given section
  f.member_sections.reserve(design.size());
  for (int s : design) f.member_sections.push_back(cat_[s].section);
  return f;
}

analysis::CombinationRunsResult Sizer::analyze_cheap(const fem::FrameModel& model,
                                                     const analysis::GridshellFrameOptions& f,
                                                     analysis::AnalysisLevel level) const {
  std::vector<analysis::FrameLoad> loads(combos_.size());
  if (f.loads == analysis::LoadModel::eurocode) {
    const std::vector<analysis::LoadCase> cases =
        analysis::eurocode_cases(mesh_, analysis::bar_weights_per_m(model, f), f);
    for (std::size_t k = 0; k < combos_.size(); ++k) {
      const std::vector<Vec3> F = analysis::combine(cases, combos_[k]);
      for (int v = 0; v < static_cast<int>(F.size()); ++v)
        if (F[v].squaredNorm() > 0) loads[k].loads.push_back({v, F[v], Vec3::Zero()});
    }
  } else {
    for (analysis::FrameLoad& l : loads) l.loads = model.loads;  // the paper's one load
  }
  const bool buckling = level == analysis::AnalysisLevel::buckling;
  for (std::size_t k = 0; k < combos_.size(); ++k) loads[k].buckling = buckling && combos_[k].uls;
  analysis::FrameAnalysisOptions o = analysis::at_level(analysis_, level);
  if (o.subject == "model") o.subject = "sizing";
  analysis::CombinationRunsResult runs;
  runs.results = analysis::analyze_frame_loads(model, loads, o);
  runs.nonlinear.assign(combos_.size(), 0);
  // The rule of analysis/combination_runs.h: no LBA of the others when the primary found none.
  const analysis::FrameResult& p = runs.results[primary_];
  if (buckling && !p.lambda_linear_buckling && p.buckling_lambdas.empty())
    for (std::size_t k = 0; k < combos_.size(); ++k) {
      if (k == primary_) continue;
      analysis::FrameResult& r = runs.results[k];
      r.lambda_linear_buckling.reset();
      r.buckling_lambdas.clear();
      r.buckling_modes.clear();
      r.mode_energy.clear();
    }
  return runs;
}

Analysed Sizer::analyse(const std::vector<int>& design, analysis::AnalysisLevel level) const {
  const analysis::GridshellFrameOptions f = frame_of(design);
  Analysed a;
  a.model = analysis::gridshell_frame(mesh_, supports_, f);
  a.mass = fem::total_mass(a.model);
  a.runs = level == analysis::AnalysisLevel::nonlinear
               ? analyze_combinations_known(mesh_, supports_, f, analysis_, level, combos_,
                                            primary_, probed_combination_,
                                            probed_design_ == design ? probed_.get() : nullptr)
               : analyze_cheap(a.model, f, level);
  for (std::size_t k = 0; k < combos_.size(); ++k) {
    const analysis::FrameResult& r = a.runs.results[k];
    if (combos_[k].uls) {
      a.utilisation = std::max({a.utilisation, r.checks.section_max, r.checks.buckling_max});
      if (r.lambda_linear_buckling && *r.lambda_linear_buckling < a.lambda_lba) {
        a.lambda_lba = *r.lambda_linear_buckling;
        a.lambda_combination = k;
      }
    }
    if (serviceability(combos_[k]) && r.delta_limit_m > 0 &&
        r.delta_max_m / r.delta_limit_m > a.delta_ratio) {
      a.delta_ratio = r.delta_max_m / r.delta_limit_m;
      a.delta_combination = k;
    }
  }
  return a;
}

bool Sizer::passes(const Analysed& a, int m, int s) const {
  const double fy = analysis_.checks.fy / analysis_.checks.gamma_M0;
  for (std::size_t k = 0; k < combos_.size(); ++k) {
    if (!combos_[k].uls) continue;
    const fem::MemberForces& f = a.runs.results[k].member_forces[m];
    if (std::max(std::abs(f.N_max), std::abs(f.N_min)) > cat_[s].A * fy) return false;
    const checks::MemberCheck c =
        checks::check_member(a.model, m, cat_[s].frame, f, analysis_.checks);
    if (!(c.section <= 1) || !(c.buckling <= 1)) return false;
  }
  return true;
}

int Sizer::lightest_passing(const Analysed& a, int m) const {
  for (int s = 0; s < static_cast<int>(cat_.size()); ++s)
    if (meets_floor(m, s) && passes(a, m, s)) return s;
  return -1;
}

std::string Sizer::strength_failure(const Analysed& a, int m) const {
  const int s = static_cast<int>(cat_.size()) - 1;
  double worst = -1;
  std::string text;
  for (std::size_t k = 0; k < combos_.size(); ++k) {
    if (!combos_[k].uls) continue;
    const checks::MemberCheck c = checks::check_member(
        a.model, m, cat_[s].frame, a.runs.results[k].member_forces[m], analysis_.checks);
    const bool buckling = c.buckling > c.section;
    const double u = std::max(c.section, c.buckling);
    if (u > worst) {
      worst = u;
      text = fmt::format("member {}: {} utilisation {:.3g} under {} even with {}", m,
                         buckling ? c.buckling_governing : c.section_governing, u, combos_[k].name,
                         sections::designation(cat_[s].section));
    }
  }
  return text;
}

/// Contiguous groups of the sorted needs minimising Σ length × mass of the group's heaviest
/// need (dynamic programming), then each group's lightest section passing for all its members.
std::vector<int> Sizer::group(const Analysed& a, std::vector<int> need) const {
  if (o_.groups <= 0) return need;
  std::vector<int> values(need);
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  const int K = static_cast<int>(values.size()), G = std::min(o_.groups, K);
  if (K <= o_.groups) return need;
  std::vector<double> len(K, 0.0);
  for (std::size_t m = 0; m < need.size(); ++m)
    len[std::lower_bound(values.begin(), values.end(), need[m]) - values.begin()] += length_[m];
  std::vector<double> prefix(K + 1, 0.0);
  for (int j = 0; j < K; ++j) prefix[j + 1] = prefix[j] + len[j];
  const double inf = std::numeric_limits<double>::infinity();
  // cost[g][j]: the first j values in g groups; cut[g][j]: where the last group starts.
  std::vector<std::vector<double>> cost(G + 1, std::vector<double>(K + 1, inf));
  std::vector<std::vector<int>> cut(G + 1, std::vector<int>(K + 1, 0));
  cost[0][0] = 0;
  for (int g = 1; g <= G; ++g)
    for (int j = 1; j <= K; ++j)
      for (int i = g - 1; i < j; ++i) {
        const double c = cost[g - 1][i] + cat_[values[j - 1]].mass * (prefix[j] - prefix[i]);
        if (c < cost[g][j]) {
          cost[g][j] = c;
          cut[g][j] = i;
        }
      }
  std::vector<int> top(K);  // per value: the index of its group's heaviest value
  for (int g = G, j = K; g > 0 && j > 0; j = cut[g][j], --g)
    for (int i = cut[g][j]; i < j; ++i) top[i] = j - 1;
  std::vector<std::vector<int>> members(K);
  for (std::size_t m = 0; m < need.size(); ++m)
    members[top[std::lower_bound(values.begin(), values.end(), need[m]) - values.begin()]]
        .push_back(static_cast<int>(m));
  for (int j = 0; j < K; ++j) {
    if (members[j].empty()) continue;
    int chosen = -1;
    for (int s = values[j]; s < static_cast<int>(cat_.size()) && chosen < 0; ++s)
      if (std::all_of(members[j].begin(), members[j].end(),
                      [&](int m) { return meets_floor(m, s) && passes(a, m, s); }))
        chosen = s;
    if (chosen < 0) chosen = values[j];  // no common section: each keeps the heaviest need
    for (int m : members[j]) need[m] = chosen;
  }
  return need;
}

/// Step 2: raises the floors of the members whose upgrades buy the most of the missing δ and
/// λ_LBA per kg, until the estimates cover every shortfall. Each combination short of its
/// target is its own shortfall — δ of every SLS combination over its limit, λ_LBA of every ULS
/// combination under the target, each with its own strain or mode energy — and an upgrade's
/// benefit is the sum of its estimated gains, each over its shortfall (one greedy for all: the
/// drifted arrangements buckle in different regions, and planning only the governing one lets
/// the next take over). A member may go up several sizes; its stiffness ratio ρ = √(ρ_A ρ_I) to
/// the analysed section counts up to kMaxGain (the estimate's validity: the mode moves once a
/// region is much stiffer). False when nothing can be upgraded.
bool Sizer::raise_for_stiffness(const Analysed& a, const std::vector<int>& design) {
  constexpr double kMaxGain = 2;
  // Each round plans this share of the estimated shortfall: the estimates are first-order, and
  // floors never come down, so the next analysis measures the rest.
  constexpr double kStep = 0.5;
  const double margin = 1 + o_.target_margin;
  // The shortfalls: δ as a fraction of the compliance of an SLS combination, λ_LBA as a relative
  // increase of the Rayleigh quotient (mode_energy sums to 1).
  struct Shortfall {
    const std::vector<double>* energy = nullptr;
    bool delta = false;
    double need = 0, got = 0;
  };
  std::vector<Shortfall> short_of;
  for (std::size_t k = 0; k < combos_.size(); ++k) {
    const analysis::FrameResult& r = a.runs.results[k];
    const double ratio = r.delta_limit_m > 0 ? r.delta_max_m / r.delta_limit_m : 0;
    if (serviceability(combos_[k]) && ratio * margin > 1) {
      const double total = std::accumulate(r.strain_energy.begin(), r.strain_energy.end(), 0.0);
      short_of.push_back({&r.strain_energy, true, kStep * (1 - 1 / (ratio * margin)) * total});
    }
    const double lambda = r.lambda_linear_buckling.value_or(0.0);
    if (level_ != analysis::AnalysisLevel::linear && combos_[k].uls && lambda > 0 &&
        lambda < lba_target_ * margin && !r.mode_energy.empty())
      short_of.push_back({&r.mode_energy, false, kStep * (lba_target_ * margin / lambda - 1)});
  }
  if (short_of.empty()) return false;
  const auto rho = [&](int m, int s) {
    const Entry& base = cat_[design[m]];
    return std::min(std::sqrt(cat_[s].Imin / base.Imin * cat_[s].A / base.A), kMaxGain);
  };
  const auto gain = [&](const Shortfall& f, int m, double r0, double r1) {
    return (*f.energy)[m] * (f.delta ? 1 / r0 - 1 / r1 : r1 - r0);
  };
  const auto missing = [&] {
    return std::any_of(short_of.begin(), short_of.end(),
                       [](const Shortfall& f) { return f.got < f.need; });
  };
  struct Item {
    double ratio = 0;
    int member = 0, from = 0, to = 0;
    bool operator<(const Item& o) const {
      return ratio < o.ratio || (ratio == o.ratio && member > o.member);
    }
  };
  // The next useful size above `from` for member m (larger A, ≥ 10 % larger I_min), valued by
  // what is still missing.
  const auto next = [&](int m, int from) -> std::optional<Item> {
    const Entry& cur = cat_[from];
    for (int s = from + 1; s < static_cast<int>(cat_.size()); ++s) {
      if (cat_[s].A < cur.A || cat_[s].Imin < 1.1 * cur.Imin) continue;
      const double r0 = rho(m, from), r1 = rho(m, s);
      double value = 0;
      for (const Shortfall& f : short_of)
        if (f.got < f.need) value += gain(f, m, r0, r1) / f.need;
      return Item{value / std::max((cat_[s].mass - cur.mass) * length_[m], 1e-9), m, from, s};
    }
    return std::nullopt;
  };
  std::priority_queue<Item> queue;
  for (std::size_t m = 0; m < design.size(); ++m)
    if (const auto it = next(static_cast<int>(m), design[m]); it && it->ratio > 0) queue.push(*it);
  int raised = 0;
  while (missing() && !queue.empty()) {
    Item u = queue.top();
    queue.pop();
    // Valued when pushed: once a shortfall is covered its gains no longer count (lazy update).
    if (const auto now = next(u.member, u.from); now && now->ratio < u.ratio) {
      if (now->ratio > 0) queue.push(*now);
      continue;
    }
    floor_A_[u.member] = std::max(floor_A_[u.member], cat_[u.to].A);
    floor_I_[u.member] = std::max(floor_I_[u.member], cat_[u.to].Imin);
    const double r0 = rho(u.member, u.from), r1 = rho(u.member, u.to);
    for (Shortfall& f : short_of) f.got += gain(f, u.member, r0, r1);
    ++raised;
    if (const auto it = next(u.member, u.to); it && it->ratio > 0) queue.push(*it);
  }
  return raised > 0;
}

void Sizer::raise_target(double lambda, const Analysed& a) {
  const double knock = lambda / a.lambda_lba;
  lba_target_ = std::max(lba_target_ * 1.05, o_.lambda_min * (1 + o_.target_margin) / knock);
  spdlog::info("[sizing] lambda {:.3f} < {:.3f} (knock-down {:.2f}): lambda_LBA target {:.3f}",
               lambda, o_.lambda_min, knock, lba_target_);
}

bool Sizer::probe(const Analysed& a, const std::vector<int>& design, int& iteration,
                  SizingResult& out) {
  const auto t0 = std::chrono::steady_clock::now();
  probed_ = std::make_unique<analysis::FrameResult>(analyze_one(
      mesh_, supports_, frame_of(design), analysis_, combos_[a.lambda_combination], level_));
  probed_combination_ = a.lambda_combination;
  probed_design_ = design;
  const analysis::FrameResult& r = *probed_;
  const std::optional<double> lambda = analysis::combination_lambda(r).first;
  out.history.push_back({++iteration, "probe", a.mass, a.utilisation, a.delta_ratio,
                         lambda.value_or(0.0), 0, seconds_since(t0)});
  spdlog::info("[sizing] probe: lambda {:.3f} under {} ({:.1f} s)", lambda.value_or(0.0),
               combos_[a.lambda_combination].name, out.history.back().seconds);
  if (!lambda || *lambda >= o_.lambda_min * (1 + o_.target_margin)) return false;
  raise_target(*lambda, a);
  return true;
}

bool Sizer::verify(const Analysed& a, const std::vector<int>& design, int& iteration, bool last,
                   SizingResult& out) {
  const auto t0 = std::chrono::steady_clock::now();
  Analysed full = analyse(design, level_);
  double lambda = std::numeric_limits<double>::infinity();
  std::size_t worst = 0;
  for (std::size_t k = 0; k < combos_.size(); ++k) {
    if (!combos_[k].uls) continue;
    const std::optional<double> l = analysis::combination_lambda(full.runs.results[k]).first;
    if (l && *l < lambda) {
      lambda = *l;
      worst = k;
    }
  }
  out.history.push_back({++iteration, "verify", full.mass, full.utilisation, full.delta_ratio,
                         std::isfinite(lambda) ? lambda : 0.0, 0, seconds_since(t0)});
  spdlog::info("[sizing] verified: lambda {:.3f} under {} ({:.1f} s)", lambda, combos_[worst].name,
               out.history.back().seconds);
  out.iterations = iteration;
  out.final = std::move(full.runs);
  if (!(lambda < o_.lambda_min)) return true;
  if (last) {
    failure_ = fmt::format(
        "lambda {:.4g} < {:.4g} under {} (non-linear, imperfect) after {} "
        "rounds",
        lambda, o_.lambda_min, combos_[worst].name, o_.max_rounds);
    return true;
  }
  raise_target(lambda, a);
  return false;
}

SizingResult Sizer::run() {
  SizingResult out;
  const analysis::AnalysisLevel cheap = std::min(level_, analysis::AnalysisLevel::buckling);
  std::vector<int> design;  // empty: the given section, for the first forces
  int iteration = 0;
  for (int round = 0; round < o_.max_rounds; ++round) {
    bool converged = false;
    Analysed a;
    while (iteration < o_.max_iterations) {
      ++iteration;
      const auto t0 = std::chrono::steady_clock::now();
      a = analyse(design, cheap);
      SizingStep step{iteration,
                      "strength",
                      a.mass,
                      a.utilisation,
                      a.delta_ratio,
                      std::isfinite(a.lambda_lba) ? a.lambda_lba : 0.0,
                      0,
                      seconds_since(t0)};
      if (iteration > o_.free_iterations && !design.empty())
        for (std::size_t m = 0; m < design.size(); ++m) {
          floor_A_[m] = std::max(floor_A_[m], cat_[design[m]].A);
          floor_I_[m] = std::max(floor_I_[m], cat_[design[m]].Imin);
        }
      // Stiffness is planned once the strength is met, or after the free iterations (the
      // strength iteration then only creeps, and stiffening changes the forces anyway).
      const bool strength_ok = a.utilisation <= 1;
      const bool stiffness_short =
          !design.empty() && (strength_ok || iteration > o_.free_iterations) &&
          (a.delta_ratio > 1 || (cheap != analysis::AnalysisLevel::linear &&
                                 std::isfinite(a.lambda_lba) && a.lambda_lba < lba_target_));
      if (stiffness_short) {
        step.phase = "stiffness";
        if (!raise_for_stiffness(a, design)) {
          out.history.push_back(step);
          failure_ = a.delta_ratio > 1
                         ? fmt::format(
                               "SLS deflection {:.3g} x its limit under {} with the "
                               "heaviest useful sections",
                               a.delta_ratio, combos_[a.delta_combination].name)
                         : fmt::format(
                               "lambda_LBA {:.4g} < {:.4g} under {} with the heaviest "
                               "useful sections",
                               a.lambda_lba, lba_target_, combos_[a.lambda_combination].name);
          break;
        }
      }
      std::vector<int> need(length_.size());
      std::string missing;
      for (std::size_t m = 0; m < need.size(); ++m) {
        need[m] = lightest_passing(a, static_cast<int>(m));
        if (need[m] < 0) {
          if (missing.empty()) missing = strength_failure(a, static_cast<int>(m));
          need[m] = static_cast<int>(cat_.size()) - 1;
        }
      }
      need = group(a, std::move(need));
      for (std::size_t m = 0; m < need.size(); ++m)
        step.changed += design.empty() || need[m] != design[m];
      out.history.push_back(step);
      spdlog::info(
          "[sizing] iteration {}: {:.0f} kg, utilisation {:.3f}, delta {:.3f} x limit, "
          "lambda_LBA {:.3f}, {} members resized ({:.2f} s)",
          iteration, a.mass, a.utilisation, a.delta_ratio, step.lambda, step.changed, step.seconds);
      if (!missing.empty() && step.changed == 0) {
        failure_ = missing;
        break;
      }
      if (step.changed == 0 && !stiffness_short && strength_ok) {
        converged = true;
        break;
      }
      design = std::move(need);
    }
    out.iterations = iteration;
    if (!converged) {
      if (failure_.empty())
        failure_ = fmt::format("no fixed point within {} iterations", o_.max_iterations);
      out.final = std::move(a.runs);
      break;
    }
    if (level_ != analysis::AnalysisLevel::nonlinear) {
      out.final = std::move(a.runs);
      break;
    }
    // Step 4: the converged design at the full level — first, while rounds remain, a probe:
    // the lowest-λ_LBA combination alone on its non-linear paths (its knock-down λ / λ_LBA);
    // the full analysis of every combination only once the probe passes.
    if (round + 1 < o_.max_rounds && probe(a, design, iteration, out)) continue;
    if (verify(a, design, iteration, round + 1 == o_.max_rounds, out)) break;
  }
  out.member_sections = frame_of(design).member_sections;
  if (out.member_sections.empty())
    out.member_sections.assign(length_.size(), *analysis::member_section(frame_).profile);
  out.combinations = combos_;
  out.primary = primary_;
  out.lambda_lba_target = lba_target_;
  // The verdict is the final analysis's, whatever the iteration concluded.
  const std::string check = final_failure(combos_, out.final, level_, o_.lambda_min);
  out.failure = !check.empty() && failure_.empty() ? check : failure_;
  out.sized = check.empty() && failure_.empty();
  out.convergence =
      out.sized ? fmt::format("fixed point after {} iterations", out.iterations) : failure_;
  return out;
}

}  // namespace

SizingResult size_members(const PolyMesh& mesh, const std::vector<int>& supports,
                          const analysis::GridshellFrameOptions& frame,
                          const analysis::FrameAnalysisOptions& analysis,
                          analysis::AnalysisLevel level, const SizingOptions& options) {
  return Sizer(mesh, supports, frame, analysis, level, options).run();
}

}  // namespace gridshell::sizing
