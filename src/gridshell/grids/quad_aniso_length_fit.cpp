#include "gridshell/grids/quad_aniso_internal.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

namespace gridshell::quad_aniso_internal {

namespace {

/// The jobs of lattice starts from … to − 1 at one spacing.
std::vector<std::pair<double, int>> starts_at(double spacing, int from, int to) {
  std::vector<std::pair<double, int>> jobs;
  for (int start = from; start < to; ++start) jobs.emplace_back(spacing, start);
  return jobs;
}

}  // namespace

void CandidatePool::add(const std::vector<std::pair<double, int>>& jobs) {
  std::vector<std::pair<double, int>> todo;
  for (const auto& job : jobs)
    if (built_.insert(job).second) todo.push_back(job);
  std::vector<Candidate> made(todo.size());
  tbb::parallel_for(0, static_cast<int>(todo.size()),
                    [&](int k) { made[k] = build_(todo[k].first, todo[k].second); });
  for (Candidate& c : made) grids_.push_back(std::move(c));
}

bool CandidatePool::within(double limit) const {
  return std::any_of(grids_.begin(), grids_.end(),
                     [&](const Candidate& c) { return std::abs(c.error) <= limit; });
}

const Candidate* CandidatePool::choose(double tolerance) const {
  const Candidate* best = nullptr;
  for (const Candidate& c : grids_) {
    const bool in = std::abs(c.error) <= tolerance;
    const bool best_in = best && std::abs(best->error) <= tolerance;
    if (!best || (in && (!best_in || c.score > best->score)) ||
        (!in && !best_in && std::abs(c.error) < std::abs(best->error)))
      best = &c;
  }
  return best;
}

SpacingFit fit_spacing(CandidatePool& pool, double h, int starts, const QuadAnisoOptions& o) {
  SpacingFit fit;
  const std::vector<Candidate>& grids = pool.grids();
  const int fits = o.length > 0 ? o.max_fits : 1;
  double h_long = 0, h_short = std::numeric_limits<double>::infinity();  // see the bracket below
  for (int k = 0; k < fits; ++k) {
    // The secant follows the median length of the starts at this h: one start's grid can lose a
    // piece (only the largest connected part is kept), and its length would send the fit astray.
    ++fit.fits;
    const size_t first = grids.size();
    size_t top = first;
    pool.add(starts_at(h, 0, starts));
    if (grids.size() == first) break;  // the fit came back to a spacing it had tried
    for (size_t c = first; c < grids.size(); ++c)
      if (grids[c].score > grids[top].score) top = c;
    std::vector<double> lengths;
    for (size_t c = first; c < grids.size(); ++c) lengths.push_back(grids[c].length);
    std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
    const double length = lengths[lengths.size() / 2];
    spdlog::info(
        "[quad-aniso] h = {:.4g} m on M': {} starts, median {:.1f} m; the best: {} joints, "
        "{} faces, {:.1f} m",
        h, starts, length, grids[top].grid.num_vertices(), grids[top].grid.num_faces(),
        grids[top].length);
    if (std::abs(grids[top].error) <= o.length_tolerance) break;
    // L(h) is a step function (whole cells) and jumps with the lattice's start, so the secant on
    // L ∝ 1/h can oscillate about the target on a small grid: once h is bracketed (one grid too
    // long, one too short) a step that leaves the bracket is replaced by its geometric middle.
    if (length > o.length)
      h_long = std::max(h_long, h);
    else
      h_short = std::min(h_short, h);
    double next = h * length / o.length;
    if (h_long > 0 && std::isfinite(h_short) && h_long < h_short &&
        !(next > h_long && next < h_short))
      next = std::sqrt(h_long * h_short);
    h = next;
  }
  fit.next_spacing = h;
  return fit;
}

void starts_across_target(CandidatePool& pool, double next_spacing, int starts,
                          const QuadAnisoOptions& o) {
  const double limit = std::max(o.length_tolerance, o.length_limit);
  if (!(o.length > 0) || pool.within(limit)) return;
  const Candidate *above = nullptr, *below = nullptr;
  for (const Candidate& c : pool.grids()) {
    if (c.error > 0 && (!above || c.error < above->error)) above = &c;
    if (c.error < 0 && (!below || c.error > below->error)) below = &c;
  }
  std::vector<double> retry;
  if (above) retry.push_back(above->spacing);
  if (below) retry.push_back(below->spacing);
  const double h = next_spacing;
  if (retry.size() < 2 && std::isfinite(h) && h > 0) retry.push_back(h);
  const int before = pool.size();
  for (int start = starts; start < starts + o.extra_starts && !pool.within(limit); ++start) {
    std::vector<std::pair<double, int>> jobs;
    for (double spacing : retry) jobs.emplace_back(spacing, start);
    pool.add(jobs);
  }
  spdlog::info("[quad-aniso] {} more lattice starts at {} spacings", pool.size() - before,
               retry.size());
}

int starts_at_chosen(CandidatePool& pool, double area_def, int starts, const QuadAnisoOptions& o) {
  const double chosen = pool.choose(o.length_tolerance)->spacing;
  const double cells = area_def / (chosen * chosen);
  const int total = static_cast<int>(std::clamp(std::floor(o.start_cells / cells), double(starts),
                                                double(std::max(starts, o.max_starts))));
  const int before = pool.size();
  pool.add(starts_at(chosen, starts, total));
  if (pool.size() > before)
    spdlog::info("[quad-aniso] {} more lattice starts at h = {:.4g} m (about {:.0f} cells)",
                 pool.size() - before, chosen, cells);
  return total;
}

}  // namespace gridshell::quad_aniso_internal
