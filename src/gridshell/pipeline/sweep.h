#pragma once
/// \file sweep.h
/// The paper's tuning experiment as a schedule: every (D, A, repeat) case, a deterministic seed
/// per case (so any partition of the cases — threads, `--shard K/N`, MPI ranks — reproduces the
/// same rows), parallel execution over TBB with results written to fixed slots, sweep.csv,
/// report.json's `points` and SVG heatmaps of the mean λ and δ over (D, A). With the Eurocode
/// loads each row also carries its design's verdict (`SweepGoverning`).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace gridshell {

struct SweepCase {
  int index = 0;  ///< position in the full, unsharded list
  double D = 1, A = 1;
  int repeat = 0;
  std::uint64_t seed = 1;
};

/// A point's verdict by the rule of `design`: report.json's `structure.governing` of that design
/// (governing_block, pipeline/design.h: over every load combination, the largest utilisation,
/// the smallest λ, the largest SLS δ, each with its combination, and the verdicts), kept as
/// plain values so that rows travel between MPI ranks as bytes (app/mpi.h).
struct SweepGoverning {
  /// Longest combination name a row holds (with its terminating zero); the command checks the
  /// file load cases' names against it before any work (kMaxLoadCaseName).
  static constexpr std::size_t kNameSize = 64;
  /// The longest file load case name whose combinations ("ULS_NAME_Ginf", …) fit.
  static constexpr std::size_t kMaxLoadCaseName = 48;
  struct Figure {
    bool known = false;   ///< a combination had this figure (no λ without buckling analysis)
    double value = 0;     ///< utilisation_value | lambda_value | delta_m
    bool judged = false;  ///< `pass` is set (δ: its combination has a limit)
    bool pass = false;    ///< utilisation ≤ 1 | λ ≥ 1 | δ ≤ its limit
    char combination[kNameSize] = {};
  };
  bool judged = false;  ///< the point was judged (--loads eurocode); the rest is set only then
  Figure utilisation, lambda, delta;
  bool pass = false;  ///< every verdict that was computed passes
};

/// The values of a `structure.governing` block (governing_block). Throws Error("--load-case")
/// when a combination's name does not fit kNameSize.
SweepGoverning sweep_governing(const nlohmann::json& governing);
/// The block again, key for key (governing_block's keys: "utilisation", "utilisation_value",
/// "utilisation_pass", "lambda", …, "delta_m", "delta_pass", "pass").
nlohmann::json governing_json(const SweepGoverning& g);

struct SweepRow {
  SweepCase c;
  int cells = 0;
  double total_length = 0;
  double lambda = 0;  ///< non-linear buckling factor (or the analysis' best available)
  double delta = 0;   ///< max displacement (m)
  SweepGoverning governing;  ///< with --loads eurocode
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

/// sweep.csv: D,A,repeat,seed,cells,total_length,lambda,delta; when the rows were judged
/// (--loads eurocode) also governing_utilisation,governing_lambda,governing_delta,pass,
/// governing_utilisation_combination,governing_lambda_combination,governing_delta_combination
/// (an empty cell where a figure was not computed, e.g. λ without a buckling analysis; pass is
/// true or false).
std::string sweep_csv(const std::vector<SweepRow>& rows);

/// report.json's `points`: per row {D, A, repeat, seed, cells, total_length_m, lambda,
/// delta_m} and, when judged, `governing` (governing_json).
nlohmann::json sweep_points_json(const std::vector<SweepRow>& rows);

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
