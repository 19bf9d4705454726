// Bad input through the real executable: every case must end with exit status 2 and one line
// "gridshell: error: ..." on stderr — never a crash, a hang or a huge allocation.

#include <fstream>

#include <gtest/gtest.h>

#include "test_support.h"

using namespace gridshell;
namespace fs = std::filesystem;

namespace {

struct Case {
  const char* name;
  const char* file;  ///< file name (extension matters)
  std::string content;
  const char* expect;  ///< a fragment the message must contain
};

void expect_clean_error(const std::string& args, const std::string& fragment) {
  test::RunResult r = test::run_gridshell(args);
  EXPECT_EQ(r.status, 2) << args << "\nstderr: " << r.err;
  EXPECT_EQ(r.err.rfind("gridshell: error: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line expected: " << r.err;
  EXPECT_NE(r.err.find(fragment), std::string::npos) << "message: " << r.err;
}

const std::string kTri = "0 0 0\n1 0 0\n0 1 0\n";

std::vector<Case> cases() {
  std::string binary_truncated =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float "
      "y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  binary_truncated += std::string(20, '\0');
  // One face whose int32 corner count is 2^31 - 1.
  std::string binary_huge_list =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float "
      "y\nproperty float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n";
  binary_huge_list += std::string(36, '\0') + "\xff\xff\xff\x7f" + std::string(12, '\0');
  return {
      {"empty", "e.ply", "", "empty"},
      {"whitespace only", "w.obj", "  \n\n", "empty"},
      {"garbage ply", "g.ply", "this is not a mesh\n\x01\x02", "not a PLY"},
      {"ply without end_header", "h.ply", "ply\nformat ascii 1.0\nelement vertex 3\n",
       "end_header"},
      {"ply absurd vertex count", "a.ply",
       "ply\nformat ascii 1.0\nelement vertex 4000000000000\nproperty float x\nproperty float "
       "y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" +
           kTri + "3 0 1 2\n",
       "too short"},
      {"ply absurd face count", "b.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 99999999999\nproperty list uchar int vertex_indices\nend_header\n" +
           kTri + "3 0 1 2\n",
       "too short"},
      {"ply truncated ascii", "t.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n" +
           kTri + "3 0 1 2\n",
       "ply"},
      {"ply truncated binary", "tb.ply", binary_truncated, "truncated"},
      {"ply bad format", "f.ply",
       "ply\nformat utf16 1.0\nelement vertex 3\nproperty float x\nend_header\n", "format"},
      {"ply index out of range", "i.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" +
           kTri + "3 0 1 7\n",
       "vertex 7"},
      {"ply nan coordinate", "n.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\nnan 0 "
       "0\n0 1 0\n3 0 1 2\n",
       "ply"},
      {"ply no faces", "nf.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n" +
           kTri,
       "no faces"},
      {"ply without z", "z.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nelement face "
       "1\nproperty list uchar int vertex_indices\nend_header\n0 0\n1 0\n0 1\n3 0 1 2\n",
       "'z'"},
      // Found by fuzz/fuzz_mesh in CGAL's PLY reader (now ours): list lengths were cast to
      // size_t unchecked; the PLY reader now checks every value as it reads it.
      {"ply negative list length", "l.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n" +
           kTri + "-1 0 1 2\n",
       "list 'vertex_indices' has length -1"},
      {"ply huge binary list length", "hl.ply", binary_huge_list, "which the file cannot hold"},
      {"ply fractional index", "fi.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" +
           kTri + "3 0 1 1.5\n",
       "refers to vertex 1.5"},
      {"ply float indices", "fl.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n" +
           kTri + "3 0 1 2\n",
       "integers expected"},
      {"ply no index list", "ni.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 1\nproperty list uchar int corners\nend_header\n" +
           kTri + "3 0 1 2\n",
       "no 'vertex_indices' list"},
      {"ply malformed value", "mv.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
       "float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 "
       "0 abc\n0 1 0\n3 0 1 2\n",
       "malformed PLY value 'abc'"},
      {"obj out of range", "o.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "error"},
      {"obj no faces", "nf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "faces"},
      {"obj inf coordinate", "inf.obj", "v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n", "error"},
      {"off absurd counts", "a.off", "OFF\n900000000000 1 0\n" + kTri + "3 0 1 2\n", "too short"},
      {"off garbage", "g.off", "OFF\nhello world\n", "counts"},
      {"off index out of range", "i.off", "OFF\n3 1 0\n" + kTri + "3 0 1 5\n", "vertex '5'"},
      // Found by fuzz/fuzz_mesh: CGAL's OFF scanner cast such indices from double (UB).
      {"off huge index", "h.off", "OFF\n3 1 0\n" + kTri + "3 0 1 88888888888888888888880\n",
       "refers to vertex '88888888888888888888880'"},
      {"off negative index", "n.off", "OFF\n3 1 0\n" + kTri + "3 0 -1 2\n", "vertex '-1'"},
      {"off huge corner count", "c.off", "OFF\n3 1 0\n" + kTri + "999999999 0 1 2\n",
       "number of corners"},
      {"off nan coordinate", "nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n",
       "NaN"},
      {"off missing coordinate", "m.off", "OFF\n3 1 0\n0 0 0\n1.5 0.5\n0 1 0\n3 0 1 2\n",
       "three coordinates"},
      {"off truncated", "t.off", "OFF\n3 2 0\n" + kTri + "3 0 1 2\n", "truncated"},
      {"off binary", "b.off", "OFF BINARY\n" + std::string(12, '\0'), "binary OFF"},
  };
}

}  // namespace

TEST(MalformedInput, EveryBadFileGivesExitTwoAndOneLine) {
  fs::path d = test::temp_dir("bad");
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    fs::path p = d / c.file;
    std::ofstream(p, std::ios::binary) << c.content;
    expect_clean_error("info " + p.string(), c.expect);
  }
}

TEST(MalformedInput, MissingFileAndDirectory) {
  expect_clean_error("info /nonexistent/surface.ply", "no such file");
  expect_clean_error("info " + fs::temp_directory_path().string(), "directory");
}

TEST(MalformedInput, BadOptions) {
  expect_clean_error("info builtin:nosuchthing", "unknown built-in");
  expect_clean_error("info builtin:dome:span=-3", "positive");
  expect_clean_error("info builtin:dome:colour=3", "unknown key");
  expect_clean_error("info builtin:dome --up q", "--up");
  expect_clean_error("info builtin:dome --scale 0", "--scale");
  expect_clean_error("info builtin:dome --supports red", "red");
  expect_clean_error("info builtin:dome --supports /nonexistent.json", "no such file");
  expect_clean_error("frobnicate", "");
  expect_clean_error("info", "surface");
}

// Built-in parameters out of their bounds (surfaces/builtin.h): each refused before anything is
// allocated, never a crash (length=85899346 once wrapped the grid size in int and wrote past
// the mesh).
TEST(MalformedInput, BuiltinParameterBounds) {
  expect_clean_error("info builtin:barrel:length=85899346", "length must be");
  expect_clean_error("info builtin:barrel:span=0.1,rise=0.05,length=1000,res=100", "vertices");
  expect_clean_error("info builtin:court:span=0.1,width=1000,hole=0.01", "vertices");
  // The cap is a 1001 × 1001 grid: res=1000 is the largest paraboloid and funicular (accepted in
  // surfaces_test), the next even res is refused, and dome's rings 1 + 3n(n + 1) pass it at
  // n = res / 2 = 578.
  expect_clean_error("info builtin:paraboloid:res=1002", "1002001");
  expect_clean_error("info builtin:funicular:res=1002", "1006009 vertices");
  expect_clean_error("info builtin:dome:res=1156", "vertices");
  expect_clean_error("info builtin:funicular:res=2002", "res must be");
  expect_clean_error("info builtin:dome:res=32.0", "whole number");
  expect_clean_error("info builtin:dome:res=1e3", "whole number");
  expect_clean_error("info builtin:dome:res=99999999999999999999", "whole number");
  expect_clean_error("info builtin:dome:res=-4", "whole number");
  expect_clean_error("info builtin:dome:span=nan", "not a number");
  expect_clean_error("info builtin:dome:span=inf", "not a number");
  expect_clean_error("info builtin:dome:span=0x10", "not a number");
  expect_clean_error("info builtin:dome:span=1e400", "not a number");
  expect_clean_error("info builtin:dome:span=1e-300", "span must be");
  expect_clean_error("info builtin:dome:span=", "not a number");
  expect_clean_error("info builtin:court:hole=1e9", "hole must be");
  expect_clean_error("info builtin:funicular:edge_q=1e9", "edge_q must be");
  expect_clean_error("info builtin:funicular:corner=2001", "corner must be");
  expect_clean_error("info builtin:barrel:rise=1e6", "rise must be");
  // At the bounds: a barrel 1000 times as long as its span (6 003 vertices) is a valid surface.
  test::RunResult r = test::run_gridshell("info builtin:barrel:span=1,rise=0.5,length=1000,res=2");
  EXPECT_EQ(r.status, 0) << r.err;
}

// Refused while reading, so memory stays proportional to the file: a binary PLY of a million
// empty faces (one byte each), and JSON nested a million deep (each `[` one byte).
TEST(MalformedInput, ImpossibleFacesAndDeepJsonAreRefusedWhileReading) {
  const fs::path d = test::temp_dir("deep");
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float "
      "y\nproperty float z\nelement face 1000000\nproperty list uchar int vertex_indices\n"
      "end_header\n";
  ply += std::string(36, '\0') + std::string(1000000, '\0');
  std::ofstream(d / "empty_faces.ply", std::ios::binary) << ply;
  expect_clean_error("info " + (d / "empty_faces.ply").string(), "face 0 has 0 vertices");
  std::ofstream(d / "empty_faces.off") << "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n0\n#" +
                                             std::string(40, ' ') + "\n";
  expect_clean_error("info " + (d / "empty_faces.off").string(), "face 1 has 0 vertices");
  std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  for (int k = 0; k < 100000; ++k) obj += "f\n";
  std::ofstream(d / "empty_faces.obj") << obj;
  expect_clean_error("info " + (d / "empty_faces.obj").string(), "line 5: face has 0 vertices");
  std::ofstream(d / "short_face.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\n  f 1 2 # 3\n";
  expect_clean_error("info " + (d / "short_face.obj").string(), "line 4: face has 2 vertices");
  const std::string deep = std::string(1000000, '[') + std::string(1000000, ']');
  std::ofstream(d / "deep.json") << deep;
  expect_clean_error("info builtin:dome --supports " + (d / "deep.json").string(),
                     "nested deeper than 64");
  expect_clean_error("design --config " + (d / "deep.json").string() + " -o " +
                         (d / "out").string(),
                     "nested deeper than 64");
  std::ofstream(d / "MODEL.json") << "{\"nodes\": " + deep + "}";
  expect_clean_error("analyze " + (d / "MODEL.json").string() + " -o " + (d / "out2").string(),
                     "nested deeper than 64");
  // 64 levels are fine as JSON (and then not a supports list).
  std::ofstream(d / "ok.json") << std::string(64, '[') + std::string(64, ']');
  expect_clean_error("info builtin:dome --supports " + (d / "ok.json").string(), "integers");
}

TEST(MalformedInput, BadSupportFiles) {
  fs::path d = test::temp_dir("badsup");
  std::ofstream(d / "range.json") << "[0, 1, 100000]";
  std::ofstream(d / "notjson.json") << "{oops";
  std::ofstream(d / "kind.json") << "[\"a\"]";
  expect_clean_error("info builtin:dome --supports " + (d / "range.json").string(), "out of range");
  expect_clean_error("info builtin:dome --supports " + (d / "notjson.json").string(), "JSON");
  expect_clean_error("info builtin:dome --supports " + (d / "kind.json").string(), "integers");
}

TEST(MalformedInput, BadModelFiles) {
  fs::path d = test::temp_dir("badmodel");
  const std::string nodes = R"("nodes": [[0, 0, 0], [1, 0, 0], [0, 1, 0]])";
  // A nodal load without its node: the shell reader read a missing key (undefined behaviour).
  std::ofstream(d / "load.json") << "{" << nodes
                                 << R"(, "triangles": [[0, 1, 2]], "loads": [{"type": "node"}]})";
  expect_clean_error("stress " + (d / "load.json").string() + " -o " + (d / "o1").string(),
                     "loads[0]: a nodal load needs 'node'");
  // Ids beyond int or int64 are refused, not wrapped round into a valid-looking node 0.
  const std::string frame = "{" + nodes +
                            R"(, "sections": {"s": {"shape": "circle", "diameter": 0.05}},
                                "materials": {"m": {"E": 2e11}}, "members": [{"nodes": [0, )";
  std::ofstream(d / "wrap.json") << frame << "4294967296]}]}";
  expect_clean_error("analyze " + (d / "wrap.json").string() + " -o " + (d / "o2").string(),
                     "members[0].nodes 4294967296 is out of range");
  std::ofstream(d / "wrap_shell.json") << "{" << nodes
                                       << R"(, "triangles": [[0, 1, 18446744073709551616]]})";
  expect_clean_error("stress " + (d / "wrap_shell.json").string() + " -o " + (d / "o3").string(),
                     "error");
  std::ofstream(d / "wrap_shell2.json") << "{" << nodes
                                        << R"(, "triangles": [[0, 1, 18446744073709551615]]})";
  expect_clean_error("stress " + (d / "wrap_shell2.json").string() + " -o " + (d / "o4").string(),
                     "refers to node 18446744073709551615, but there are 3 nodes");
  EXPECT_FALSE(fs::exists(d / "o1" / "report.json"));
}
