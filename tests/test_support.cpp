#include "test_support.h"

#include <sys/wait.h>
#include <unistd.h>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

namespace gridshell::test {

namespace fs = std::filesystem;

fs::path shared_data() {
  fs::path p = fs::path(GRIDSHELL_SHARED_DIR) / "data";
  std::error_code ec;
  return fs::is_directory(p, ec) ? p : fs::path();
}

fs::path shared_file(const std::string& relative) {
  fs::path d = shared_data();
  if (d.empty()) return {};
  fs::path p = d / relative;
  return fs::exists(p) ? p : fs::path();
}

fs::path temp_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string tag = info ? std::string(info->test_suite_name()) + "_" + info->name() : "t";
  // The pid keeps parallel ctest processes (and fixtures' set-up, which has no test name) apart.
  fs::path p = fs::temp_directory_path() /
               ("gridshell_test_" + tag + "_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

RunResult run_command(const std::string& command) {
  fs::path d = temp_dir("run");
  std::string cmd = command + " >" + (d / "out").string() + " 2>" + (d / "err").string() +
                    " </dev/null";
  int rc = std::system(cmd.c_str());
  RunResult r;
  r.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.out = slurp(d / "out");
  r.err = slurp(d / "err");
  return r;
}

RunResult run_gridshell(const std::string& args) {
  return run_command(std::string(GRIDSHELL_EXE) + " " + args);
}

nlohmann::json read_dxf(const fs::path& file) {
  const fs::path script = temp_dir("ezdxf") / "read.py";
  std::ofstream(script) << (
             "import ezdxf, json, sys\n"
             "doc = ezdxf.readfile(sys.argv[1])\n"
             "audit = doc.audit()\n"
             "msp = doc.modelspace()\n"
             "print(json.dumps({'units': doc.header.get('$INSUNITS'),\n"
             "  'audit_errors': len(audit.errors),\n"
             "  'polylines': [[e.dxf.layer, [list(p) for p in e.get_points('xy')], e.closed]\n"
             "                for e in msp if e.dxftype() == 'LWPOLYLINE'],\n"
             "  'texts': [[e.dxf.layer, e.dxf.text, e.dxf.height] for e in msp\n"
             "            if e.dxftype() == 'TEXT']}))\n");
  const auto r = run_command("/usr/bin/python3 " + script.string() + " " + file.string());
  if (r.status != 0) return nlohmann::json();
  return nlohmann::json::parse(r.out);
}

}  // namespace gridshell::test
