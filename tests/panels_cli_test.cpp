// `--panels flat` through the command line (docs/panels.md): a design whose flat stage passes
// reports flat panels within the post-check's 0.5 mm in report.json and panels.csv; a baseline
// whose panels are flat already (triangles) keeps its grid as it is; one whose flat stage fails
// keeps exactly its free grid and says why.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace fs = std::filesystem;
using namespace gridshell;
using test::read_json;

namespace {

/// The largest value of panels.csv's `out_of_plane_mm` column.
double panels_csv_out_of_plane_max_mm(const fs::path& csv) {
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  int column = -1, k = 0;
  std::stringstream hs(header);
  for (std::string cell; std::getline(hs, cell, ','); ++k)
    if (cell == "out_of_plane_mm") column = k;
  EXPECT_GE(column, 0) << header;
  double largest = -1;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::string cell;
    for (int c = 0; c <= column && std::getline(ls, cell, ','); ++c) {
    }
    largest = std::max(largest, std::stod(cell));
  }
  return largest;
}

/// Runs a baseline of the built-in dome with and without `--panels flat`.
struct BaselinePair {
  fs::path free_dir, flat_dir;
  std::string flat_err;  ///< what the flat run printed on stderr
};

/// How often `text` says `what`.
int count_of(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}
BaselinePair dome_baseline(const std::string& kind) {
  BaselinePair p{test::temp_dir("panels_cli_free_" + kind),
                 test::temp_dir("panels_cli_flat_" + kind), {}};
  const std::string base =
      "baseline builtin:dome --kind " + kind + " --length 440 --analyze none --quiet -o ";
  const auto free = test::run_gridshell(base + p.free_dir.string());
  EXPECT_EQ(free.status, 0) << free.err;
  const auto flat = test::run_gridshell(base + p.flat_dir.string() + " --panels flat");
  EXPECT_EQ(flat.status, 0) << flat.err;
  p.flat_err = flat.err;
  return p;
}

}  // namespace

TEST(PanelsCli, FlatDesignPanelsAreWithinHalfAMillimetre) {
  const fs::path d = test::temp_dir("panels_cli_design");
  const auto r = test::run_gridshell(
      "design builtin:dome --cells 120 --seed 1 --panels flat --analyze none --quiet -o " +
      d.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto mesh = read_json(d / "report.json").at("mesh");
  EXPECT_EQ(mesh.at("panels"), "flat");
  EXPECT_LE(mesh.at("out_of_plane_max_m").get<double>(), 5e-4);
  EXPECT_EQ(mesh.at("self_intersecting_panels").get<int>(), 0);
  EXPECT_LE(panels_csv_out_of_plane_max_mm(d / "panels.csv"), 0.5);
  // The free design of the same options is not flat (the stage did the work): the dome's cells
  // are curved hexagons, out of plane by centimetres at this size.
  const fs::path f = test::temp_dir("panels_cli_design_free");
  ASSERT_EQ(test::run_gridshell("design builtin:dome --cells 120 --seed 1 --analyze none "
                                "--quiet -o " + f.string())
                .status,
            0);
  EXPECT_GT(read_json(f / "report.json").at("mesh").at("out_of_plane_max_m").get<double>(),
            5e-3);
}

TEST(PanelsCli, TrianglesAreFlatAlreadyAndKeptAsTheyAre) {
  const BaselinePair p = dome_baseline("tri");
  const auto report = read_json(p.flat_dir / "report.json");
  EXPECT_EQ(report.at("mesh").at("panels"), "flat");
  EXPECT_FALSE(report.at("flat_panels").contains("failure"));
  EXPECT_EQ(test::slurp(p.flat_dir / "gridshell.obj"), test::slurp(p.free_dir / "gridshell.obj"));
}

TEST(PanelsCli, AFailedFlatStageKeepsTheFreeGridAndSaysWhy) {
  // Quads of the dome's grid: valence-4 joints whose split collapses beams or folds panels.
  const BaselinePair p = dome_baseline("quad");
  const auto report = read_json(p.flat_dir / "report.json");
  EXPECT_EQ(report.at("mesh").at("panels"), "free");
  EXPECT_FALSE(report.at("flat_panels").at("failure").get<std::string>().empty());
  EXPECT_EQ(test::slurp(p.flat_dir / "gridshell.obj"), test::slurp(p.free_dir / "gridshell.obj"));
  // One warning (with --quiet too), naming the failure report.json records.
  EXPECT_EQ(count_of(p.flat_err, "keeping the free panels"), 1) << p.flat_err;
  EXPECT_NE(p.flat_err.find(report.at("flat_panels").at("failure").get<std::string>()),
            std::string::npos)
      << p.flat_err;
}

TEST(PanelsCli, FlatDoublyCurvedDesignsKeepTheirBucklingLoad) {
  // λ_LBA of the flat design within 10 % of the free one's (docs/panels.md)
  // where the flat stage passes on a doubly curved roof. Measured at 120 cells: dome +10 %,
  // paraboloid +8 % (the joints leave the surface a little towards a funicular shape).
  for (const std::string surface : {"dome", "paraboloid"}) {
    double lambda[2] = {0, 0};
    for (int flat = 0; flat < 2; ++flat) {
      const fs::path d = test::temp_dir("panels_cli_lba_" + surface + std::to_string(flat));
      const auto r = test::run_gridshell("design builtin:" + surface +
                                         " --cells 120 -D 2 -A 2 --seed 1 --analyze buckling "
                                         "--figures none --quiet --panels " +
                                         (flat ? "flat" : "free") + " -o " + d.string());
      ASSERT_EQ(r.status, 0) << r.err;
      const auto report = read_json(d / "report.json");
      ASSERT_EQ(report.at("mesh").at("panels"), flat ? "flat" : "free") << surface;
      lambda[flat] = report.at("structure").at("lambda_lba").get<double>();
    }
    EXPECT_GT(lambda[0], 0) << surface;
    EXPECT_GE(lambda[1], 0.9 * lambda[0]) << surface;
    EXPECT_LE(lambda[1], 1.2 * lambda[0]) << surface;
  }
}
