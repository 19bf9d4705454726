#pragma once
/// \file sweep.h
/// The paper's tuning experiment as a schedule: every (D, A, repeat) case, a deterministic seed
/// per case (so any partition of the cases — threads, `--shard K/N`, MPI ranks — reproduces the
/// same rows), parallel execution over TBB with results written to fixed slots, sweep.csv and
/// SVG heatmaps of the mean λ and δ over (D, A).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace gridshell {

struct SweepCase {
  int index = 0;  ///< position in the full, unsharded list
  double D = 1, A = 1;
  int repeat = 0;
  std::uint64_t seed = 1;
};

struct SweepRow {
  SweepCase c;
  int cells = 0;
  double total_length = 0;
  double lambda = 0;  ///< non-linear buckling factor (or the analysis' best available)
  double delta = 0;   ///< max displacement (m)
};

/// Parses "a:b" (integers a..b), "a:b:step" or a single value "a". Throws Error(option, ...).
std::vector<double> parse_range(const std::string& text, const std::string& option);

/// All cases in a fixed order (D outer, A, repeat inner); seeds derived from base_seed and the
/// case's (D, A, repeat) only.
std::vector<SweepCase> sweep_cases(const std::vector<double>& D, const std::vector<double>& A,
                                   int repeats, std::uint64_t base_seed);

/// Cases of shard K of N (1-based K): every N-th case starting at K-1. Parses "K/N".
std::vector<SweepCase> shard_cases(const std::vector<SweepCase>& cases, const std::string& shard);

/// Runs every case (in parallel when `parallel`), returning rows in case order.
std::vector<SweepRow> run_sweep(const std::vector<SweepCase>& cases,
                                const std::function<SweepRow(const SweepCase&)>& run_case,
                                bool parallel = true);

/// sweep.csv: D,A,repeat,seed,cells,total_length,lambda,delta
std::string sweep_csv(const std::vector<SweepRow>& rows);

/// The mean of `value` per (D, A) of `rows`: the distinct D and A values (ascending) and
/// mean(j, i) over the rows with A = A[j], D = D[i] (NaN where no row has them, e.g. a shard);
/// count(j, i) is the number of rows averaged.
struct SweepGrid {
  std::vector<double> D, A;
  Eigen::MatrixXd mean;
  Eigen::MatrixXi count;
};
SweepGrid sweep_grid(const std::vector<SweepRow>& rows,
                     const std::function<double(const SweepRow&)>& value);

/// An SVG heatmap of the mean of `value` over the (D, A) grid of `rows`.
std::string sweep_heatmap_svg(const std::vector<SweepRow>& rows, const std::string& title,
                              const std::function<double(const SweepRow&)>& value);

}  // namespace gridshell
