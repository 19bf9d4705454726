#pragma once
// Helpers shared by the tests: where the shared data lives, running the executable, temp dirs.

#include <filesystem>
#include <string>

namespace gridshell::test {

/// ../shared/data beside the checkout, or empty when absent (tests then GTEST_SKIP).
std::filesystem::path shared_data();

/// Path of a file under shared/data, or empty when absent.
std::filesystem::path shared_file(const std::string& relative);

/// A fresh empty folder under the system temp dir, unique per test.
std::filesystem::path temp_dir(const std::string& name);

/// Runs the gridshell executable with `args` (a shell-quoted string); returns the exit status and
/// captures stdout and stderr.
struct RunResult {
  int status = -1;
  std::string out;
  std::string err;
};
RunResult run_gridshell(const std::string& args);

}  // namespace gridshell::test

#define SKIP_WITHOUT_SHARED_DATA()                                                   \
  do {                                                                               \
    if (gridshell::test::shared_data().empty()) GTEST_SKIP() << "no ../shared/data"; \
  } while (0)
