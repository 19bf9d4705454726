#pragma once

#include <cstdlib>
// Helpers shared by the tests: where the shared data lives, running the executable, temp dirs.

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "gridshell/field/field.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell::test {

/// ../shared/data beside the checkout, or empty when absent (tests then GTEST_SKIP).
std::filesystem::path shared_data();

/// Path of a file under shared/data, or empty when absent.
std::filesystem::path shared_file(const std::string& relative);

/// The whole content of a file (empty when it cannot be read).
std::string slurp(const std::filesystem::path& path);

/// A JSON file parsed (throws nlohmann::json::exception when it is missing or malformed).
nlohmann::json read_json(const std::filesystem::path& path);

/// A fresh empty folder under the system temp dir, unique per test.
std::filesystem::path temp_dir(const std::string& name);

/// A finished command: its exit status and what it wrote.
struct RunResult {
  int status = -1;
  std::string out;
  std::string err;
};
/// Runs a shell command (stdin from /dev/null); its exit status, stdout and stderr.
RunResult run_command(const std::string& command);
/// Runs the gridshell executable with `args` (a shell-quoted string).
RunResult run_gridshell(const std::string& args);

/// A DXF file read back by an independent reader (Debian's python3-ezdxf) as JSON: `units`
/// ($INSUNITS), `audit_errors`, `polylines` ([layer, [[x, y], …], closed] in file order) and
/// `texts` ([layer, text, height]); null when the reader is missing or fails.
nlohmann::json read_dxf(const std::filesystem::path& file);

/// Centroid of triangle f.
inline Vec3 centroid(const TriMesh& m, int f) {
  return (m.vertex(m.F(f, 0)) + m.vertex(m.F(f, 1)) + m.vertex(m.F(f, 2))) / 3;
}

/// A synthetic field: u = x everywhere, d and a given as functions of the triangle centroid.
template <class Fd, class Fa>
Field synthetic_field(const TriMesh& m, Fd d, Fa a) {
  Field fd = uniform_field(m);
  for (int f = 0; f < m.num_faces(); ++f) {
    const Vec3 c = centroid(m, f);
    fd.u[f] = Vec3::UnitX();
    fd.d[f] = d(c);
    fd.a[f] = a(c);
  }
  return fd;
}

}  // namespace gridshell::test

/// An independent oracle (CalculiX, an MPI runtime) that is missing: the test is skipped on a
/// developer's machine, but fails in CI (CI set), where the set-up script installs it and a
/// silent skip would hide a missing check.
#define SKIP_OR_FAIL_IN_CI(why)                                         \
  do {                                                                  \
    if (std::getenv("CI") != nullptr) FAIL() << (why) << " (in CI: a missing oracle fails)"; \
    GTEST_SKIP() << (why);                                              \
  } while (0)

/// CI always has ../shared/data: there its absence fails the test instead of skipping it.
#define SKIP_WITHOUT_SHARED_DATA()                                          \
  do {                                                                      \
    if (gridshell::test::shared_data().empty()) SKIP_OR_FAIL_IN_CI("no ../shared/data"); \
  } while (0)
