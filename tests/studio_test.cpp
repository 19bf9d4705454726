// gridshell studio (src/gridshell/studio/): the request parser against the command line's
// messages, the zip writer against unzip, the server's API against a `design` run with the same
// parameters and seed, bad input (HTTP 400, the server lives on), superseded requests, and the
// page in headless Chromium (a slider moved by the page's script redraws the mesh).

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/studio/request.h"
#include "gridshell/studio/server.h"
#include "gridshell/studio/zip.h"
#include "png_support.h"
#include "studio_support.h"
#include "test_support.h"

using gridshell::test::find_chromium;
using gridshell::test::Image;
using gridshell::test::read_png;
using gridshell::test::slurp;

#include <httplib.h>  // last: its <resolv.h> defines `_res`, which breaks Eigen headers after it

namespace fs = std::filesystem;
using gridshell::test::run_gridshell;
using gridshell::test::temp_dir;

namespace {

/// The message parse_request throws, as the CLI prints it.
std::string request_error(const gridshell::studio::Params& params) {
  try {
    (void)gridshell::studio::parse_request(params);
  } catch (const gridshell::Error& e) {
    return "gridshell: error: " + e.message() + "\n";
  }
  return "";
}

/// One server for the tests of this file, on a free port.
class StudioServerTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    gridshell::studio::ServerOptions options;
    options.port = 0;
    server_ = new gridshell::studio::Server(options);
    port_ = server_->start();
  }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static httplib::Client client() {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(300, 0);
    c.set_default_headers({{"X-Gridshell-Token", server_->token()}});
    return c;
  }
  static gridshell::studio::Server* server_;
  static int port_;
};
gridshell::studio::Server* StudioServerTest::server_ = nullptr;
int StudioServerTest::port_ = 0;

}  // namespace

// ---------------------------------------------------------------------------------------------
// Requests and zip

TEST(StudioRequest, BadParametersGiveTheCommandLinesMessage) {
  // The same line `gridshell design` prints for the same mistake.
  const auto d0 = run_gridshell("design -D 0 --quiet -o " + temp_dir("d0").string());
  EXPECT_EQ(d0.status, 2);
  EXPECT_EQ(request_error({{"D", "0"}}), d0.err);
  const auto sym = run_gridshell("design --symmetry z --quiet -o " + temp_dir("sym").string());
  EXPECT_EQ(request_error({{"symmetry", "z"}}), sym.err);
  const auto obj = run_gridshell("design --objective best --quiet -o " + temp_dir("obj").string());
  EXPECT_EQ(request_error({{"objective", "best"}}), obj.err);
  EXPECT_EQ(request_error({{"A", "x"}}), "gridshell: error: -A: must be a number ≥ 1\n");
  EXPECT_EQ(request_error({{"cells", "0"}}), "gridshell: error: --cells: must be positive\n");
  EXPECT_EQ(request_error({{"cells", "100"}, {"length", "50"}}),
            "gridshell: error: --radius/--cells/--length: give at most one of them\n");
  EXPECT_NE(request_error({{"speed", "1"}}).find("speed: unknown parameter"), std::string::npos);
  // A good one, and its canonical query.
  const auto r = gridshell::studio::parse_request(
      {{"surface", "builtin:dome"}, {"D", "2.5"}, {"A", "1"}, {"cells", "150"}, {"seed", "7"}});
  EXPECT_EQ(r.D, 2.5);
  EXPECT_EQ(r.cells, 150);
  EXPECT_EQ(r.seed, 7u);
  EXPECT_EQ(gridshell::studio::request_query(r),
            "surface=builtin:dome&D=2.5&A=1&cells=150&symmetry=none&analyze=buckling&seed=7");
}

TEST(StudioRequest, OptionsComeFromTheCommandLinesBuilderAndTheConfigSaysWhatDiffers) {
  // The studio's options are build_design_options' (pipeline/design_settings.h) for the
  // request's settings; the one thing the studio does differently from `design`'s defaults (the
  // perfect non-linear path only) is written into its config.json.
  using gridshell::studio::parse_request;
  const auto r = parse_request({{"D", "2.5"}, {"A", "1.5"}, {"cells", "90"}, {"seed", "4"},
                                {"analyze", "nonlinear"}});
  const gridshell::DesignOptions o = gridshell::studio::design_options(r);
  EXPECT_EQ(o.field_options.D, 2.5);
  EXPECT_EQ(o.field_options.A, 1.5);
  EXPECT_EQ(o.tessellation.cells, 90);
  EXPECT_EQ(o.tessellation.seed, 4u);
  EXPECT_EQ(o.finish, gridshell::Finish::regularize);
  EXPECT_FALSE(o.frame_analysis.stability);
  const nlohmann::json config = gridshell::studio::request_config(r, "builtin:funicular");
  EXPECT_EQ(config["options"]["single-path"], true);
  const nlohmann::json buckling =
      gridshell::studio::request_config(parse_request({{"analyze", "buckling"}}), "x");
  EXPECT_FALSE(buckling["options"].contains("single-path"));
}

TEST(StudioZip, CrcAndArchiveCheckWithUnzip) {
  EXPECT_EQ(gridshell::studio::crc32("123456789"), 0xCBF43926u);  // the CRC-32 check value
  EXPECT_EQ(gridshell::studio::crc32(""), 0u);
  std::string binary;
  for (int i = 0; i < 70000; ++i) binary.push_back(static_cast<char>((i * 7919) & 0xff));
  const fs::path dir = temp_dir("zip");
  const std::string zip =
      gridshell::studio::zip_stored({{"a.txt", "hello\n"}, {"sub/b.bin", binary}, {"empty", ""}});
  gridshell::io::write_file_atomic(dir / "x.zip", zip);
  if (std::system("command -v unzip >/dev/null 2>&1") != 0)
    SKIP_OR_FAIL_IN_CI("no unzip: it checks the archive");
  EXPECT_EQ(std::system(("unzip -tq " + (dir / "x.zip").string() + " >/dev/null").c_str()), 0);
  ASSERT_EQ(std::system(("cd " + dir.string() + " && unzip -q x.zip -d out").c_str()), 0);
  EXPECT_EQ(slurp(dir / "out" / "a.txt"), "hello\n");
  EXPECT_EQ(slurp(dir / "out" / "sub" / "b.bin"), binary);
  EXPECT_TRUE(fs::exists(dir / "out" / "empty"));
  EXPECT_EQ(fs::file_size(dir / "out" / "empty"), 0u);
}

// ---------------------------------------------------------------------------------------------
// The API

TEST_F(StudioServerTest, DesignAnswerMatchesTheCommandLine) {
  auto c = client();
  const auto res = c.Get("/api/design?surface=builtin:funicular&D=2&A=2&cells=120&seed=3");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200) << res->body;
  const nlohmann::json j = nlohmann::json::parse(res->body);
  const auto& mesh = j["mesh"];
  const std::size_t nv = mesh["vertices"].size(), nf = mesh["faces"].size();
  EXPECT_EQ(j["beams"].size(), j["axial_force"].size());
  EXPECT_GT(j["beams"].size(), nv);  // a grid-shell: more beams than joints
  EXPECT_FALSE(mesh["supports"].empty());
  EXPECT_EQ(j["view"]["joints"].size(), 3 * nv);
  for (const char* key : {"lambda_linear_buckling", "delta_max_m"})
    EXPECT_TRUE(j["report"]["structure"][key].is_number()) << key;
  // Equilibrium: the vertical reactions carry the structure's weight, so the beams meeting at
  // supports are mostly in compression on this funicular shell.
  double sum = 0;
  for (const auto& n : j["axial_force"]) sum += n.get<double>();
  EXPECT_LT(sum, 0);

  // The same design from the command line, and from the page's config.json.
  const fs::path dir = temp_dir("cli");
  const auto cli = run_gridshell(
      "design builtin:funicular -D 2 -A 2 --cells 120 --seed 3 --analyze buckling --figures none "
      "--quiet -o " +
      dir.string());
  ASSERT_EQ(cli.status, 0) << cli.err;
  const auto obj = gridshell::io::read_mesh(dir / "gridshell.obj").mesh;
  EXPECT_EQ(static_cast<std::size_t>(obj.num_vertices()), nv);
  EXPECT_EQ(obj.faces.size(), nf);
  const nlohmann::json report = nlohmann::json::parse(slurp(dir / "report.json"));
  EXPECT_NEAR(report["structure"]["lambda_linear_buckling"].get<double>(),
              j["report"]["structure"]["lambda_linear_buckling"].get<double>(), 1e-9);
  EXPECT_NEAR(report["mesh"]["total_length_m"].get<double>(),
              j["report"]["mesh"]["total_length_m"].get<double>(), 1e-9);
  for (std::size_t v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k)
      ASSERT_NEAR(obj.V(static_cast<Eigen::Index>(v), k), mesh["vertices"][v][k].get<double>(),
                  1e-5);
}

TEST_F(StudioServerTest, DesignsOfOneSurfaceShareTheirStressAndFieldAndAreUnchangedByIt) {
  // The server keeps the stress, field and M′ of a surface's designs (server.h "Memory"): a
  // request at another seed, or back at an earlier (D, A), takes them from there. Its answer is
  // the design computed from scratch (design_request without a cache), bit for bit.
  using gridshell::studio::parse_request;
  auto c = client();
  const std::string base = "/api/design?surface=builtin:funicular&cells=90&";
  for (const char* q : {"D=2&A=2&seed=5", "D=1.5&A=2&seed=5", "D=2&A=2&seed=6"}) {
    const auto res = c.Get(base + q);
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200) << res->body;
  }
  const auto cached = c.Get(base + "D=1.5&A=2&seed=6");
  ASSERT_TRUE(cached);
  ASSERT_EQ(cached->status, 200) << cached->body;
  const auto request = parse_request(
      {{"surface", "builtin:funicular"}, {"cells", "90"}, {"D", "1.5"}, {"A", "2"}, {"seed", "6"}});
  const gridshell::Surface surface = gridshell::load_surface("builtin:funicular");
  const nlohmann::json fresh = gridshell::studio::design_answer(
      gridshell::studio::design_request(surface, request), "builtin:funicular");
  nlohmann::json answer = nlohmann::json::parse(cached->body);
  ASSERT_EQ(answer["request"], fresh["request"]);
  for (const char* key : {"mesh", "beams", "axial_force", "config"})
    EXPECT_EQ(answer[key].dump(), fresh[key].dump()) << key;
  nlohmann::json report = answer["report"], fresh_report = fresh["report"];
  report.erase("timings_s"), fresh_report.erase("timings_s");
  report["structure"].erase("timings_s"), fresh_report["structure"].erase("timings_s");
  EXPECT_EQ(report.dump(), fresh_report.dump());
  EXPECT_GT(report["structure"]["lambda_linear_buckling"].get<double>(), 0);
}

TEST_F(StudioServerTest, ConfigRepeatsTheDesignAndExportHasTheDesignFiles) {
  auto c = client();
  const std::string q = "surface=builtin:dome&D=1.5&A=1&cells=80&seed=2";
  const auto config = c.Get("/api/config.json?" + q);
  ASSERT_TRUE(config);
  ASSERT_EQ(config->status, 200) << config->body;
  const auto zip = c.Get("/api/export.zip?" + q);
  ASSERT_TRUE(zip);
  ASSERT_EQ(zip->status, 200) << zip->body;
  const fs::path dir = temp_dir("export");
  gridshell::io::write_file_atomic(dir / "config.json", config->body);
  gridshell::io::write_file_atomic(dir / "design.zip", zip->body);
  if (std::system("command -v unzip >/dev/null 2>&1") != 0)
    SKIP_OR_FAIL_IN_CI("no unzip: it checks the archive");
  ASSERT_EQ(std::system(("unzip -tq " + (dir / "design.zip").string() + " >/dev/null").c_str()), 0);
  ASSERT_EQ(std::system(("cd " + dir.string() + " && unzip -q design.zip -d zip").c_str()), 0);
  // What `design -o` writes.
  for (const char* f : {"gridshell.obj", "gridshell_raw.obj", "gridshell.ply", "gridshell.vtp",
                        "field.vtp", "cells.csv", "joints.csv", "beams.csv", "panels.csv",
                        "panels.svg", "panels.dxf", "beams.dxf", "gridshell.glb", "report.json",
                        "config.json", "report.html"})
    EXPECT_TRUE(fs::exists(dir / "zip" / f)) << f;
  EXPECT_FALSE(fs::is_empty(dir / "zip" / "figures"));
  // `gridshell design --config` gives the same grid-shell, byte for byte.
  const auto run = run_gridshell("design --config " + (dir / "config.json").string() +
                                 " --figures none --quiet -o " + (dir / "cli").string());
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(slurp(dir / "cli" / "gridshell.obj"), slurp(dir / "zip" / "gridshell.obj"));
  EXPECT_EQ(slurp(dir / "cli" / "beams.csv"), slurp(dir / "zip" / "beams.csv"));
  EXPECT_EQ(slurp(dir / "cli" / "gridshell.glb"), slurp(dir / "zip" / "gridshell.glb"));
  // One writer for both (report/design_folder.h): the export has design's analysis files too,
  // the buckling modes and the frame, and report.json's load combinations and steel.
  for (const char* f : {"modes.csv", "frame.json"}) {
    ASSERT_TRUE(fs::exists(dir / "zip" / f)) << f;
    EXPECT_EQ(slurp(dir / "cli" / f), slurp(dir / "zip" / f)) << f;
  }
  const nlohmann::json cli = nlohmann::json::parse(slurp(dir / "cli" / "report.json"));
  const nlohmann::json zipped = nlohmann::json::parse(slurp(dir / "zip" / "report.json"));
  ASSERT_TRUE(zipped["structure"].contains("combinations"));
  EXPECT_EQ(zipped["structure"]["combinations"], cli["structure"]["combinations"]);
  EXPECT_EQ(zipped["structure"]["governing"], cli["structure"]["governing"]);
  for (const char* key : {"steel", "loads"})
    EXPECT_EQ(zipped["structure"][key], cli["structure"][key]) << key;
  EXPECT_EQ(zipped["mass"], cli["mass"]);
  EXPECT_EQ(zipped["fabrication"], cli["fabrication"]);
}

TEST_F(StudioServerTest, BadInputGets400AndTheServerLivesOn) {
  auto c = client();
  const auto unknown = c.Get("/api/design?surface=builtin:nope&cells=100");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 400);
  const auto cli = run_gridshell("design builtin:nope --quiet -o " + temp_dir("nope").string());
  EXPECT_EQ(unknown->body, cli.err);
  const auto path = c.Get("/api/design?surface=/etc/passwd");
  ASSERT_TRUE(path);
  EXPECT_EQ(path->status, 400);  // no file on the server's disk is read on request
  const auto d0 = c.Get("/api/design?D=0");
  ASSERT_TRUE(d0);
  EXPECT_EQ(d0->status, 400);
  EXPECT_EQ(d0->body, "gridshell: error: -D: must be a number ≥ 1\n");

  // A malformed upload: the CLI's message, with the file's own name.
  const fs::path bad = temp_dir("upload") / "broken.ply";
  gridshell::io::write_file_atomic(bad,
                                   "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n");
  const auto cli_bad =
      run_gridshell("design " + bad.string() + " --quiet -o " + temp_dir("bad").string());
  EXPECT_EQ(cli_bad.status, 2);
  const auto up = c.Post("/api/surface?name=broken.ply", slurp(bad), "application/octet-stream");
  ASSERT_TRUE(up);
  EXPECT_EQ(up->status, 400);
  std::string expected = cli_bad.err;
  for (std::size_t at; (at = expected.find(bad.string())) != std::string::npos;)
    expected.replace(at, bad.string().size(), "broken.ply");
  EXPECT_EQ(up->body, expected);
  const auto garbage = c.Post("/api/surface?name=x.off", std::string("\0\1\2", 3), "x/y");
  ASSERT_TRUE(garbage);
  EXPECT_EQ(garbage->status, 400);
  EXPECT_EQ(garbage->body.rfind("gridshell: error: ", 0), 0u);

  // A good upload designs like a built-in.
  const fs::path good = temp_dir("good");
  ASSERT_EQ(run_gridshell("design builtin:barrel -D 1 -A 1 --cells 60 --analyze none --figures "
                          "none --quiet -o " +
                          good.string())
                .status,
            0);
  const auto ok = c.Post("/api/surface?name=roof.obj", slurp(good / "gridshell.obj"), "x/y");
  ASSERT_TRUE(ok);
  ASSERT_EQ(ok->status, 200) << ok->body;
  const std::string id = nlohmann::json::parse(ok->body)["surface"];
  const auto designed = c.Get("/api/design?surface=" + id + "&D=1&A=1&cells=60&analyze=linear");
  ASSERT_TRUE(designed);
  ASSERT_EQ(designed->status, 200) << designed->body;
  EXPECT_EQ(nlohmann::json::parse(designed->body)["config"]["positional"][0], "roof.obj");

  const auto page = c.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("gridshell studio"), std::string::npos);
}

TEST_F(StudioServerTest, FlatPanelsOfAnUploadedRoofGlazeTheirFailingPanelsAsTriangles) {
  // Aquadom at D = A = 2: every plane optimisation of its flat stage fails, and the last resort
  // glazes a failing panel as triangles (docs/panels.md). The studio answers with the flat
  // design, its per-panel view (one value per panel, the triangles included) and the count.
  SKIP_WITHOUT_SHARED_DATA();
  auto c = client();
  const auto up = c.Post("/api/surface?name=aquadom_Vouga.ply",
                         slurp(gridshell::test::shared_file("surfaces/aquadom_Vouga.ply")), "x/y");
  ASSERT_TRUE(up);
  ASSERT_EQ(up->status, 200) << up->body;
  const std::string id = nlohmann::json::parse(up->body)["surface"];
  const auto res =
      c.Get("/api/design?surface=" + id + "&D=2&A=2&cells=300&seed=1&panels=flat&analyze=linear");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200) << res->body;
  const nlohmann::json j = nlohmann::json::parse(res->body);
  const auto& report = j["report"];
  EXPECT_EQ(report["mesh"]["panels"], "flat");
  const int glazed = report["design"]["flat_panels"]["triangulated_panels"].get<int>();
  EXPECT_GE(glazed, 1);
  EXPECT_LE(glazed, 30);
  EXPECT_GT(j["mesh"]["faces"].size(), 300u);  // the triangles follow the 300 panels
  EXPECT_LE(report["mesh"]["out_of_plane_max_m"].get<double>(), 5e-4);
  EXPECT_EQ(report["mesh"]["self_intersecting_panels"].get<int>(), 0);
}

namespace {

/// A server of its own whose design requests stop at the gate's pause points.
class StudioPauseTest : public ::testing::Test {
 protected:
  void SetUp() override {
    gridshell::studio::ServerOptions options;
    options.port = 0;
    options.pause_hook = gate_.hook();
    server_ = std::make_unique<gridshell::studio::Server>(options);
    port_ = server_->start();
  }
  void TearDown() override {
    gate_.release();  // never leave a request waiting at the gate
    server_.reset();
  }
  httplib::Client client() const {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(600, 0);
    c.set_default_headers({{"X-Gridshell-Token", server_->token()}});
    return c;
  }
  /// GET `q` on a thread of its own; its status lands in `status` (-1: no answer).
  std::thread get(const std::string& q, int& status) const {
    return std::thread([this, q, &status] {
      auto c = client();
      const auto r = c.Get(q);
      status = r ? r->status : -1;
    });
  }
  /// A request `slow` held at the gate's `pause_at`-th check, a quick linear design sent while it
  /// waits, then the gate released: both statuses, and whether the gate saw each in time.
  struct Superseded {
    int slow = 0, quick = 0;
    bool paused = false, queued = false;
  };
  Superseded supersede(int pause_at, const std::string& slow) {
    Superseded s;
    gate_.pause_at(pause_at);
    std::thread a = get(slow, s.slow);
    s.paused = gate_.wait_paused();
    std::thread b =
        get("/api/design?surface=builtin:dome&D=1&A=1&cells=60&analyze=linear", s.quick);
    s.queued = s.paused && gate_.wait_queued(2);
    gate_.release();
    a.join();
    b.join();
    return s;
  }
  gridshell::test::StudioGate gate_;
  std::unique_ptr<gridshell::studio::Server> server_;
  int port_ = 0;
};

}  // namespace

TEST_F(StudioPauseTest, RapidRequestsAreSupersededAndTheLastOneAnswers) {
  // The first request is held after it took its number, until five more have taken theirs
  // (the server's thread pool has at least eight threads): then only the newest is designed.
  gate_.pause_at(1, /*at_queued=*/true);
  std::vector<int> status(6, 0);
  std::vector<std::thread> threads;
  threads.push_back(get("/api/design?D=2&A=2&cells=100", status[0]));
  ASSERT_TRUE(gate_.wait_paused());
  for (int k = 1; k < 6; ++k)
    threads.push_back(get("/api/design?D=2&A=2&cells=" + std::to_string(100 + 10 * k), status[k]));
  ASSERT_TRUE(gate_.wait_queued(6));
  gate_.release();
  for (auto& t : threads) t.join();
  EXPECT_EQ(std::count(status.begin(), status.end(), 409), 5);
  EXPECT_EQ(std::count(status.begin(), status.end(), 200), 1);
  // The server still answers, and with what was asked last.
  auto c = client();
  const auto last = c.Get("/api/design?D=1.5&A=2&cells=170");
  ASSERT_TRUE(last);
  ASSERT_EQ(last->status, 200) << last->body;
  const nlohmann::json j = nlohmann::json::parse(last->body);
  EXPECT_EQ(j["request"],
            "surface=builtin:funicular&D=1.5&A=2&cells=170&symmetry=none&analyze=buckling&seed=1");
  EXPECT_EQ(j["mesh"]["faces"].size(), 170u);
}

TEST_F(StudioPauseTest, ANewerRequestStopsANonlinearAnalysisAtItsNextStep) {
  // Held at its third arc-length step; a quick request comes in; released, the path stops at
  // once: no step after the third asks again.
  const Superseded s =
      supersede(3, "/api/design?surface=builtin:dome&D=1&A=1&cells=100&analyze=nonlinear&seed=6");
  ASSERT_TRUE(s.paused && s.queued);
  EXPECT_EQ(s.slow, 409);
  EXPECT_EQ(s.quick, 200);
  EXPECT_EQ(gate_.checks(), 3);
}

TEST_F(StudioPauseTest, ANewerRequestStopsAnObjectiveSearchBeforeItsNextCandidate) {
  // Held where the search asks after its reference design; released after a newer request, it
  // designs no candidate of its first round (each would ask first).
  const Superseded s = supersede(1, "/api/design?surface=builtin:dome&cells=100&objective=lambda");
  ASSERT_TRUE(s.paused && s.queued);
  EXPECT_EQ(s.slow, 409);
  EXPECT_EQ(s.quick, 200);
  EXPECT_EQ(gate_.checks(), 1);
}

TEST_F(StudioPauseTest, ABadRequestDoesNotStopTheRunningDesign) {
  gate_.pause_at(2);
  int slow = 0;
  std::thread a =
      get("/api/design?surface=builtin:dome&D=1&A=1&cells=80&analyze=nonlinear&seed=2", slow);
  ASSERT_TRUE(gate_.wait_paused());
  auto c = client();
  for (const char* bad : {"/api/design?D=0", "/api/design?surface=builtin:nope",
                          "/api/design?surface=builtin:barrel:length%3D85899346",
                          "/api/design?cells=100&length=5", "/api/design?surface=upload:9"}) {
    const auto r = c.Get(bad);
    ASSERT_TRUE(r) << bad;
    EXPECT_EQ(r->status, 400) << bad;
  }
  // Busy: an export while the design runs.
  const auto busy = c.Get("/api/export.zip?surface=builtin:dome&cells=60");
  ASSERT_TRUE(busy);
  EXPECT_EQ(busy->status, 503);
  EXPECT_EQ(gate_.queued(), 1);  // none of them took a number
  gate_.release();
  a.join();
  EXPECT_EQ(slow, 200);
}

// ---------------------------------------------------------------------------------------------
// The page in headless Chromium

namespace {

/// Headless Chromium with WebGL on SwiftShader and no network but 127.0.0.1: a screenshot of
/// `url` (when `png` is set) and the DOM after the scripts ran.
std::string chromium(const std::string& exe, const std::string& url, const fs::path& work,
                     const fs::path& png = {}) {
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --use-angle=swiftshader --enable-unsafe-swiftshader"
      " --hide-scrollbars --window-size=1200,800 --virtual-time-budget=20000"
      " --host-resolver-rules=\"MAP * ~NOTFOUND, EXCLUDE 127.0.0.1\" --user-data-dir=" +
      (work / "profile").string();
  if (!png.empty()) {
    const std::string cmd = "timeout 180 " + exe + flags + " --screenshot=" + png.string() + " '" +
                            url + "' >/dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  const std::string cmd = "timeout 180 " + exe + flags + " --dump-dom '" + url + "' >" +
                          (work / "dom.html").string() + " 2>/dev/null";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return slurp(work / "dom.html");
}

/// Share of the 3D view's pixels (left of the 330 px side panel) that are not the background.
double drawn_share(const Image& im) {
  int drawn = 0, all = 0;
  for (int y = 60; y < im.height - 60; ++y)
    for (int x = 0; x < im.width - 340; ++x) {
      const unsigned char* p = &im.rgb[3 * (y * im.width + x)];
      ++all;
      if (std::abs(p[0] - 0xf6) + std::abs(p[1] - 0xf6) + std::abs(p[2] - 0xf3) > 30) ++drawn;
    }
  return all ? static_cast<double>(drawn) / all : 0;
}

double differing_share(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height || a.rgb.empty()) return 0;
  int differ = 0;
  for (std::size_t i = 0; i < a.rgb.size(); i += 3)
    if (std::abs(a.rgb[i] - b.rgb[i]) + std::abs(a.rgb[i + 1] - b.rgb[i + 1]) +
            std::abs(a.rgb[i + 2] - b.rgb[i + 2]) >
        30)
      ++differ;
  return static_cast<double>(differ) / (a.rgb.size() / 3);
}

std::string attribute(const std::string& dom, const std::string& name) {
  std::smatch m;
  if (std::regex_search(dom, m, std::regex(name + "=\"([^\"]*)\""))) return m[1];
  return "<none>";
}

}  // namespace

TEST_F(StudioServerTest, PageRedrawsWhenASliderMovesInChromium) {
  const std::string exe = find_chromium();
  if (exe.empty()) SKIP_OR_FAIL_IN_CI("no chromium: headless Chromium is the studio's browser");
  const std::string base = "http://127.0.0.1:" + std::to_string(port_) + "/";
  const fs::path work = temp_dir("chromium");

  // The first design, then the cells slider moved by the page (an input event, as a user's).
  const std::string dom1 = chromium(exe, base + "#cells=120&A=1", work, work / "a.png");
  const Image a = read_png(work / "a.png");
  EXPECT_EQ(attribute(dom1, "data-errors"), "");
  EXPECT_EQ(attribute(dom1, "data-ready"), "1");
  EXPECT_EQ(attribute(dom1, "data-draws"), "1");
  EXPECT_NE(attribute(dom1, "data-request").find("cells=120"), std::string::npos);

  const std::string dom2 =
      chromium(exe, base + "#cells=120&A=1&then=cells:400", work, work / "b.png");
  const Image b = read_png(work / "b.png");
  EXPECT_EQ(attribute(dom2, "data-errors"), "");
  EXPECT_EQ(attribute(dom2, "data-draws"), "2");
  EXPECT_NE(attribute(dom2, "data-request").find("cells=400"), std::string::npos);
  ASSERT_GT(a.width, 0);
  ASSERT_GT(b.width, 0);
  const double drawn_a = drawn_share(a), drawn_b = drawn_share(b);
  EXPECT_GT(drawn_a, 0.05) << "first view nearly blank";
  EXPECT_GT(drawn_b, 0.05) << "second view nearly blank";
  EXPECT_GT(differing_share(a, b), 0.01) << "the mesh was not redrawn";
  RecordProperty("drawn_a", std::to_string(drawn_a));
  RecordProperty("drawn_b", std::to_string(drawn_b));

  // Twenty quick slider moves, then a last one: the page shows the last.
  const std::string dom3 = chromium(exe, base + "#cells=120&burst=20&then=cells:250", work);
  EXPECT_EQ(attribute(dom3, "data-errors"), "");
  EXPECT_EQ(attribute(dom3, "data-status"), "ready");
  EXPECT_NE(attribute(dom3, "data-request").find("cells=250"), std::string::npos);

  // Bad input: the page shows the server's message.
  const std::string dom4 = chromium(exe, base + "#D=0", work);
  EXPECT_EQ(attribute(dom4, "data-status"), "error");
  EXPECT_NE(dom4.find("gridshell: error: -D: must be a number ≥ 1"), std::string::npos);
  const std::string dom5 = chromium(exe, base + "#surface=builtin:nope", work);
  EXPECT_NE(dom5.find("unknown built-in surface"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// The command: `gridshell studio --port 0` as a child process

TEST(StudioCli, PortZeroPrintsTheUrlAndATakenPortIsAnError) {
  const fs::path dir = temp_dir("cli");
  const fs::path log = dir / "stderr";
  // Start it in the background; the shell prints the child's pid.
  const std::string cmd = std::string(GRIDSHELL_EXE) + " studio builtin:dome --port 0 --quiet 2>" +
                          log.string() + " >/dev/null </dev/null & echo $! >" +
                          (dir / "pid").string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const int pid = std::stoi(slurp(dir / "pid"));
  // Stopped however the test ends.
  const std::shared_ptr<void> stop(nullptr, [pid](void*) { ::kill(pid, SIGTERM); });
  std::smatch m;
  std::string text;
  for (int i = 0; i < 600; ++i) {  // up to a minute
    text = slurp(log);
    if (std::regex_search(text, m, std::regex("studio: http://127\\.0\\.0\\.1:([0-9]+)/\n"))) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_FALSE(m.empty()) << text;
  const int port = std::stoi(m[1]);
  httplib::Client c("127.0.0.1", port);
  c.set_read_timeout(120, 0);
  // The token is in the page (and nowhere else): without it the API refuses.
  const auto page = c.Get("/");
  ASSERT_TRUE(page);
  std::smatch t;
  ASSERT_TRUE(std::regex_search(page->body, t,
                                std::regex("name=\"gridshell-token\" content=\"([0-9a-f]{32})\"")));
  const auto refused = c.Get("/api/surfaces");
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 403);
  c.set_default_headers({{"X-Gridshell-Token", t[1].str()}});
  const auto surfaces = c.Get("/api/surfaces");
  ASSERT_TRUE(surfaces);
  EXPECT_EQ(nlohmann::json::parse(surfaces->body)["initial"], "builtin:dome");
  const auto bad = c.Get("/api/design?D=0");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  // A second server on the same port: exit status 2 and one line.
  const auto taken = run_gridshell("studio --port " + std::to_string(port) + " --quiet");
  EXPECT_EQ(taken.status, 2);
  EXPECT_EQ(taken.err, "gridshell: error: --port: cannot listen on 127.0.0.1:" +
                           std::to_string(port) + " (in use?)\n");
  // The first still answers after that.
  const auto again = c.Get("/api/design?D=1&A=1&cells=60&analyze=linear");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200);
  // A bad surface on the command line ends it at once, as `design` would.
  const auto nope = run_gridshell("studio builtin:nope --port 0");
  EXPECT_EQ(nope.status, 2);
  EXPECT_NE(nope.err.find("gridshell: error: builtin:nope: unknown built-in surface"),
            std::string::npos);
}
