// Results do not depend on the thread count (docs/DEVELOPING.md: deterministic for a --seed
// whatever the thread count): whole runs of the executable with --threads 1, 2 and 4 write the
// same files byte for byte — a default `design` with its objective search and a non-linear
// analysis, the quad-aniso baseline, and a small sweep. Only the measured seconds may differ —
// `timings_s` blocks and the search candidates' `seconds` in report.json and inside report.html's
// embedded data — and config.json's record of the run's own `out` and `threads` options: those
// are removed before comparing, nothing else.

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <regex>
#include <string>

#include <nlohmann/json.hpp>

#include "test_support.h"

namespace fs = std::filesystem;
using gridshell::test::run_gridshell;
using gridshell::test::slurp;
using gridshell::test::temp_dir;

namespace {

/// Removes what a run measures or was told about itself, recursively: `timings_s` blocks and
/// `seconds` figures (wall times), and in a config's `options` the output folder and thread count.
void strip_timings(nlohmann::json& j) {
  if (j.is_object()) {
    for (const char* key : {"timings_s", "seconds"}) j.erase(key);
    if (j.contains("options") && j["options"].is_object())
      for (const char* key : {"out", "threads"}) j["options"].erase(key);
    for (auto& [key, value] : j.items()) strip_timings(value);
  } else if (j.is_array()) {
    for (auto& value : j) strip_timings(value);
  }
}

/// A file's content as compared: bytes, except JSON files (parsed, stripped as above) and
/// report.html (the same keys stripped from its embedded JSON as text).
std::string comparable(const fs::path& file) {
  const std::string text = slurp(file);
  if (file.extension() == ".json") {
    nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded()) return text;
    strip_timings(j);
    return j.dump(1);
  }
  if (file.extension() == ".html") {
    static const std::regex measured(
        R"re("(timings_s|seconds)"\s*:\s*(\{[^{}]*\}|[-0-9.eE+]+),?|"(out|threads)"\s*:\s*"[^"]*",?)re");
    return std::regex_replace(text, measured, "");
  }
  return text;
}

/// Every file under `dir`, by path relative to it.
std::map<std::string, std::string> files_of(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out[fs::relative(e.path(), dir).string()] = comparable(e.path());
  return out;
}

/// Runs `args -o DIR --threads T` for T = 1, 2, 4 and expects the same files.
void expect_same_for_thread_counts(const std::string& name, const std::string& args) {
  std::map<std::string, std::string> first;
  for (int threads : {1, 2, 4}) {
    const fs::path dir = temp_dir(name + "_t" + std::to_string(threads));
    const auto r = run_gridshell(args + " --quiet --threads " + std::to_string(threads) + " -o " +
                                 dir.string());
    ASSERT_EQ(r.status, 0) << args << "\n" << r.err;
    const auto files = files_of(dir);
    ASSERT_FALSE(files.empty());
    if (threads == 1) {
      first = files;
      continue;
    }
    ASSERT_EQ(files.size(), first.size()) << name << " with " << threads << " threads";
    for (const auto& [path, content] : first) {
      const auto it = files.find(path);
      ASSERT_NE(it, files.end()) << path << " missing with " << threads << " threads";
      EXPECT_TRUE(it->second == content)
          << name << ": " << path << " differs between 1 and " << threads << " threads";
    }
  }
}

}  // namespace

TEST(Determinism, DefaultDesignWithObjectiveSearchAndNonlinearAnalysis) {
  // The default design (builtin:funicular, 300 cells, the balanced objective search) with the
  // non-linear path on top.
  expect_same_for_thread_counts("design", "design --analyze nonlinear");
}

TEST(Determinism, QuadAnisoBaseline) {
  expect_same_for_thread_counts(
      "quad_aniso", "baseline builtin:dome --kind quad-aniso --length 400 --analyze buckling");
}

TEST(Determinism, SmallSweep) {
  expect_same_for_thread_counts(
      "sweep", "sweep builtin:dome --D 1:2 --A 1:2 --repeats 2 --cells 40 --analyze buckling");
}
