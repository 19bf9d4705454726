// The sweep schedule: ranges, deterministic per-case seeds, shards that partition the cases.

#include <gtest/gtest.h>

#include "gridshell/core/error.h"
#include "gridshell/pipeline/sweep.h"

using namespace gridshell;

TEST(Sweep, Ranges) {
  EXPECT_EQ(parse_range("1:4", "--D"), (std::vector<double>{1, 2, 3, 4}));
  EXPECT_EQ(parse_range("2", "--D"), (std::vector<double>{2}));
  EXPECT_EQ(parse_range("1:2:0.5", "--D"), (std::vector<double>{1, 1.5, 2}));
  EXPECT_THROW(parse_range("4:1", "--D"), Error);
  EXPECT_THROW(parse_range("a:b", "--D"), Error);
  EXPECT_THROW(parse_range("1:2:0", "--D"), Error);
}

TEST(Sweep, ShardsPartitionTheCasesWithTheSameSeeds) {
  auto all = sweep_cases(parse_range("1:4", "D"), parse_range("1:4", "A"), 3, 7);
  ASSERT_EQ(all.size(), 48u);
  auto s1 = shard_cases(all, "1/2"), s2 = shard_cases(all, "2/2");
  EXPECT_EQ(s1.size() + s2.size(), 48u);
  std::vector<int> seen(48, 0);
  for (const auto& c : s1) seen[c.index]++;
  for (const auto& c : s2) seen[c.index]++;
  for (int n : seen) EXPECT_EQ(n, 1);
  for (const auto& c : s2) EXPECT_EQ(c.seed, all[c.index].seed);
  // Seeds differ between cases and depend on the base seed.
  EXPECT_NE(all[0].seed, all[1].seed);
  EXPECT_NE(sweep_cases({1}, {1}, 1, 8)[0].seed, all[0].seed);
  EXPECT_THROW(shard_cases(all, "3/2"), Error);
  EXPECT_THROW(shard_cases(all, "0/2"), Error);
  EXPECT_THROW(shard_cases(all, "x"), Error);
}

TEST(Sweep, ParallelRunFillsRowsInCaseOrder) {
  auto cases = sweep_cases({1, 2}, {1, 2, 3}, 2, 1);
  auto run = [](const SweepCase& c) {
    SweepRow r;
    r.c = c;
    r.lambda = c.D * 10 + c.A + c.repeat;  // mean over the two repeats: 10 D + A + 0.5
    return r;
  };
  auto par = run_sweep(cases, run, true), seq = run_sweep(cases, run, false);
  EXPECT_EQ(sweep_csv(par), sweep_csv(seq));
  EXPECT_EQ(par[5].lambda, 14);  // D = 1, A = 3, repeat 1
  std::string svg = sweep_heatmap_svg(par, "lambda", [](const SweepRow& r) { return r.lambda; });
  // One cell per (D, A), each labelled with its mean at its place: D = 2 is the second column
  // (x = 60 + 70 + 35), A = 3 the top row of three (y = 50 + 35 + 4).
  std::size_t rects = 0;
  for (auto at = svg.find("<rect"); at != std::string::npos; at = svg.find("<rect", at + 1)) ++rects;
  EXPECT_EQ(rects, 6u);
  EXPECT_NE(svg.find("<text x=\"165\" y=\"89\" text-anchor=\"middle\">23.5</text>"),
            std::string::npos)
      << svg;
  EXPECT_NE(svg.find("<text x=\"95\" y=\"229\" text-anchor=\"middle\">11.5</text>"),
            std::string::npos)
      << svg;
}
