#include "gridshell/analysis/frame_analysis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>

#include <fmt/format.h>

#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "gridshell/core/enum_words.h"
#include "gridshell/core/error.h"
#include "gridshell/analysis/frame_records.h"

namespace gridshell::analysis {

using namespace gridshell::fem;

namespace {
double plan_span(const Points& X) {
  const Eigen::RowVector3d lo = X.colwise().minCoeff(), hi = X.colwise().maxCoeff();
  const double s = std::max(hi(0) - lo(0), hi(1) - lo(1));
  return s > 0 ? s : (hi - lo).norm();
}

/// The automatic displacement stop of the path (FrameAnalysisOptions::path_reach).
double automatic_stop(const Points& X, double span, double path_reach) {
  if (!(path_reach > 0)) return span / 5;
  return path_reach * (X.colwise().maxCoeff() - X.colwise().minCoeff()).maxCoeff();
}

/// λ where the path quantity x (one value per path point, λ = 0 first) first reaches `level`:
/// the quadratic through the crossing pair and the point before it, when x rises through the
/// three (the arc-length steps are long, and λ(x) bends: linear interpolation between two points
/// is off by the bend), else linear; never outside the three points' λ.
std::optional<double> lambda_at_level(const std::vector<double>& x,
                                      const std::vector<double>& lambdas, double level) {
  for (std::size_t i = 1; i < x.size(); ++i) {
    if (x[i] < level) continue;
    const double x0 = x[i - 1], x1 = x[i], l0 = lambdas[i - 1], l1 = lambdas[i];
    if (i >= 2 && x[i - 2] < x0 && x0 < x1) {
      const double xm = x[i - 2], lm = lambdas[i - 2];
      const double t = level;
      const double q = lm * (t - x0) * (t - x1) / ((xm - x0) * (xm - x1)) +
                       l0 * (t - xm) * (t - x1) / ((x0 - xm) * (x0 - x1)) +
                       l1 * (t - xm) * (t - x0) / ((x1 - xm) * (x1 - x0));
      return std::clamp(q, std::min({lm, l0, l1}), std::max({lm, l0, l1}));
    }
    const double rise = x1 - x0;
    const double t = rise > 0 ? (level - x0) / rise : 1.0;
    return l0 + std::clamp(t, 0.0, 1.0) * (l1 - l0);
  }
  return std::nullopt;
}

/// λ where the path's displacement first reaches `limit`.
std::optional<double> lambda_at_displacement(const std::vector<PathPoint>& path, double limit) {
  std::vector<double> x, lambdas;
  for (const PathPoint& p : path) {
    x.push_back(p.displacement);
    lambdas.push_back(p.lambda);
  }
  return lambda_at_level(x, lambdas, limit);
}
}  // namespace

namespace {
constexpr EnumWords<AnalysisLevel, 4> kLevelWords{{{"none", AnalysisLevel::none},
                                                   {"linear", AnalysisLevel::linear},
                                                   {"buckling", AnalysisLevel::buckling},
                                                   {"nonlinear", AnalysisLevel::nonlinear}}};
}  // namespace

AnalysisLevel parse_analysis_level(const std::string& word) {
  return parse_word(word, "--analyze", kLevelWords);
}

const char* to_string(AnalysisLevel level) { return word_of(level, kLevelWords); }

FrameAnalysisOptions at_level(FrameAnalysisOptions o, AnalysisLevel level) {
  o.linear = level != AnalysisLevel::none;
  o.buckling = level == AnalysisLevel::buckling || level == AnalysisLevel::nonlinear;
  o.nonlinear = level == AnalysisLevel::nonlinear;
  return o;
}

void perturb_geometry(FrameMesh& mesh, const Eigen::VectorXd& mode, double amplitude) {
  for (int v = 0; v < static_cast<int>(mesh.X.rows()); ++v)
    for (int c = 0; c < 3; ++c)
      if (mesh.dof[v][c] >= 0) mesh.X(v, c) += amplitude * mode(mesh.dof[v][c]);
  for (auto& e : mesh.elements) {
    const Vec3 a = mesh.X.row(e.i).transpose(), b = mesh.X.row(e.j).transpose();
    e.beam.l0 = (b - a).norm();
    e.beam.R0 = element_frame(a, b, e.beam.R0.col(2));
  }
}

namespace {

/// Per-member sums of per-element values.
std::vector<double> per_member(const FrameMesh& mesh, const std::vector<double>& per_element) {
  std::vector<double> out(mesh.member_elements.size(), 0.0);
  for (size_t m = 0; m < mesh.member_elements.size(); ++m)
    for (int k : mesh.member_elements[m]) out[m] += per_element[k];
  return out;
}

}  // namespace

namespace detail {

/// The linear solution's figures: δ, displacements, axial forces, reactions, strain energies,
/// equilibrium check.
void record_linear(const FrameMesh& mesh, const FrameAssembler& assembler,
                   const LinearResult& lin, const Eigen::VectorXd& load_full, FrameResult& res) {
  const int n0 = mesh.num_model_nodes;
  res.displacement = lin.displacement.topRows(n0);
  res.delta_max_m = lin.displacement.rowwise().norm().maxCoeff();
  if (n0 > 0) res.displacement.rowwise().norm().maxCoeff(&res.delta_node);
  res.axial_force.resize(mesh.member_elements.size());
  for (size_t m = 0; m < mesh.member_elements.size(); ++m)
    res.axial_force[m] = lin.axial[mesh.member_elements[m].front()];
  res.reactions = lin.reactions.head(6 * n0);
  res.strain_energy = per_member(mesh, element_strain_energy(mesh, assembler, lin.u));
  Vec3 R = Vec3::Zero(), F = Vec3::Zero();
  double Fabs = 0;
  for (int v = 0; v < static_cast<int>(mesh.X.rows()); ++v) {
    R += lin.reactions.segment<3>(6 * v);
    F += load_full.segment<3>(6 * v);
    Fabs += load_full.segment<3>(6 * v).norm();
  }
  res.equilibrium_error = Fabs > 0 ? (R + F).norm() / Fabs : 0;
  spdlog::info("linear: delta = {:.6g} m ({} elements, {} dofs)", res.delta_max_m, res.num_elements,
               res.num_dofs);
}

/// The linear solution's member checks and serviceability.
void record_checks(const FrameModel& model, const FrameMesh& mesh, const FrameAssembler& assembler,
                   const LinearResult& lin, const FrameAnalysisOptions& o, FrameResult& res) {
  res.member_forces = member_forces(mesh, element_section_forces(mesh, assembler, lin.u));
  res.checks = checks::check_members(model, res.member_forces, o.checks);
  if (res.checks.section_max > 0) res.lambda_yield_linear = 1 / res.checks.section_max;
  if (!(o.deflection_limit_divisor > 0))
    throw Error("--deflection-limit", "must be a span divisor > 0 (e.g. 300 for span/300)");
  res.span_m = plan_span(mesh.X);
  res.delta_limit_m = res.span_m / o.deflection_limit_divisor;
  res.delta_pass = res.delta_max_m <= res.delta_limit_m;
  spdlog::info("checks: utilisation {:.4g} (beam {}), buckling {:.4g}, delta {:.4g} m of {:.4g} m",
               res.checks.section_max, res.checks.section_worst, res.checks.buckling_max,
               res.delta_max_m, res.delta_limit_m);
}

/// The buckling modes' figures: λ_LBA, the factors, and the members' mode energy (modes within
/// 10 % of the first count alike: on a symmetric structure the first mode is an arbitrary member
/// of a degenerate pair, and its energy alone would be lopsided).
void record_buckling(const FrameMesh& mesh, const FrameAssembler& assembler,
                     const BucklingResult& lba, FrameResult& res) {
  res.buckling_lambdas = lba.lambdas;
  for (const Eigen::VectorXd& mode : lba.modes) {
    Points shape = Points::Zero(mesh.num_model_nodes, 3);
    for (int v = 0; v < mesh.num_model_nodes; ++v)
      for (int c = 0; c < 3; ++c)
        if (mesh.dof[v][c] >= 0) shape(v, c) = mode(mesh.dof[v][c]);
    const double largest = shape.rows() ? shape.rowwise().norm().maxCoeff() : 0.0;
    if (largest > 0) shape /= largest;
    res.buckling_modes.push_back(std::move(shape));
  }
  if (!lba.lambdas.empty()) {
    res.lambda_linear_buckling = lba.lambdas.front();
    res.mode_energy.assign(mesh.member_elements.size(), 0.0);
    for (std::size_t k = 0; k < lba.modes.size(); ++k) {
      if (lba.lambdas[k] > 1.1 * lba.lambdas.front()) break;
      const std::vector<double> e =
          per_member(mesh, element_strain_energy(mesh, assembler, lba.modes[k]));
      double sum = 0;
      for (double x : e) sum += x;
      if (sum > 0)
        for (std::size_t m = 0; m < e.size(); ++m) res.mode_energy[m] += e[m] / sum;
    }
    double total_energy = 0;
    for (double x : res.mode_energy) total_energy += x;
    if (total_energy > 0)
      for (double& x : res.mode_energy) x /= total_energy;
  }
  spdlog::info("linear buckling: lambda = {}",
               lba.lambdas.empty() ? std::string("none") : std::to_string(lba.lambdas[0]));
}

}  // namespace detail

namespace {

/// λ where the utilisation along the path first reaches 1.
std::optional<double> lambda_at_utilisation(const std::vector<double>& lambdas,
                                            const std::vector<double>& utilisation) {
  return lambda_at_level(utilisation, lambdas, 1.0);
}

/// One non-linear path (of the geometry perturbed by a buckling mode, or the perfect one) to its
/// first critical point, with the largest cross-section utilisation at every path point.
struct PathRun {
  ArcLengthResult al;
  std::vector<double> lambdas, utilisation;
};

/// One path of run_path being followed: the (perturbed) frame, its assembler and arc-length
/// options, the path, and what its points gave. Not movable (the assembler and the path refer to
/// the members).
struct PathJob {
  int mode = -1;  ///< < 0: the perfect path; else the geometry perturbed by sign × this mode
  double sign = 1;
  FrameMesh mesh;
  std::optional<FrameAssembler> assembler;
  ArcLengthOptions options;
  std::optional<ArcLengthPath> path;
  PathRun run;
  bool busy = false, done = false;
  bool stopped = false;  ///< ended early, above the lowest critical λ of the finished candidates
};

/// The job of one path: `mode` < 0 the perfect path; else the geometry perturbed by `sign` ×
/// that buckling mode (scaled to the imperfection amplitude). Every job's tangent has the same
/// pattern: its solvers copy `analysis`, made by the first job (ArcLengthOptions::analysis).
std::unique_ptr<PathJob> path_job(const FrameModel& model, const FrameMesh& mesh,
                                  const FrameAnalysisOptions& o, const BucklingResult& lba,
                                  const FrameResult& res, int mode, double sign,
                                  std::shared_ptr<const TangentSolver>& analysis) {
  const double span = plan_span(mesh.X);
  auto job = std::make_unique<PathJob>();
  job->mode = mode;
  job->sign = sign;
  job->mesh = mesh;
  if (mode >= 0 && mode < static_cast<int>(lba.modes.size()))
    perturb_geometry(job->mesh, lba.modes[mode], sign * res.imperfection_amplitude_m);
  job->assembler.emplace(job->mesh);
  ArcLengthOptions& ao = job->options;
  ao = o.arc;
  if (!analysis) {
    auto first = std::make_shared<TangentSolver>(Refactorisation::repeated);
    first->analyze(job->assembler->pattern());
    analysis = std::move(first);
  }
  ao.analysis = analysis;
  if (!(ao.initial_lambda > 0)) {
    ao.initial_lambda = res.lambda_linear_buckling
                            ? *res.lambda_linear_buckling / 10
                            : span / 2000 / std::max(res.delta_max_m, 1e-300);
  }
  if (!(ao.max_displacement > 0)) ao.max_displacement = automatic_stop(mesh.X, span, o.path_reach);
  // Only λ_δ asked: nothing beyond the displacement limit changes it.
  if (o.path_goal == PathGoal::displacement_limit)
    ao.max_displacement = std::min(ao.max_displacement, res.displacement_limit_m);
  if (res.lambda_linear_buckling && ao.max_lambda >= 1e9)
    ao.max_lambda = 20 * *res.lambda_linear_buckling;
  PathJob* j = job.get();
  const auto utilisation = [j, &model, &o](const FrameState& state) {
    return checks::max_section_utilisation(
        model, member_forces(j->mesh, element_section_forces(j->mesh, state)), o.checks);
  };
  ao.on_point = [j, utilisation](const FrameState& state, double lambda) {
    j->run.lambdas.push_back(lambda);
    j->run.utilisation.push_back(utilisation(state));
  };
  // The steps on which λ_δ and λ_y lie (kDisplacementCrossing, kYieldCrossing), for run_path to
  // locate on the paths whose λ_δ and λ_y it reports.
  ao.crossings = {{[j](const FrameState& state, double) {
                     return (state.x - j->mesh.X).rowwise().norm().maxCoeff();
                   },
                   res.displacement_limit_m},
                  {[utilisation](const FrameState& state, double) { return utilisation(state); },
                   1.0}};
  job->path.emplace(job->mesh, *job->assembler, ao, reference_state(job->mesh));
  return job;
}

/// The crossings every path records (ArcLengthOptions::crossings, in this order): the largest
/// displacement reaching the displacement limit (λ_δ), the largest utilisation reaching 1 (λ_y).
constexpr std::size_t kDisplacementCrossing = 0, kYieldCrossing = 1;

/// λ where the path of `job` (whose result is `al`) meets crossing `k`: located on the step the
/// path recorded (fem::locate_crossing, to 1e-6 of the level), so that it does not depend on
/// where the path's points fall; else `read_off` from the points (the crossing lies on the
/// bracketed step past a critical point, or the shorter steps did not converge).
std::optional<double> crossing_lambda(const PathJob* job, const ArcLengthResult& al,
                                      std::size_t k, const std::optional<double>& read_off) {
  if (!job || k >= al.crossing_steps.size() || !al.crossing_steps[k]) return read_off;
  const FrameAssembler assembler(job->mesh);
  int factorizations = 0;
  const std::optional<double> at =
      locate_crossing(job->mesh, assembler, job->options, job->options.crossings[k],
                      *al.crossing_steps[k], factorizations);
  spdlog::debug("non-linear: crossing {} located at lambda {} ({} factorisations; read off: {})",
                k, at ? fmt::format("{:.10g}", *at) : "-", factorizations,
                read_off ? fmt::format("{:.10g}", *read_off) : "-");
  return at ? at : read_off;
}

/// Ends a job's path (when `reason` is not empty, early, for that reason) and frees its solvers.
void end_job(PathJob& job, const std::string& reason) {
  job.run.al = job.path->finish(reason);
  job.path.reset();
  job.assembler.reset();
}

/// Follows the jobs' paths on up to as many threads as TBB may use, one attempted step at a
/// time, always advancing the free path of the lowest λ: the paths climb together. With `cap`,
/// an imperfection candidate (mode ≥ 0) whose λ has passed `critical(result)` of a candidate
/// that has ended is ended there: its critical point, if any, lies higher, so it cannot be the
/// lowest. Which candidates are ended early, and where, depends on the timing;
/// report_candidates turns it into what does not.
template <class Critical>
void follow_paths(std::vector<std::unique_ptr<PathJob>>& jobs, bool cap, const Critical& critical) {
  std::mutex mutex;
  double bound = std::numeric_limits<double>::infinity();
  const int threads =
      static_cast<int>(std::min<std::size_t>(tbb::this_task_arena::max_concurrency(), jobs.size()));
  const auto next_job = [&]() -> PathJob* {
    std::lock_guard lock(mutex);
    PathJob* best = nullptr;
    for (const auto& j : jobs) {
      if (j->busy || j->done) continue;
      if (cap && j->mode >= 0 && j->path->lambda() > bound) {
        j->done = j->stopped = true;
        end_job(*j, "stopped above a lower candidate's critical point");
        continue;
      }
      if (!best || j->path->lambda() < best->path->lambda()) best = j.get();
    }
    if (best) best->busy = true;
    return best;
  };
  tbb::parallel_for(0, std::max(threads, 1), [&](int) {
    while (PathJob* job = next_job()) {
      bool more = true;
      tbb::this_task_arena::isolate([&] { more = job->path->advance(); });
      if (!more) end_job(*job, "");
      std::lock_guard lock(mutex);
      job->busy = false;
      if (more) continue;
      job->done = true;
      if (job->mode >= 0)
        bound = std::min(bound, critical(job->run.al).value_or(std::numeric_limits<double>::infinity()));
    }
  });
}

/// The imperfections tried (FrameAnalysisOptions::imperfection_mode_margin): both signs of the
/// first mode, and of the next modes whose λ is within the margin of the first.
std::vector<std::pair<int, double>> imperfection_candidates(const FrameAnalysisOptions& o,
                                                            const BucklingResult& lba) {
  std::vector<std::pair<int, double>> out;
  for (std::size_t k = 0; k < lba.modes.size() && k < lba.lambdas.size(); ++k) {
    if (k > 0 && (static_cast<int>(k) >= o.imperfection_max_modes ||
                  lba.lambdas[k] > (1 + o.imperfection_mode_margin) * lba.lambdas.front()))
      break;
    out.emplace_back(static_cast<int>(k), 1.0);
    if (o.imperfection_both_signs) out.emplace_back(static_cast<int>(k), -1.0);
  }
  return out;
}

/// What a candidate reports: its critical λ, or, when it has passed the lowest candidate's
/// critical λ (λ_min) before any critical point of its own, the first of its points above λ_min
/// (`lambda_above`: no critical point up to there; it cannot be the lowest). Decided from the
/// path's points and λ_min alone — every candidate is followed at least to that point or to its
/// own critical point, whichever comes first, whatever follow_paths ended early —, so it does
/// not depend on the timing or the threads.
struct CandidateReport {
  std::optional<double> lambda, lambda_above;
  int steps = 0, factorizations = 0;  ///< the effort spent (for the log; timing-dependent)
};

template <class Critical>
std::vector<CandidateReport> report_candidates(const std::vector<std::unique_ptr<PathJob>>& jobs,
                                               bool cap, const Critical& critical) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const auto& j : jobs)
    if (j->mode >= 0 && !j->stopped)
      lowest = std::min(lowest, critical(j->run.al).value_or(lowest));
  std::vector<CandidateReport> out(jobs.size());
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const ArcLengthResult& al = jobs[i]->run.al;
    CandidateReport& r = out[i];
    r.steps = al.steps;
    r.factorizations = al.factorizations;
    if (jobs[i]->mode < 0) continue;
    // The converged points before the critical point (a bracketed path's last point lies past it).
    const std::size_t end = al.path.size() - (al.limit_type != fem::LimitType::none ? 1 : 0);
    for (std::size_t k = 1; cap && k < end && !r.lambda_above; ++k)
      if (al.path[k].lambda > lowest) r.lambda_above = al.path[k].lambda;
    if (!r.lambda_above) r.lambda = critical(al);
  }
  return out;
}

/// Why λ_imperfect came out above λ_perfect (report.json structure.imperfection.note).
std::string imperfection_note(const ArcLengthResult& perfect, const ArcLengthResult& imperfect) {
  if (perfect.limit_type == fem::LimitType::none)
    return fmt::format("the perfect path stopped before a critical point ({}) at lambda {:.4g}; "
                       "its lambda is where it stopped, not a critical load",
                       perfect.stop_reason, perfect.lambda_critical);
  if (perfect.limit_type == fem::LimitType::bifurcation)
    return "the perfect structure's critical point is a bifurcation; the imperfect paths (both "
           "signs of the modes tried) pass it on a stable branch and reach a higher limit point";
  if (imperfect.limit_type == fem::LimitType::none)
    return fmt::format("every imperfect path tried stopped before a critical point ({})",
                       imperfect.stop_reason);
  return "every imperfection tried (both signs of the modes within the margin) stiffens the "
         "structure: the perfect limit point is the lower one";
}

/// The non-linear path the options ask for (perfect, or imperfect with `imperfection`), λ at
/// the displacement limit and λ_y; with `stability` also the other path. The imperfect path is
/// the lowest of imperfection_candidates (the unfavourable direction).
void run_path(const FrameModel& model, const FrameMesh& mesh, const FrameAnalysisOptions& o,
              const BucklingResult& lba, FrameResult& res) {
  const double span = plan_span(mesh.X);
  res.imperfection_amplitude_m =
      o.imperfection_amplitude > 0 ? o.imperfection_amplitude : span / 300;
  res.displacement_limit_m = o.displacement_limit > 0 ? o.displacement_limit : span / 100;
  // λ of a path that stopped at the displacement limit is not its critical λ.
  const auto critical_lambda = [&](const ArcLengthResult& a) -> std::optional<double> {
    if (o.path_goal == PathGoal::displacement_limit && a.limit_type == fem::LimitType::none)
      return std::nullopt;
    return a.lambda_critical;
  };
  // Loads that go straight into the supports (every loaded joint pinned) leave nothing to
  // follow: no displacement, no buckling; a path would start at λ = span / 2000 / 0.
  if (!(res.delta_max_m > 0) && !res.lambda_linear_buckling) {
    res.nonlinear_stop_reason = "no displacement under the load (every loaded joint supported)";
    spdlog::info("non-linear: {}", res.nonlinear_stop_reason);
    return;
  }
  const bool can_perturb = !lba.modes.empty();
  const bool main_imperfect = o.imperfection && can_perturb;
  // The paths are independent: followed together (each the same whatever the threads).
  std::vector<std::unique_ptr<PathJob>> jobs;
  std::shared_ptr<const TangentSolver> analysis;
  if (!main_imperfect || o.stability)
    jobs.push_back(path_job(model, mesh, o, lba, res, -1, 1.0, analysis));
  if (can_perturb && (main_imperfect || o.stability))
    for (const auto& [mode, sign] : imperfection_candidates(o, lba))
      jobs.push_back(path_job(model, mesh, o, lba, res, mode, sign, analysis));
  for (std::size_t i = 1; i < jobs.size(); ++i) jobs[i]->options.progress = {};  // one display
  // Candidates are ended above a lower one's critical point only when that is what they are
  // followed for (with the displacement-limit goal a path's λ is not its critical λ).
  const bool cap = o.path_goal == PathGoal::critical && !o.imperfection_full_paths;
  follow_paths(jobs, cap, critical_lambda);
  std::optional<PathRun> perfect, imperfect;
  const PathJob *perfect_job = nullptr, *imperfect_job = nullptr;
  const std::vector<CandidateReport> reports = report_candidates(jobs, cap, critical_lambda);
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    PathJob& job = *jobs[i];
    if (job.mode < 0) {
      perfect = std::move(job.run);
      perfect_job = &job;
      continue;
    }
    const ArcLengthResult& al = job.run.al;
    const CandidateReport& report = reports[i];
    res.imperfections_tried.push_back({job.mode, job.sign, report.lambda, report.lambda_above});
    if (report.lambda_above)
      spdlog::info("non-linear (imperfect, mode {} sign {:+}): no critical point up to lambda = "
                   "{:.6g}, above the lowest candidate's ({} steps, {} factorisations)",
                   job.mode + 1, job.sign, *report.lambda_above, report.steps,
                   report.factorizations);
    else
      spdlog::info("non-linear (imperfect, mode {} sign {:+}): lambda = {:.6g} ({}; {} steps, {} "
                   "factorisations)",
                   job.mode + 1, job.sign, al.lambda_critical, fem::to_string(al.limit_type),
                   al.steps, al.factorizations);
    const double l = report.lambda.value_or(std::numeric_limits<double>::infinity());
    if (!report.lambda_above && (!imperfect || l < best)) {
      best = l;
      imperfect = std::move(job.run);
      imperfect_job = &job;
      res.imperfection_mode = job.mode;
      res.imperfection_sign = job.sign;
    }
  }
  const auto largest = [](const std::vector<double>& u) {
    return u.empty() ? 0.0 : *std::max_element(u.begin(), u.end());
  };
  const PathRun& main = main_imperfect ? *imperfect : *perfect;
  const PathJob* main_job = main_imperfect ? imperfect_job : perfect_job;
  const PathRun* yield_run = imperfect ? &*imperfect : &main;
  const PathJob* yield_job = imperfect ? imperfect_job : main_job;
  // λ_y of the perfect path and of the reported one (the same without an imperfect path) and λ_δ
  // of the main path, each located on its own path's frame: side by side.
  std::optional<double> lambda_delta;
  tbb::task_group locate;
  if (perfect)
    locate.run([&] {
      res.lambda_yield_perfect =
          crossing_lambda(perfect_job, perfect->al, kYieldCrossing,
                          lambda_at_utilisation(perfect->lambdas, perfect->utilisation));
    });
  if (imperfect)
    locate.run([&] {
      res.lambda_yield =
          crossing_lambda(yield_job, yield_run->al, kYieldCrossing,
                          lambda_at_utilisation(yield_run->lambdas, yield_run->utilisation));
    });
  locate.run([&] {
    lambda_delta = crossing_lambda(main_job, main.al, kDisplacementCrossing,
                                   lambda_at_displacement(main.al.path, res.displacement_limit_m));
  });
  locate.wait();
  if (perfect) res.lambda_perfect = critical_lambda(perfect->al);
  if (!imperfect && perfect) res.lambda_yield = res.lambda_yield_perfect;
  res.lambda_yield_path = imperfect ? "imperfect" : "perfect";
  res.path_utilisation_max = largest(yield_run->utilisation);
  if (imperfect) {
    res.lambda_imperfect = critical_lambda(imperfect->al);
    if (res.lambda_perfect && res.lambda_imperfect && *res.lambda_imperfect > *res.lambda_perfect)
      res.imperfection_note = imperfection_note(perfect->al, imperfect->al);
  }
  const ArcLengthResult& al = main.al;
  res.path = al.path;
  res.lambda_nonlinear = critical_lambda(al);
  res.limit_type = al.limit_type;
  res.nonlinear_stop_reason = al.stop_reason;
  res.nonlinear_steps = al.steps;
  res.nonlinear_iterations = al.iterations;
  res.nonlinear_factorizations = al.factorizations;
  res.lambda_displacement_limit = lambda_delta;
  if (!res.lambda_displacement_limit && al.limit_type != fem::LimitType::none)
    res.lambda_displacement_limit = al.lambda_critical;
  spdlog::info("non-linear: lambda = {:.6g} ({}; {} steps, {} iterations)", al.lambda_critical,
               fem::to_string(al.limit_type), al.steps, al.iterations);
}

/// The non-linear equilibrium at one load factor.
void record_nonlinear_static(const FrameMesh& mesh, const FrameAssembler& assembler,
                             const FrameAnalysisOptions& o, FrameResult& res) {
  const int n0 = mesh.num_model_nodes;
  const NonlinearStaticResult ns =
      nonlinear_static(mesh, assembler, o.nonlinear_static, {}, o.subject);
  res.nonlinear_displacement = Points(displacements(mesh, ns.state).topRows(n0));
  res.nonlinear_rotation = Points(rotations(ns.state).topRows(n0));
  res.nonlinear_axial_force.resize(mesh.member_elements.size());
  for (size_t m = 0; m < mesh.member_elements.size(); ++m)
    res.nonlinear_axial_force[m] = ns.axial[mesh.member_elements[m].front()];
}

}  // namespace

FrameResult analyze_frame(const FrameModel& model, const FrameAnalysisOptions& o) {
  Stopwatch total, t;
  FrameResult res;
  const FrameMesh mesh = discretize(model, o.subject);
  if (mesh.load.norm() == 0 && mesh.load_full.norm() == 0)
    throw Error(o.subject, "no loads: nothing to analyse");
  res.num_elements = static_cast<int>(mesh.elements.size());
  res.num_dofs = mesh.num_dofs;
  res.mass_kg = total_mass(model);
  res.total_length_m = total_length(model);
  res.nodes = model.nodes;
  const FrameAssembler assembler(mesh);
  res.timings["setup"] = t.seconds();

  t = Stopwatch();
  LinearResult lin = linear_static(mesh, assembler, o.subject);
  res.timings["linear"] = t.seconds();
  detail::record_linear(mesh, assembler, lin, mesh.load_full, res);
  detail::record_checks(model, mesh, assembler, lin, o, res);
  if (o.after_linear) o.after_linear(res);

  BucklingResult lba;
  if (o.buckling || (o.nonlinear && (o.imperfection || o.stability))) {
    t = Stopwatch();
    BucklingOptions bo;
    bo.modes = std::max(1, o.buckling_modes);
    lba = linear_buckling(mesh, assembler, lin, bo);
    res.timings["buckling"] = t.seconds();
    detail::record_buckling(mesh, assembler, lba, res);
  }
  lin.stiffness.reset();  // K's factor (tens of MB on large frames) is not needed any more
  if (o.nonlinear) {
    t = Stopwatch();
    run_path(model, mesh, o, lba, res);
    res.timings["nonlinear"] = t.seconds();
  }
  if (o.nonlinear_static > 0) {
    t = Stopwatch();
    record_nonlinear_static(mesh, assembler, o, res);
    res.timings["nonlinear_static"] = t.seconds();
  }
  res.timings["total"] = total.seconds();
  return res;
}

}  // namespace gridshell::analysis
