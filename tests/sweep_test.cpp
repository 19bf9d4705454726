// The sweep schedule: ranges, deterministic per-case seeds, shards that partition the cases.

#include <gtest/gtest.h>

#include <type_traits>

#include "gridshell/core/error.h"
#include "gridshell/pipeline/design.h"
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

TEST(Sweep, RowsKeepDesignsGoverningBlockKeyForKey) {
  // design's governing_block over hand-written combinations (the drifted ones govern, δ fails)
  // survives the row's plain values unchanged; a block without λ (no buckling analysis) leaves
  // the λ cells empty; rows travel between MPI ranks as bytes.
  static_assert(std::is_trivially_copyable_v<SweepRow>);
  const nlohmann::json combinations = {
      {"ULS", {{"uls", true}, {"lambda", 2.5}, {"utilisation_max", 0.4}, {"delta_max_m", 0.05},
               {"delta_limit_m", 0.0667}}},
      {"ULS_S_x+", {{"uls", true}, {"lambda", 1.6}, {"utilisation_max", 0.9},
                    {"delta_max_m", 0.12}, {"delta_limit_m", 0.0667}}},
      {"SLS_S_x+", {{"uls", false}, {"delta_max_m", 0.09}, {"delta_limit_m", 0.0667}}}};
  const nlohmann::json g = governing_block(combinations);
  ASSERT_EQ(g.at("lambda"), "ULS_S_x+");
  ASSERT_FALSE(g.at("pass").get<bool>());
  EXPECT_EQ(governing_json(sweep_governing(g)), g);
  nlohmann::json linear = combinations;
  for (auto& [name, c] : linear.items()) c.erase("lambda");
  const nlohmann::json gl = governing_block(linear);
  ASSERT_FALSE(gl.contains("lambda"));
  EXPECT_EQ(governing_json(sweep_governing(gl)), gl);

  std::vector<SweepRow> rows(2);
  rows[0].c = sweep_cases({2}, {1}, 1, 1)[0];
  rows[0].governing = sweep_governing(g);
  rows[1].governing = sweep_governing(gl);
  const std::string csv = sweep_csv(rows);
  const std::string header = csv.substr(0, csv.find('\n'));
  EXPECT_EQ(header,
            "D,A,repeat,seed,cells,total_length,lambda,delta,governing_utilisation,"
            "governing_lambda,governing_delta,pass,governing_utilisation_combination,"
            "governing_lambda_combination,governing_delta_combination");
  EXPECT_NE(csv.find(",0.9,1.6,0.09,false,ULS_S_x+,ULS_S_x+,SLS_S_x+\n"), std::string::npos)
      << csv;
  EXPECT_NE(csv.find(",0.9,,0.09,false,ULS_S_x+,,SLS_S_x+\n"), std::string::npos) << csv;
  const nlohmann::json points = sweep_points_json(rows);
  EXPECT_EQ(points.at(0).at("governing"), g);
  EXPECT_EQ(points.at(0).at("D").get<double>(), 2);
  // Unjudged rows (the paper's load) keep the columns of the paper's table.
  const std::string paper = sweep_csv({SweepRow{}});
  EXPECT_EQ(paper.substr(0, paper.find('\n')), "D,A,repeat,seed,cells,total_length,lambda,delta");
  EXPECT_FALSE(sweep_points_json({SweepRow{}}).at(0).contains("governing"));
  // A combination name that does not fit a row is an error, never a cut name.
  nlohmann::json long_name = g;
  long_name["lambda"] = std::string(SweepGoverning::kNameSize, 'x');
  EXPECT_THROW(sweep_governing(long_name), Error);
}
