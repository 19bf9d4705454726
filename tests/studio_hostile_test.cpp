// The studio (src/gridshell/studio/server.h) against hostile requests: a foreign Host or Origin,
// no or a wrong token, path-like upload names, oversized bodies however they are sent (length,
// chunked, gzip), NaN / inf / huge parameters, and export + design + upload at once. Every answer
// is one of 400 / 403 / 405 / 409 / 413 / 503 — never 500, never a crash — and the server answers
// normally afterwards. Concurrency is ordered by the server's pause points (studio_support.h).

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "gridshell/io/files.h"
#include "gridshell/studio/server.h"
#include "studio_support.h"
#include "test_support.h"

#include <httplib.h>  // last: its <resolv.h> defines `_res`, which breaks Eigen headers after it

namespace fs = std::filesystem;
using gridshell::test::run_gridshell;
using gridshell::test::slurp;
using gridshell::test::temp_dir;

namespace {

class StudioHostileTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    gate_ = new gridshell::test::StudioGate;
    gridshell::studio::ServerOptions options;
    options.port = 0;
    options.pause_hook = gate_->hook();
    server_ = new gridshell::studio::Server(options);
    port_ = server_->start();
  }
  static void TearDownTestSuite() {
    gate_->release();
    delete server_;
    delete gate_;
  }
  void TearDown() override {
    gate_->release();
    // The server still answers normally after each test.
    auto c = client();
    const auto r = c.Get("/api/surfaces");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
  }
  static httplib::Client client(bool token = true) {
    httplib::Client c("127.0.0.1", port_);
    c.set_read_timeout(600, 0);
    c.set_write_timeout(60, 0);
    if (token) c.set_default_headers({{"X-Gridshell-Token", server_->token()}});
    return c;
  }
  /// The status of GET `path` with extra `headers` (-1: no answer).
  static int get(const std::string& path, const httplib::Headers& headers = {}, bool token = true) {
    auto c = client(token);
    const auto r = c.Get(path, headers);
    return r ? r->status : -1;
  }
  static std::string other_origin() { return "http://127.0.0.1:" + std::to_string(port_ + 1); }
  static gridshell::test::StudioGate* gate_;
  static gridshell::studio::Server* server_;
  static int port_;
};
gridshell::test::StudioGate* StudioHostileTest::gate_ = nullptr;
gridshell::studio::Server* StudioHostileTest::server_ = nullptr;
int StudioHostileTest::port_ = 0;

const std::set<int> kRefusals = {400, 403, 405, 409, 413, 503};

}  // namespace

TEST_F(StudioHostileTest, OnlyItsOwnPageWithTheTokenIsAnswered) {
  const std::string own = "127.0.0.1:" + std::to_string(port_);
  for (const std::string path : {"/", "/api/surfaces", "/api/design?cells=60&analyze=none",
                                 "/api/config.json", "/api/export.zip?cells=60"}) {
    // DNS rebinding: the browser sends the attacker's name as Host.
    EXPECT_EQ(get(path, {{"Host", "attacker.example:" + std::to_string(port_)}}), 403) << path;
    EXPECT_EQ(get(path, {{"Host", "127.0.0.1:1"}}), 403) << path;
    // A page of another origin (another port is another origin), or a sandboxed one.
    EXPECT_EQ(get(path, {{"Origin", other_origin()}}), 403) << path;
    EXPECT_EQ(get(path, {{"Origin", "null"}}), 403) << path;
    EXPECT_EQ(get(path, {{"Origin", "http://" + own + ".attacker.example"}}), 403) << path;
  }
  for (const std::string path : {"/api/surfaces", "/api/design?cells=60&analyze=none",
                                 "/api/config.json", "/api/export.zip?cells=60"}) {
    EXPECT_EQ(get(path, {}, /*token=*/false), 403) << path;
    EXPECT_EQ(get(path, {{"X-Gridshell-Token", "0123456789abcdef0123456789abcdef"}}, false), 403)
        << path;
    EXPECT_EQ(get(path, {{"X-Gridshell-Token", server_->token() + "0"}}, false), 403) << path;
    EXPECT_EQ(get(path, {{"Sec-Fetch-Site", "same-site"}}), 403) << path;
    EXPECT_EQ(get(path, {{"Sec-Fetch-Site", "cross-site"}}), 403) << path;
  }
  // None of them took a design number, and the token is not in any refusal.
  EXPECT_EQ(gate_->queued(), 0);
  auto c = client(false);
  const auto refused = c.Get("/api/surfaces");
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->body.find(server_->token()), std::string::npos);
  // The page opened by another page (a link or a frame: its link could preset a design).
  EXPECT_EQ(get("/", {{"Sec-Fetch-Site", "same-site"}}), 403);
  EXPECT_EQ(get("/", {{"Sec-Fetch-Site", "cross-site"}}), 403);
  // Its own page, as a browser asks for it, is answered, with the token in it.
  const auto page = c.Get("/", {{"Sec-Fetch-Site", "none"}});
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find(server_->token()), std::string::npos);
  EXPECT_EQ(page->get_header_value("X-Frame-Options"), "DENY");
  EXPECT_EQ(get("/api/surfaces", {{"Origin", "http://" + own}, {"Sec-Fetch-Site", "same-origin"}}),
            200);
  EXPECT_EQ(get("/api/surfaces", {{"Host", "localhost:" + std::to_string(port_)}}), 200);
}

TEST_F(StudioHostileTest, BadParametersAre400) {
  for (const std::string q :
       {"D=nan", "D=inf", "D=-inf", "D=1e308", "D=11", "A=1e400", "A=0x10", "cells=nan",
        "cells=1e9", "cells=5001", "cells=-1", "cells=2.5", "length=nan", "length=1e308",
        "length=-3", "length=100000", "seed=-1", "seed=1e300", "seed=nan",
        "surface=builtin:barrel:length%3D85899346", "surface=builtin:paraboloid:res%3D1000000000",
        "surface=builtin:dome:res%3D1e9", "surface=builtin:dome:span%3Dnan",
        "surface=builtin:court:span%3D0.1,width%3D1000,hole%3D0.01", "surface=../../etc/passwd",
        "surface=/etc/passwd", "surface=upload:999", "surface=upload:-1", "surface=upload:",
        "surface=", "surface=builtin:", "objective=nope", "analyze=everything", "symmetry=q",
        "speed=1", "surface=builtin:dome%00x"}) {
    for (const std::string route : {"/api/design?", "/api/config.json?", "/api/export.zip?"})
      EXPECT_EQ(get(route + q), 400) << route << q;
  }
  EXPECT_EQ(gate_->queued(), 0);  // a bad request never takes a design number
}

TEST_F(StudioHostileTest, UploadNamesAndBodies) {
  const fs::path dir = temp_dir("hostile_upload");
  ASSERT_EQ(run_gridshell("design builtin:barrel -D 1 -A 1 --cells 60 --analyze none --figures "
                          "none --quiet -o " +
                          dir.string())
                .status,
            0);
  const std::string obj = slurp(dir / "gridshell.obj");
  auto c = client();
  // Path-like names: only the last component counts, and only known extensions.
  for (const std::string name : {"..", "../", "/", "", "a/..", "x.exe", "..%2F..%2Fx.sh"}) {
    const auto r = c.Post("/api/surface?name=" + name, obj, "application/octet-stream");
    ASSERT_TRUE(r) << name;
    EXPECT_EQ(r->status, 400) << name << ": " << r->body;
  }
  const auto up = c.Post("/api/surface?name=..%2F..%2F..%2Ftmp%2Fevil.obj", obj, "x/y");
  ASSERT_TRUE(up);
  ASSERT_EQ(up->status, 200) << up->body;
  EXPECT_EQ(nlohmann::json::parse(up->body)["name"], "evil.obj");
  EXPECT_FALSE(fs::exists("/tmp/evil.obj"));
  // Bodies over the cap: by length, chunked, and gzip that inflates past it.
  const std::size_t over = gridshell::studio::kMaxUploadBytes + (1u << 20);
  const auto big = c.Post("/api/surface?name=big.obj", std::string(over, ' '), "x/y");
  ASSERT_TRUE(big);
  EXPECT_EQ(big->status, 413);
  const std::string chunk(1u << 16, ' ');
  const auto chunked = client().Post(
      "/api/surface?name=chunked.obj",
      [&](std::size_t offset, httplib::DataSink& sink) {
        if (offset >= over) {
          sink.done();
        } else {
          sink.write(chunk.data(), chunk.size());
        }
        return true;
      },
      "x/y");
  ASSERT_TRUE(chunked);
  EXPECT_EQ(chunked->status, 413);
  if (std::system("command -v gzip >/dev/null 2>&1") != 0)
    SKIP_OR_FAIL_IN_CI("no gzip: it makes the compressed body");
  const fs::path bomb = dir / "bomb.gz";
  ASSERT_EQ(std::system(("head -c " + std::to_string(over) + " /dev/zero | gzip -c >" +
                         bomb.string())
                            .c_str()),
            0);
  const auto inflated = client().Post("/api/surface?name=bomb.obj",
                                      {{"Content-Encoding", "gzip"}}, slurp(bomb), "x/y");
  ASSERT_TRUE(inflated);
  EXPECT_EQ(inflated->status, 413);
  // A body where none belongs, and a method that does not exist.
  const auto get_body = client().Post("/api/design?cells=60", "x", "x/y");
  ASSERT_TRUE(get_body);
  EXPECT_TRUE(kRefusals.count(get_body->status)) << get_body->status;
  const auto del = client().Delete("/api/surfaces");
  ASSERT_TRUE(del);
  EXPECT_TRUE(kRefusals.count(del->status)) << del->status;
}

TEST_F(StudioHostileTest, ExportDesignAndUploadAtOnce) {
  // A non-linear design held at its second step; meanwhile an export (503: busy), an upload
  // (served: loading does not wait for designs), a bad design (400, and it does not stop the
  // held one), then a newer good design, which does.
  gate_->pause_at(2);
  int held = 0, newer = 0;
  std::thread a([&] {
    auto c = client();
    const auto r =
        c.Get("/api/design?surface=builtin:dome&D=1&A=1&cells=80&analyze=nonlinear&seed=4");
    held = r ? r->status : -1;
  });
  ASSERT_TRUE(gate_->wait_paused());
  const int queued = gate_->queued();
  EXPECT_EQ(get("/api/export.zip?surface=builtin:dome&D=1&A=1&cells=60"), 503);
  EXPECT_EQ(get("/api/design?surface=builtin:dome&D=1&A=1&cells=60&seed=nan"), 400);
  EXPECT_EQ(get("/api/config.json?surface=builtin:dome:span%3D20.0&D=1&A=1&cells=60"), 200);
  const std::string off = "OFF\n4 2 0\n0 0 0\n10 0 0\n10 10 1\n0 10 0\n3 0 1 2\n3 0 2 3\n";
  auto c = client();
  const auto up = c.Post("/api/surface?name=quad.off", off, "x/y");
  ASSERT_TRUE(up);
  EXPECT_EQ(up->status, 200) << up->body;
  EXPECT_EQ(gate_->queued(), queued);
  std::thread b([&] {
    auto cb = client();
    const auto r = cb.Get("/api/design?surface=builtin:dome:span%3D20.0&D=1&A=1&cells=60&analyze=none");
    newer = r ? r->status : -1;
  });
  ASSERT_TRUE(gate_->wait_queued(queued + 1));
  gate_->release();
  a.join();
  b.join();
  EXPECT_EQ(held, 409);
  EXPECT_EQ(newer, 200);
  // An export of what was designed last is served once nothing runs.
  const auto zip = c.Get("/api/export.zip?surface=builtin:dome:span%3D20&D=1&A=1&cells=60&analyze=none");
  ASSERT_TRUE(zip);
  EXPECT_EQ(zip->status, 200);
}

TEST_F(StudioHostileTest, TheSurfaceCacheIsBoundedAndItsKeysNormalised) {
  // span=20 and span=20.0 are one surface; many different ones stay within the cache's bound.
  for (int k = 0; k < 2 * gridshell::studio::kMaxCachedSurfaces + 3; ++k) {
    const std::string q =
        "/api/config.json?surface=builtin:dome:res%3D" + std::to_string(8 + 2 * k) + "&cells=60";
    EXPECT_EQ(get(q), 200) << q;
  }
  EXPECT_LE(server_->cached_surfaces(), 1 + gridshell::studio::kMaxCachedSurfaces);
  auto c = client();
  const auto a = c.Get("/api/config.json?surface=builtin:dome:span%3D20,res%3D12&cells=60");
  const auto b = c.Get("/api/config.json?surface=builtin:dome:res%3D12,span%3D20.000&cells=60");
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->body, b->body);
  EXPECT_EQ(nlohmann::json::parse(a->body)["positional"][0], "builtin:dome:res=12,span=20");
  const int cached = server_->cached_surfaces();
  EXPECT_EQ(get("/api/config.json?surface=builtin:dome:span%3D20.0,res%3D12.&cells=60"), 400);
  EXPECT_EQ(get("/api/config.json?surface=builtin:dome:res%3D12,span%3D2e1&cells=60"), 200);
  EXPECT_EQ(server_->cached_surfaces(), cached);  // the same entry
}
