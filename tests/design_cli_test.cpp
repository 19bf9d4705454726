// gridshell design: files written per the CONTRACT, report contents, determinism, errors.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/topology.h"
#include "test_support.h"

using gridshell::test::run_gridshell;
using gridshell::test::temp_dir;
namespace fs = std::filesystem;

namespace {
std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

TEST(DesignCli, WritesTheContractFiles) {
  const fs::path d = temp_dir("out");
  const auto r = run_gridshell("design builtin:dome --cells 80 --seed 3 -o " + d.string());
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* f : {"gridshell_raw.obj", "gridshell.obj", "gridshell.ply", "gridshell.vtp",
                        "cells.csv", "report.json", "config.json"})
    EXPECT_TRUE(fs::exists(d / f)) << f;
  EXPECT_EQ(slurp(d / "gridshell.obj"), slurp(d / "gridshell_raw.obj"));
  const auto report = nlohmann::json::parse(slurp(d / "report.json"));
  const auto& m = report.at("mesh");
  EXPECT_EQ(m.at("faces").get<int>(), 80);
  // The numbers agree with the mesh written.
  const auto file = gridshell::io::read_mesh(d / "gridshell.obj");
  EXPECT_EQ(file.mesh.num_vertices(), m.at("vertices").get<int>());
  EXPECT_EQ(file.mesh.num_faces(), m.at("faces").get<int>());
  const gridshell::Topology topo = gridshell::build_topology(file.mesh);
  EXPECT_EQ(topo.num_edges(), m.at("edges").get<int>());
  double len = 0;
  for (const auto& e : topo.edges) len += (file.mesh.vertex(e[0]) - file.mesh.vertex(e[1])).norm();
  EXPECT_NEAR(len, m.at("total_length_m").get<double>(), 1e-6 * len);
  int sides_total = 0;
  for (const auto& [k, v] : m.at("face_sides").items()) sides_total += v.get<int>();
  EXPECT_EQ(sides_total, 80);
  for (const char* k :
       {"hex_share_interior", "valence3_share_interior", "edge_length_cv", "radius_m",
        "lloyd_iterations", "supports", "planarity_mean", "regularity_mean"})
    EXPECT_TRUE(m.contains(k)) << k;
  EXPECT_FALSE(m.at("supports").empty());
  EXPECT_TRUE(report.at("timings_s").contains("tessellation"));
  EXPECT_TRUE(report.at("timings_s").contains("total"));
  // cells.csv: header + one row per face, uniform targets.
  std::istringstream csv(slurp(d / "cells.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "face,sides,area,d_target,a_target");
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    EXPECT_EQ(line.substr(line.size() - 4), ",1,1");
  }
  EXPECT_EQ(rows, 80);
  // config.json repeats the run identically.
  const fs::path d2 = temp_dir("again");
  const auto r2 =
      run_gridshell("design --config " + (d / "config.json").string() + " --out " + d2.string());
  ASSERT_EQ(r2.status, 0) << r2.err;
  EXPECT_EQ(slurp(d / "gridshell.obj"), slurp(d2 / "gridshell.obj"));
  // Thread count does not change the result.
  const fs::path d3 = temp_dir("threads");
  const auto r3 = run_gridshell("design builtin:dome --cells 80 --seed 3 --quiet --threads 1 -o " +
                                d3.string());
  ASSERT_EQ(r3.status, 0) << r3.err;
  EXPECT_EQ(slurp(d / "gridshell.obj"), slurp(d3 / "gridshell.obj"));
}

TEST(DesignCli, RejectsWhatIsNotAvailableYet) {
  const fs::path d = temp_dir("bad");
  for (const char* args : {"--field stress", "-A 2", "-D 3", "--analyze linear",
                           "--radius 1 --cells 10", "--cells -5", "--field foo"}) {
    const auto r = run_gridshell(std::string("design builtin:dome ") + args + " -o " + d.string());
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find("gridshell: error"), std::string::npos) << args << ": " << r.err;
  }
  const auto missing = run_gridshell("design /nonexistent.ply -o " + d.string());
  EXPECT_EQ(missing.status, 2);
}
