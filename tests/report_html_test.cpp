// report.html (report/report_html.h): the page is self-contained, its data block holds the
// grid-shell with the ids of the CSV files, the commands write it, and headless Chromium draws
// the mesh from disk and over HTTP alike, with no error logged.

#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/report/assets.h"
#include "gridshell/report/report_html.h"
#include "png_support.h"
#include "test_support.h"

using gridshell::test::find_chromium;
using gridshell::test::Image;
using gridshell::test::read_png;
using gridshell::test::slurp;

using gridshell::PolyMesh;
using gridshell::test::run_gridshell;
using gridshell::test::temp_dir;
namespace fs = std::filesystem;
namespace rep = gridshell::report;

namespace {

/// A shallow dome of n × n quads over 10 m × 10 m, supported along its whole boundary.
struct Dome {
  PolyMesh mesh;
  std::vector<int> supports;
};
Dome quad_dome(int n) {
  Dome d;
  d.mesh.V.resize((n + 1) * (n + 1), 3);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = 10.0 * i / n - 5, y = 10.0 * j / n - 5;
      d.mesh.V.row(i * (n + 1) + j) << x, y, 2.5 - 0.05 * (x * x + y * y);
      if (i == 0 || j == 0 || i == n || j == n) d.supports.push_back(i * (n + 1) + j);
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j;
      d.mesh.faces.push_back({a, a + n + 1, a + n + 2, a + 1});
    }
  return d;
}

/// A 2 × 1 RGB PNG (70 bytes) and its base64 text (written independently, by Python's base64).
const unsigned char kPng[] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
    0x44, 0x52, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00,
    0x00, 0x7b, 0x40, 0xe8, 0xdd, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x44, 0x41, 0x54, 0x78,
    0x9c, 0x63, 0xf8, 0xcf, 0x00, 0x04, 0xff, 0x01, 0x07, 0x00, 0x01, 0xff, 0xe2, 0x23,
    0x9e, 0x59, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
const char* kPngBase64 =
    "iVBORw0KGgoAAAANSUhEUgAAAAIAAAABCAIAAAB7QOjdAAAADUlEQVR4nGP4zwAE/wEHAAH/"
    "4iOeWQAAAABJRU5ErkJggg==";
std::string png_bytes() {
  return std::string(reinterpret_cast<const char*>(kPng), sizeof kPng);
}

/// The JSON data block of a page.
nlohmann::json page_data(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"gridshell-data\">";
  const std::size_t a = html.find(open);
  EXPECT_NE(a, std::string::npos);
  if (a == std::string::npos) return {};
  const std::size_t b = html.find("</script>", a);
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

/// The analysed dome, written with a figure into a fresh folder; returns the folder.
fs::path dome_report(const std::string& name, int n = 8) {
  const Dome d = quad_dome(n);
  const auto r = gridshell::analyze_gridshell(d.mesh, d.supports,
                                              gridshell::analysis::AnalysisLevel::buckling);
  rep::ReportInput in = rep::gridshell_report_input(d.mesh, d.supports, &r);
  in.title = "dome <test>";
  // Two overlaps and one panel glazed as two triangles (report.json's mesh and design blocks),
  // so that the key figures say so: "143 (1 glazed as 2 triangles)" for the 144 quads.
  in.report = {{"structure", {{"delta_max_m", r.delta_max_m}}},
               {"mesh", {{"overlaps", 2}}},
               {"design", {{"flat_panels", {{"cells", n * n - 1}, {"triangulated_panels", 1}}}}}};
  const fs::path dir = temp_dir(name);
  fs::create_directories(dir / "figures");
  gridshell::io::write_file_atomic(dir / "figures" / "a.png", png_bytes());
  gridshell::io::write_file_atomic(dir / "figures" / "notes.txt", "not a figure");
  const rep::ReportWritten w = rep::write_report_html(dir, in);
  EXPECT_EQ(w.figures, 1);
  EXPECT_EQ(w.bytes, fs::file_size(dir / "report.html"));
  return dir;
}

}  // namespace

TEST(ReportHtml, PageIsSelfContained) {
  const fs::path dir = dome_report("page");
  const std::string html = slurp(dir / "report.html");
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  // One inline viewer, no script, style sheet, frame or image loaded from anywhere.
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("<iframe"), std::string::npos);
  EXPECT_FALSE(std::regex_search(html, std::regex(R"(<script[^>]*\ssrc\s*=)")));
  EXPECT_FALSE(std::regex_search(html, std::regex(R"((src|href)\s*=\s*["']?\s*(https?:)?//)")));
  EXPECT_FALSE(std::regex_search(html, std::regex(R"(url\(\s*["']?(https?:)?//)")));
  EXPECT_FALSE(std::regex_search(html, std::regex(R"(\bimport\s*\(|\bfetch\s*\()")));
  // The viewer is there once, whole; the title is escaped; no placeholder is left.
  const std::string_view viewer = rep::viewer_script();
  EXPECT_GT(viewer.size(), 100000u);
  EXPECT_NE(html.find(viewer), std::string::npos);
  EXPECT_EQ(html.find(viewer, html.find(viewer) + 1), std::string::npos);
  EXPECT_EQ(viewer.find("</script"), std::string_view::npos);
  EXPECT_NE(html.find("<title>dome &lt;test&gt;</title>"), std::string::npos);
  for (const char* p : {"@TITLE@", "@DATA@", "@VIEWER@"})
    EXPECT_EQ(html.find(p), std::string::npos);
  // Size: viewer + data + template, nothing else.
  EXPECT_LT(html.size(), viewer.size() + rep::report_template().size() + 200000);
}

TEST(ReportHtml, DataUsesTheIdsOfTheCsvFiles) {
  const int n = 8;
  const Dome d = quad_dome(n);
  const fs::path dir = dome_report("data", n);
  const nlohmann::json j = page_data(slurp(dir / "report.html"));
  const gridshell::Topology t = gridshell::build_topology(d.mesh);
  // Joints = vertices (6 significant digits), beams = Topology edges, panels = faces.
  ASSERT_EQ(j.at("joints").size(), 3u * d.mesh.num_vertices());
  for (int v = 0; v < d.mesh.num_vertices(); ++v)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(j["joints"][3 * v + c].get<double>(), d.mesh.V(v, c), 1e-5 * 5) << v;
  ASSERT_EQ(j.at("beams").size(), 2u * t.num_edges());
  EXPECT_EQ(t.num_edges(), 2 * n * (n + 1));
  for (int e = 0; e < t.num_edges(); ++e) {
    EXPECT_EQ(j["beams"][2 * e].get<int>(), t.edges[e][0]);
    EXPECT_EQ(j["beams"][2 * e + 1].get<int>(), t.edges[e][1]);
  }
  EXPECT_EQ(j.at("panels").get<std::vector<std::vector<int>>>(), d.mesh.faces);
  EXPECT_EQ(j.at("supports").get<std::vector<int>>(), d.supports);
  EXPECT_EQ(j.at("axial_force").size(), static_cast<std::size_t>(t.num_edges()));
  EXPECT_EQ(j.at("displacement").size(), 3u * d.mesh.num_vertices());
  EXPECT_TRUE(j.at("density").empty());  // no field: no density mode
  // Utilisation per beam: the member checks' cross-section figure, as in beams.csv.
  ASSERT_EQ(j.at("utilisation").size(), static_cast<std::size_t>(t.num_edges()));
  // It is N/(A fy) + M/(W fy) ≥ |N|/(A fy) (the paper's Ø37 mm bars, S355 by default).
  const double A_fy = 3.14159265358979 * 0.037 * 0.037 / 4 * 355e6;
  for (int e = 0; e < t.num_edges(); ++e)
    EXPECT_GE(j["utilisation"][e].get<double>() * (1 + 1e-5),
              std::abs(j["axial_force"][e].get<double>()) / A_fy)
        << e;
  // A doubly curved dome under its weight is in compression: most bars pushed, none much pulled.
  int compressed = 0;
  for (const auto& x : j["axial_force"]) compressed += x.get<double>() < 0;
  EXPECT_GT(compressed, t.num_edges() / 2);
  // Planarity: z = c - k x² - k y² is a translational surface (f(x) + g(y)), so every quad of
  // the axis-aligned grid is exactly planar; a twisted quad elsewhere is not.
  const auto pl = j.at("planarity").get<std::vector<double>>();
  ASSERT_EQ(pl.size(), d.mesh.faces.size());
  for (double x : pl) EXPECT_NEAR(x, 0, 1e-9);
  Dome twisted = quad_dome(n);
  twisted.mesh.V(0, 2) += 0.5;
  const auto tj = nlohmann::json::parse(rep::report_data_json(
      rep::gridshell_report_input(twisted.mesh, twisted.supports, nullptr), {}));
  EXPECT_GT(tj["planarity"][0].get<double>(), 0.01);
  EXPECT_NEAR(tj["planarity"][1].get<double>(), 0, 1e-9);
  // Buckling modes: one translation per joint, the largest of length 1 (4 digits), zero at the
  // pinned supports.
  const auto& modes = j.at("buckling").at("modes");
  ASSERT_GE(modes.size(), 1u);
  EXPECT_EQ(j["buckling"]["lambdas"].size(), modes.size());
  EXPECT_GT(j["buckling"]["lambdas"][0].get<double>(), 0);
  for (const auto& m : modes) {
    ASSERT_EQ(m.size(), 3u * d.mesh.num_vertices());
    double largest = 0;
    for (int v = 0; v < d.mesh.num_vertices(); ++v)
      largest = std::max(largest, std::hypot(m[3 * v].get<double>(), m[3 * v + 1].get<double>(),
                                             m[3 * v + 2].get<double>()));
    EXPECT_NEAR(largest, 1, 2e-3);
    for (int v : d.supports) EXPECT_NEAR(m[3 * v + 2].get<double>(), 0, 1e-9);
  }
  // The figure: a data URI whose base64 is the file's.
  ASSERT_EQ(j.at("figures").size(), 1u);
  EXPECT_EQ(j["figures"][0]["name"], "a.png");
  EXPECT_EQ(j["figures"][0]["src"], std::string("data:image/png;base64,") + kPngBase64);
  EXPECT_EQ(j.at("report").at("structure").count("delta_max_m"), 1u);
}

TEST(ReportHtml, Base64PaddingAndEscaping) {
  rep::ReportInput in;
  in.joints.resize(3, 3);
  in.joints << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  in.beams = {{{0, 1}}, {{1, 2}}, {{2, 0}}};
  in.panels = {{0, 1, 2}};
  in.report = {{"note", "</script><script>alert(1)</script>"}};
  const std::vector<rep::Figure> figs = {{"1.png", "M"}, {"2.png", "Ma"}, {"3.png", "Man"}};
  const std::string text = rep::report_data_json(in, figs);
  EXPECT_EQ(text.find('<'), std::string::npos);  // cannot end the script element
  const nlohmann::json j = nlohmann::json::parse(text);
  EXPECT_EQ(j["report"]["note"], "</script><script>alert(1)</script>");
  EXPECT_EQ(j["figures"][0]["src"], "data:image/png;base64,TQ==");
  EXPECT_EQ(j["figures"][1]["src"], "data:image/png;base64,TWE=");
  EXPECT_EQ(j["figures"][2]["src"], "data:image/png;base64,TWFu");
}

TEST(ReportHtml, RejectsInconsistentInput) {
  const Dome d = quad_dome(3);
  const rep::ReportInput good = rep::gridshell_report_input(d.mesh, d.supports, nullptr);
  EXPECT_NO_THROW(rep::report_data_json(good, {}));
  rep::ReportInput in = good;
  in.axial_force.assign(good.beams.size() - 1, 1.0);  // one short
  EXPECT_THROW(rep::report_data_json(in, {}), gridshell::Error);
  in = good;
  in.density.assign(good.panels.size(), 1.0);
  in.density[2] = std::nan("");
  EXPECT_THROW(rep::report_data_json(in, {}), gridshell::Error);
  in = good;
  in.beams.push_back({{0, d.mesh.num_vertices()}});
  EXPECT_THROW(rep::report_data_json(in, {}), gridshell::Error);
  in = good;
  in.beam_sections.assign(good.beams.size() + 1, "CHS 88.9x3.2");  // one too many
  EXPECT_THROW(rep::report_data_json(in, {}), gridshell::Error);
  in = good;
  in.buckling_lambdas = {2.0};  // a lambda without its mode
  EXPECT_THROW(rep::report_data_json(in, {}), gridshell::Error);
}

TEST(ReportHtml, CommandsWriteIt) {
  // design (mesh + density from the field + analysis), then analyze on its mesh and on a
  // MODEL.json frame (members as beams, no panels).
  const fs::path d = temp_dir("design");
  auto r = run_gridshell(
      "design builtin:dome --cells 40 --seed 3 -D 2 -A 1 --analyze buckling "
      "--quiet -o " +
      d.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto mesh = gridshell::io::read_mesh(d / "gridshell.obj").mesh;
  const gridshell::Topology t = gridshell::build_topology(mesh);
  nlohmann::json j = page_data(slurp(d / "report.html"));
  EXPECT_EQ(j["joints"].size(), 3u * mesh.num_vertices());
  EXPECT_EQ(j["beams"].size(), 2u * t.num_edges());
  EXPECT_EQ(j["panels"].size(), mesh.faces.size());
  EXPECT_EQ(j["density"].size(), mesh.faces.size());
  EXPECT_EQ(j["axial_force"].size(), static_cast<std::size_t>(t.num_edges()));
  EXPECT_FALSE(j["buckling"]["modes"].empty());
  EXPECT_EQ(j["report"], nlohmann::json::parse(slurp(d / "report.json")));
  EXPECT_EQ(j["config"], nlohmann::json::parse(slurp(d / "config.json")));
  // The page's beam b is beams.csv's row b.
  std::istringstream beams_csv(slurp(d / "beams.csv"));
  std::string line;
  std::getline(beams_csv, line);
  for (int b = 0; std::getline(beams_csv, line); ++b) {
    int id = 0, i = 0, k = 0;
    char comma = 0;
    std::istringstream row(line);
    row >> id >> comma >> i >> comma >> k;
    ASSERT_LT(2 * b + 1, static_cast<int>(j["beams"].size()));
    EXPECT_EQ(id, b);
    EXPECT_EQ(j["beams"][2 * b].get<int>(), i);
    EXPECT_EQ(j["beams"][2 * b + 1].get<int>(), k);
  }

  const fs::path a = temp_dir("analyze");
  r = run_gridshell("analyze " + (d / "gridshell.obj").string() + " --analyze linear --quiet -o " +
                    a.string());
  ASSERT_EQ(r.status, 0) << r.err;
  j = page_data(slurp(a / "report.html"));
  EXPECT_EQ(j["beams"].size(), 2u * t.num_edges());
  EXPECT_EQ(j["displacement"].size(), 3u * mesh.num_vertices());
  EXPECT_TRUE(j["buckling"]["modes"].empty());

  const fs::path m = temp_dir("model");
  const nlohmann::json model = {
      {"nodes", {{0, 0, 0}, {0, 0, 3}, {4, 0, 3}, {4, 0, 0}}},
      {"members",
       {{{"nodes", {0, 1}}, {"section", "S"}, {"material", "M"}},
        {{"nodes", {1, 2}}, {"section", "S"}, {"material", "M"}},
        {{"nodes", {2, 3}}, {"section", "S"}, {"material", "M"}}}},
      {"sections", {{"S", {{"shape", "circle"}, {"diameter", 0.1}}}}},
      {"materials", {{"M", {{"E", 2.1e11}, {"nu", 0.3}, {"density", 7850}}}}},
      {"supports",
       {{{"node", 0}, {"fix", {"ux", "uy", "uz", "rx", "ry", "rz"}}},
        {{"node", 3}, {"fix", {"ux", "uy", "uz", "rx", "ry", "rz"}}}}},
      {"loads", {{{"node", 1}, {"force", {1000, 0, -5000}}}}}};
  gridshell::io::write_file_atomic(m / "MODEL.json", model.dump());
  r = run_gridshell("analyze " + (m / "MODEL.json").string() + " --analyze buckling --quiet -o " +
                    (m / "out").string());
  ASSERT_EQ(r.status, 0) << r.err;
  j = page_data(slurp(m / "out" / "report.html"));
  EXPECT_EQ(j["joints"].size(), 12u);
  EXPECT_EQ(j["beams"], nlohmann::json({0, 1, 1, 2, 2, 3}));
  EXPECT_TRUE(j["panels"].empty());
  EXPECT_EQ(j["supports"], nlohmann::json({0, 3}));
  EXPECT_EQ(j["axial_force"].size(), 3u);
  // Equilibrium of the portal: the two columns carry the 5 kN down between them.
  EXPECT_NEAR(j["axial_force"][0].get<double>() + j["axial_force"][2].get<double>(), -5000, 1);
}

// ---------------------------------------------------------------------------------------------
// Headless Chromium: the page from disk and over HTTP.

namespace {

struct Shot {
  int status = -1;
  std::string dom, log;
};

/// Runs headless Chromium on `url` with WebGL on SwiftShader and every host name unresolvable
/// (no network), once for a screenshot (none when `png` is empty) and once for the DOM after the
/// scripts ran.
Shot chromium(const std::string& exe, const std::string& url, const fs::path& png,
              const fs::path& work) {
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --use-angle=swiftshader --enable-unsafe-swiftshader"
      " --hide-scrollbars --window-size=1200,800 --virtual-time-budget=4000"
      " --host-resolver-rules=\"MAP * ~NOTFOUND, EXCLUDE 127.0.0.1\" --enable-logging=stderr --v=0"
      " --user-data-dir=" +
      (work / "profile").string();
  Shot s;
  std::string cmd = "timeout 120 " + exe + flags + " --screenshot=" + png.string() + " '" + url +
                    "' >/dev/null 2>" + (work / "shot.log").string();
  s.status = png.empty() ? 0 : std::system(cmd.c_str());
  if (png.empty()) gridshell::io::write_file_atomic(work / "shot.log", "");
  cmd = "timeout 120 " + exe + flags + " --dump-dom '" + url + "' >" +
        (work / "dom.html").string() + " 2>" + (work / "dom.log").string();
  const int status = std::system(cmd.c_str());
  if (s.status == 0) s.status = status;
  s.dom = slurp(work / "dom.html");
  s.log = slurp(work / "shot.log") + slurp(work / "dom.log");
  return s;
}

/// Console lines of the page that are errors (Chromium's own GPU performance notes aside).
std::vector<std::string> console_errors(const std::string& log) {
  std::vector<std::string> out;
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line))
    if (line.find(":CONSOLE") != std::string::npos &&
        line.find("GL Driver Message") == std::string::npos &&
        std::regex_search(line, std::regex("rror|Uncaught|Failed|refused", std::regex::icase)))
      out.push_back(line);
  return out;
}

/// A minimal HTTP/1.1 server on 127.0.0.1 (a free port) that serves the files of one folder,
/// one request per connection, until destroyed.
class FolderServer {
 public:
  explicit FolderServer(fs::path root) : root_(std::move(root)) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof addr;
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        ::listen(fd_, 16) != 0 || ::getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
      return;
    port_ = ntohs(addr.sin_port);
    thread_ = std::thread([this] { serve(); });
  }
  ~FolderServer() {
    ::shutdown(fd_, SHUT_RDWR);  // wakes accept()
    if (thread_.joinable()) thread_.join();
    ::close(fd_);
  }
  int port() const { return port_; }
  int requests() const { return requests_; }

 private:
  void serve() {
    for (;;) {
      const int c = ::accept(fd_, nullptr, nullptr);
      if (c < 0) return;
      std::string request;
      char buf[4096];
      while (request.find("\r\n\r\n") == std::string::npos && request.size() < 65536) {
        const ssize_t n = ::recv(c, buf, sizeof buf, 0);
        if (n <= 0) break;
        request.append(buf, static_cast<std::size_t>(n));
      }
      std::smatch m;
      std::string status = "404 Not Found", body = "not found", type = "text/plain";
      if (std::regex_search(request, m, std::regex("^GET /([A-Za-z0-9_./-]*)")) &&
          m[1].str().find("..") == std::string::npos && fs::is_regular_file(root_ / m[1].str())) {
        status = "200 OK";
        body = slurp(root_ / m[1].str());
        type =
            m[1].str().ends_with(".html") ? "text/html; charset=utf-8" : "application/octet-stream";
        ++requests_;
      }
      const std::string response = "HTTP/1.1 " + status + "\r\nContent-Type: " + type +
                                   "\r\nContent-Length: " + std::to_string(body.size()) +
                                   "\r\nConnection: close\r\n\r\n" + body;
      for (std::size_t sent = 0; sent < response.size();) {
        const ssize_t n = ::send(c, response.data() + sent, response.size() - sent, MSG_NOSIGNAL);
        if (n <= 0) break;
        sent += static_cast<std::size_t>(n);
      }
      ::close(c);
    }
  }

  fs::path root_;
  int fd_ = -1;
  int port_ = -1;
  std::atomic<int> requests_{0};
  std::thread thread_;
};

/// The page's error record (<html data-errors="...">), or "(none)" when the attribute is missing
/// (the page's scripts did not run).
std::string page_errors(const std::string& dom) {
  std::smatch m;
  if (!std::regex_search(dom, m, std::regex("<html[^>]*\\sdata-errors=\"([^\"]*)\"")))
    return "(none)";
  return m[1];
}

}  // namespace

TEST(ReportHtml, ChromiumDrawsTheMeshFromDiskAndOverHttp) {
  const std::string exe = find_chromium();
  if (exe.empty()) SKIP_OR_FAIL_IN_CI("no chromium: headless Chromium is the report's browser");
  const fs::path dir = dome_report("chromium", 12);
  const fs::path work = temp_dir("chromium_work");

  // From disk.
  const Shot disk = chromium(exe, "file://" + fs::absolute(dir / "report.html").string(),
                             work / "disk.png", work);
  ASSERT_EQ(disk.status, 0) << disk.log;
  EXPECT_EQ(page_errors(disk.dom), "") << disk.dom.substr(0, 400);
  EXPECT_NE(disk.dom.find("data-ready=\"1\""), std::string::npos);
  EXPECT_TRUE(console_errors(disk.log).empty()) << console_errors(disk.log).front();
  EXPECT_NE(disk.dom.find("<th>cells (panels)</th><td>143 (1 glazed as 2 triangles)</td>"),
            std::string::npos);
  EXPECT_NE(disk.dom.find("<th>overlaps</th><td><b style=\"color:#b00\">2</b> (not buildable as "
                          "is)</td>"),
            std::string::npos);
  const Image a = read_png(work / "disk.png");
  ASSERT_EQ(a.width, 1200);
  ASSERT_EQ(a.height, 800);
  // The 3D view is left of the 340 px side panel; its background is (246, 246, 243). Count the
  // pixels the mesh covers, those drawn in the axial-force colours (red or blue, not grey), and
  // the extent of the drawing.
  const int view_width = 1200 - 340;
  long covered = 0, coloured = 0;
  int x0 = view_width, x1 = 0, y0 = a.height, y1 = 0;
  for (int y = 60; y < a.height - 120; ++y)  // above the legend, below the hover line
    for (int x = 0; x < view_width; ++x) {
      const unsigned char* p = a.at(x, y);
      const int diff = std::abs(p[0] - 246) + std::abs(p[1] - 246) + std::abs(p[2] - 243);
      if (diff <= 24) continue;
      ++covered;
      coloured += std::abs(p[0] - p[2]) > 60;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  const double area = double(view_width) * (a.height - 180);
  EXPECT_GT(covered / area, 0.10) << "the canvas is nearly blank";
  EXPECT_GT(coloured, 2000) << "no beams in the force colours";
  EXPECT_GT(x1 - x0, view_width / 2) << "the mesh is not fitted to the view";
  EXPECT_GT(y1 - y0, (a.height - 180) / 4);

  // Over HTTP (a small server in this test serving the folder): the same picture.
  Shot http;
  {
    const FolderServer server(dir);
    ASSERT_GT(server.port(), 0);
    http = chromium(exe, "http://127.0.0.1:" + std::to_string(server.port()) + "/report.html",
                    work / "http.png", work);
    EXPECT_EQ(server.requests(), 2);  // the page, once per Chromium run: nothing else
  }
  ASSERT_EQ(http.status, 0) << http.log;
  EXPECT_EQ(page_errors(http.dom), "");
  EXPECT_TRUE(console_errors(http.log).empty()) << console_errors(http.log).front();
  const Image b = read_png(work / "http.png");
  ASSERT_EQ(b.width, a.width);
  ASSERT_EQ(b.height, a.height);
  long differ = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const unsigned char *p = a.at(x, y), *q = b.at(x, y);
      differ += std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) > 24;
    }
  EXPECT_LT(differ, a.width * a.height / 200) << "disk and HTTP renderings differ";

  // A link to another view (web/src/viewer.js applyLink): coloured by displacement, the first
  // buckling mode at 10 % of the span, and a click in the middle of the view, whose id the info
  // line shows. The picture changes; still no error.
  const Shot linked = chromium(exe,
                               "file://" + fs::absolute(dir / "report.html").string() +
                                   "#colour=displacement&mode=1&amplitude=10&click=430,420",
                               work / "linked.png", work);
  ASSERT_EQ(linked.status, 0) << linked.log;
  EXPECT_EQ(page_errors(linked.dom), "");
  EXPECT_TRUE(console_errors(linked.log).empty()) << console_errors(linked.log).front();
  std::smatch m;
  ASSERT_TRUE(
      std::regex_search(linked.dom, m, std::regex("<div id=\"info\">(joint|beam|panel) (\\d+)")))
      << "the click found nothing";
  const int id = std::stoi(m[2]);
  const int count = m[1] == "joint" ? 13 * 13 : m[1] == "beam" ? 2 * 12 * 13 : 12 * 12;
  EXPECT_LT(id, count) << m[0];
  const Image c = read_png(work / "linked.png");
  ASSERT_EQ(c.width, a.width);
  long changed = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < view_width; ++x) {
      const unsigned char *p = a.at(x, y), *q = c.at(x, y);
      changed += std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) > 24;
    }
  EXPECT_GT(changed, long(0.05 * area)) << "the link did not change the view";
}

// A sized design (sizing/sizing.h): the data block has each beam's section as beams.csv has it;
// the page colours the beams by section with one legend entry per distinct section, lightest per
// metre first, in colours that the picture shows; the Steel panel's mass is report.json's.
TEST(ReportHtml, SizedDesignShowsSectionsAndSteel) {
  const fs::path d = temp_dir("sized");
  const auto r = run_gridshell(
      "design builtin:dome --cells 40 --seed 3 -D 1 -A 1 --size --analyze buckling --quiet -o " +
      d.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json report = nlohmann::json::parse(slurp(d / "report.json"));
  ASSERT_TRUE(report.at("sizing").at("sized").get<bool>());
  const nlohmann::json& mass = report.at("mass");
  const nlohmann::json j = page_data(slurp(d / "report.html"));
  const std::size_t n_beams = j.at("beams").size() / 2;
  ASSERT_EQ(j.at("beam_sections").size(), n_beams);
  ASSERT_EQ(j.at("buckling_utilisation").size(), n_beams);
  // beams.csv's `section` (column 10) and `buckling_utilisation` (column 7), row b = beam b.
  std::istringstream csv(slurp(d / "beams.csv"));
  std::string line;
  std::getline(csv, line);
  std::size_t rows = 0;
  std::set<std::string> distinct;
  for (; std::getline(csv, line); ++rows) {
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string c; std::getline(row, c, ',');) cells.push_back(c);
    ASSERT_GE(cells.size(), 10u) << line;
    ASSERT_LT(rows, n_beams);
    EXPECT_EQ(j["beam_sections"][rows].get<std::string>(), cells[9]) << rows;
    EXPECT_NEAR(j["buckling_utilisation"][rows].get<double>(), std::stod(cells[6]),
                1e-4 * std::abs(std::stod(cells[6])) + 1e-12);
    distinct.insert(cells[9]);
  }
  EXPECT_EQ(rows, n_beams);
  ASSERT_EQ(distinct.size(), mass.at("distinct_sections").get<std::size_t>());
  ASSERT_GE(distinct.size(), 3u) << "a sized dome uses several sections";
  // Its frame.json analysed again: the members' section names are the same designations.
  const auto again = run_gridshell("analyze " + (d / "frame.json").string() +
                                   " --analyze linear --quiet -o " + (d / "again").string());
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(page_data(slurp(d / "again" / "report.html")).at("beam_sections"), j["beam_sections"]);

  const std::string exe = find_chromium();
  if (exe.empty()) SKIP_OR_FAIL_IN_CI("no chromium: headless Chromium is the report's browser");
  const fs::path work = temp_dir("sized_work");
  const Shot s =
      chromium(exe, "file://" + fs::absolute(d / "report.html").string() + "#colour=section",
               work / "section.png", work);
  ASSERT_EQ(s.status, 0) << s.log;
  EXPECT_EQ(page_errors(s.dom), "");
  // The legend (inside <div id="legend">, before the side panel): one entry per section, in the
  // order of mass per metre (report.json's mass / length), members summing to the beams.
  const std::size_t a = s.dom.find("<div id=\"legend\">"), b = s.dom.find("<div id=\"side\">");
  ASSERT_TRUE(a != std::string::npos && b != std::string::npos && a < b);
  const std::string legend = s.dom.substr(a, b - a);
  const std::regex entry(
      "<tr class=\"legend-entry\"><td><span class=\"swatch\" style=\"background:"
      "rgb\\((\\d+), ?(\\d+), ?(\\d+)\\)\"></span></td><th>([^<]*)</th><td>(\\d+)</td>");
  std::vector<std::string> names;
  std::vector<std::array<int, 3>> colours;
  std::size_t members = 0;
  for (auto it = std::sregex_iterator(legend.begin(), legend.end(), entry);
       it != std::sregex_iterator(); ++it) {
    names.push_back((*it)[4]);
    colours.push_back({std::stoi((*it)[1]), std::stoi((*it)[2]), std::stoi((*it)[3])});
    members += std::stoul((*it)[5]);
  }
  ASSERT_EQ(names.size(), distinct.size()) << legend.substr(0, 600);
  EXPECT_EQ(members, n_beams);
  std::map<std::string, double> per_metre;
  for (const auto& sec : mass.at("sections"))
    per_metre[sec.at("designation")] =
        sec.at("mass_kg").get<double>() / sec.at("length_m").get<double>();
  for (std::size_t k = 0; k + 1 < names.size(); ++k)
    EXPECT_LE(per_metre.at(names[k]), per_metre.at(names[k + 1]))
        << names[k] << " " << names[k + 1];
  const std::set<std::array<int, 3>> unique_colours(colours.begin(), colours.end());
  EXPECT_EQ(unique_colours.size(), colours.size()) << "two sections share a colour";
  // The Steel panel: the mass shown (4 significant digits) is report.json's.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(s.dom, m, std::regex("<td id=\"steel-mass\">([0-9.e+]+) kg</td>")));
  EXPECT_NEAR(std::stod(m[1]), mass.at("mass_kg").get<double>(),
              5e-4 * mass.at("mass_kg").get<double>());
  EXPECT_NE(s.dom.find("<p id=\"sizing-verdict\"><b style=\"color:#161\">sized</b>"),
            std::string::npos);
  // The picture: the beams are drawn in the legend's colours, at least three of them plainly
  // (looked for right of the legend box, left of the side panel).
  const Image img = read_png(work / "section.png");
  std::vector<long> seen(colours.size(), 0);
  for (int y = 60; y < img.height; ++y)
    for (int x = 330; x < img.width - 340; ++x) {
      const unsigned char* p = img.at(x, y);
      for (std::size_t k = 0; k < colours.size(); ++k)
        if (std::abs(p[0] - colours[k][0]) + std::abs(p[1] - colours[k][1]) +
                std::abs(p[2] - colours[k][2]) <=
            30) {
          ++seen[k];
          break;
        }
    }
  int shown = 0;
  for (long c : seen) shown += c > 50;
  EXPECT_GE(shown, std::min<int>(3, static_cast<int>(colours.size())))
      << ::testing::PrintToString(seen);
}

// A section list that cannot carry the load: the Steel panel says "not sized" in red with the
// failing check of report.json, never a plain mass as if the design were safe.
TEST(ReportHtml, UnsizedDesignSaysWhyInRed) {
  const fs::path d = temp_dir("unsized");
  gridshell::io::write_file_atomic(d / "small.txt", "CHS 21.3x2.3\nCHS 26.9x2.3\n");
  const auto r = run_gridshell(
      "design builtin:dome --cells 40 --seed 3 -D 1 -A 1 --size --sections " +
      (d / "small.txt").string() + " --analyze linear --quiet -o " + (d / "out").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json report = nlohmann::json::parse(slurp(d / "out" / "report.json"));
  ASSERT_FALSE(report.at("sizing").at("sized").get<bool>());
  const std::string failure = report["sizing"].at("failure");
  ASSERT_FALSE(failure.empty());
  const std::string exe = find_chromium();
  if (exe.empty()) SKIP_OR_FAIL_IN_CI("no chromium: headless Chromium is the report's browser");
  const fs::path work = temp_dir("unsized_work");
  const Shot s =
      chromium(exe, "file://" + fs::absolute(d / "out" / "report.html").string(), fs::path(), work);
  ASSERT_EQ(s.status, 0) << s.log;
  EXPECT_EQ(page_errors(s.dom), "");
  // The failure text is plain here (designations and clause numbers: no character to escape).
  EXPECT_NE(s.dom.find("<p id=\"sizing-verdict\" style=\"color:#b00\"><b>not sized</b>: " +
                       failure + "</p>"),
            std::string::npos)
      << failure;
}
