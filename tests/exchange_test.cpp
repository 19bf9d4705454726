// Files for other programs (src/gridshell/exchange/, fabrication/panel_sheets.h,
// fabrication/exchange_files.h): panels.dxf and beams.dxf read back by an independent DXF reader
// (Debian's python3-ezdxf), gridshell.glb checked by the Khronos glTF validator (npm
// gltf-validator, installed with the viewer's packages) and read back here, and the kerf offset.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <regex>
#include <set>

#include <nlohmann/json.hpp>

#include "gridshell/core/error.h"
#include "gridshell/exchange/dxf.h"
#include "gridshell/fabrication/panel_sheets.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"
#include "test_support.h"

using gridshell::PolyMesh;
using gridshell::test::read_dxf;
using gridshell::test::run_command;
using gridshell::test::run_gridshell;
using gridshell::test::slurp;
using gridshell::test::temp_dir;
using Vec2 = Eigen::Vector2d;
namespace fs = std::filesystem;

namespace {

/// A small design folder (dome, 40 cells, linear analysis), made once.
const fs::path& design_folder() {
  static const fs::path dir = [] {
    const fs::path d = temp_dir("exchange_design");
    const auto r = run_gridshell("design builtin:dome --cells 40 --seed 2 --analyze linear "
                                 "--figures none --quiet -o " + d.string());
    EXPECT_EQ(r.status, 0) << r.err;
    return d;
  }();
  return dir;
}

bool have_ezdxf() {
  return run_command("/usr/bin/python3 -c 'import ezdxf'").status == 0;
}

/// panels.svg's polygons (class, points in SVG millimetres) in file order.
std::vector<std::pair<bool, std::vector<Vec2>>> svg_polygons(const std::string& svg) {
  std::vector<std::pair<bool, std::vector<Vec2>>> out;
  const std::regex polygon("<polygon( class=\"big\")? points=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), polygon);
       it != std::sregex_iterator(); ++it) {
    std::vector<Vec2> points;
    std::istringstream in((*it)[2].str());
    std::string pair;
    while (in >> pair) {
      const auto comma = pair.find(',');
      points.emplace_back(std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1)));
    }
    out.emplace_back((*it)[1].matched, points);
  }
  return out;
}

double svg_height_mm(const std::string& svg) {
  std::smatch m;
  EXPECT_TRUE(std::regex_search(svg, m, std::regex("height=\"([0-9.]+)mm\"")));
  return std::stod(m[1].str());
}

TEST(Exchange, PanelsDxfHasTheOutlinesOfPanelsSvg) {
  if (!have_ezdxf()) SKIP_OR_FAIL_IN_CI("no python3-ezdxf: the independent DXF reader");
  const fs::path& dir = design_folder();
  const nlohmann::json dxf = read_dxf(dir / "panels.dxf");
  ASSERT_FALSE(dxf.is_null());
  EXPECT_EQ(dxf["units"], 4);  // millimetres
  EXPECT_EQ(dxf["audit_errors"], 0);
  const std::string svg = slurp(dir / "panels.svg");
  const auto polygons = svg_polygons(svg);
  const double height = svg_height_mm(svg);
  std::vector<nlohmann::json> panels;
  for (const auto& p : dxf["polylines"])
    if (p[0] == "PANELS" || p[0] == "OVERSIZE") panels.push_back(p);
  const PolyMesh mesh = gridshell::io::read_mesh(dir / "gridshell.obj").mesh;
  ASSERT_EQ(polygons.size(), static_cast<std::size_t>(mesh.num_faces()));
  ASSERT_EQ(panels.size(), polygons.size());
  double worst = 0;
  for (std::size_t k = 0; k < panels.size(); ++k) {
    EXPECT_EQ(panels[k][0] == "OVERSIZE", polygons[k].first);
    EXPECT_TRUE(panels[k][2].get<bool>());
    const auto& pts = panels[k][1];
    ASSERT_EQ(pts.size(), polygons[k].second.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      // DXF: y up from the page's bottom edge; SVG: y down from its top edge.
      const Vec2 d(pts[i][0].get<double>(), height - pts[i][1].get<double>());
      worst = std::max(worst, (d - polygons[k].second[i]).norm());
    }
  }
  EXPECT_LT(worst, 1e-3);  // millimetres: 1e-6 m
  // Every panel labelled once with its id.
  std::set<std::string> labels;
  for (const auto& t : dxf["texts"])
    if (t[0] == "LABELS") labels.insert(t[1].get<std::string>());
  EXPECT_EQ(labels.size(), polygons.size());
}

TEST(Exchange, BeamsDxfDrawsEveryCutLengthInCuttingOrder) {
  if (!have_ezdxf()) SKIP_OR_FAIL_IN_CI("no python3-ezdxf: the independent DXF reader");
  const fs::path& dir = design_folder();
  const nlohmann::json dxf = read_dxf(dir / "beams.dxf");
  ASSERT_FALSE(dxf.is_null());
  EXPECT_EQ(dxf["audit_errors"], 0);
  // beams.csv: beam,node_i,node_j,length,…
  std::istringstream csv(slurp(dir / "beams.csv"));
  std::string line;
  std::getline(csv, line);
  std::vector<double> length;
  while (std::getline(csv, line)) {
    const auto a = line.find(','), b = line.find(',', a + 1), c = line.find(',', b + 1);
    length.push_back(std::stod(line.substr(c + 1, line.find(',', c + 1) - c - 1)));
  }
  const auto& bars = dxf["polylines"];
  const auto& texts = dxf["texts"];
  ASSERT_EQ(bars.size(), length.size());
  ASSERT_EQ(texts.size(), length.size());
  std::set<int> seen;
  double previous = 1e300;
  for (std::size_t k = 0; k < bars.size(); ++k) {
    const auto& p = bars[k][1];
    const double drawn = p[1][0].get<double>() - p[0][0].get<double>();
    const int id = std::stoi(texts[k][1].get<std::string>().substr(5));  // "beam N  …"
    ASSERT_GE(id, 0);
    ASSERT_LT(id, static_cast<int>(length.size()));
    EXPECT_NEAR(drawn, 1000 * length[id], 1e-3) << "beam " << id;
    EXPECT_LE(length[id], previous + 1e-12) << "longest first (one section)";
    previous = length[id];
    seen.insert(id);
  }
  EXPECT_EQ(seen.size(), length.size());
}

/// The GLB's JSON chunk and binary chunk.
std::pair<nlohmann::json, std::string> read_glb(const fs::path& file) {
  const std::string bytes = slurp(file);
  EXPECT_GE(bytes.size(), 28u);
  std::uint32_t head[5];
  std::memcpy(head, bytes.data(), sizeof head);
  EXPECT_EQ(head[0], 0x46546C67u);  // "glTF"
  EXPECT_EQ(head[1], 2u);
  EXPECT_EQ(head[2], bytes.size());
  const std::uint32_t json_length = head[3];
  nlohmann::json j = nlohmann::json::parse(bytes.substr(20, json_length));
  std::uint32_t bin_length = 0;
  std::memcpy(&bin_length, bytes.data() + 20 + json_length, 4);
  return {j, bytes.substr(28 + json_length, bin_length)};
}

/// The float values of an accessor (tightly packed, as the writer lays them out).
std::vector<float> floats(const nlohmann::json& g, const std::string& bin, int accessor) {
  const auto& a = g["accessors"][accessor];
  const auto& v = g["bufferViews"][a["bufferView"].get<int>()];
  const int width = a["type"] == "VEC3" ? 3 : 1;
  std::vector<float> out(a["count"].get<std::size_t>() * width);
  std::memcpy(out.data(), bin.data() + v.value("byteOffset", 0), out.size() * sizeof(float));
  return out;
}

TEST(Exchange, GlbHasEveryBeamAndPanelOfTheObj) {
  const fs::path& dir = design_folder();
  const auto [g, bin] = read_glb(dir / "gridshell.glb");
  const PolyMesh mesh = gridshell::io::read_mesh(dir / "gridshell.obj").mesh;
  const auto topo = gridshell::build_topology(mesh);
  ASSERT_EQ(g["meshes"].size(), 2u);
  for (const auto& m : g["meshes"]) {
    const std::string kind = m["extras"]["kind"];
    const int expected = kind == "beams" ? topo.num_edges() : mesh.num_faces();
    EXPECT_EQ(m["extras"]["count"], expected) << kind;
    const auto& attributes = m["primitives"][0]["attributes"];
    const auto ids = floats(g, bin, attributes["_ID"].get<int>());
    std::set<int> distinct(ids.begin(), ids.end());
    EXPECT_EQ(static_cast<int>(distinct.size()), expected) << kind;
    if (kind != "panels") continue;
    // Every panel vertex is a joint of the obj, in glTF's y-up axes (x, z, −y), to float.
    const auto p = floats(g, bin, attributes["POSITION"].get<int>());
    double worst = 0;
    for (std::size_t k = 0; k < ids.size(); ++k) {
      double nearest = 1e300;
      for (int v = 0; v < mesh.num_vertices(); ++v) {
        const auto x = mesh.vertex(v);
        nearest = std::min(nearest, std::hypot(p[3 * k] - x.x(), p[3 * k + 1] - x.z(),
                                               p[3 * k + 2] + x.y()));
      }
      worst = std::max(worst, nearest);
    }
    EXPECT_LT(worst, 1e-5);
  }
}

TEST(Exchange, GlbPassesTheKhronosValidator) {
  const fs::path validator = fs::path(GRIDSHELL_WEB_DIR) / "node_modules" / "gltf-validator";
  if (!fs::exists(validator) || run_command("node --version").status != 0)
    SKIP_OR_FAIL_IN_CI("no node or web/node_modules/gltf-validator (npm ci --prefix web)");
  const fs::path script = temp_dir("exchange_validator") / "validate.cjs";
  {
    std::ofstream out(script);
    out << "const v = require(" << nlohmann::json(validator.string()).dump() << ");\n"
        << "const bytes = new Uint8Array(require('fs').readFileSync(process.argv[2]));\n"
        << "v.validateBytes(bytes).then(r => console.log(JSON.stringify({errors: "
           "r.issues.numErrors, warnings: r.issues.numWarnings, triangles: "
           "r.info.totalTriangleCount})));\n";
  }
  const auto r =
      run_command("node " + script.string() + " " + (design_folder() / "gridshell.glb").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto report = nlohmann::json::parse(r.out);
  EXPECT_EQ(report["errors"], 0) << r.out;
  EXPECT_EQ(report["warnings"], 0) << r.out;
  EXPECT_GT(report["triangles"].get<int>(), 0);
}

/// Distance from p to the line through a and b.
double line_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = (b - a).normalized();
  const Vec2 r = p - a;
  return std::abs(r.x() * d.y() - r.y() * d.x());
}

TEST(Exchange, KerfOffsetMovesEveryEdgeOutwardByTheDistance) {
  // An L-shaped (non-convex) outline, counter-clockwise.
  const std::vector<Vec2> l = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const double d = 0.05;
  const auto o = gridshell::fabrication::offset_outline(l, d);
  ASSERT_EQ(o.size(), l.size());  // right angles: mitred, no bevel
  for (std::size_t k = 0; k < l.size(); ++k) {
    const std::size_t n = (k + 1) % l.size();
    EXPECT_NEAR(line_distance(o[k], l[k], l[n]), d, 1e-12);
    EXPECT_NEAR(line_distance(o[n], l[k], l[n]), d, 1e-12);
  }
  // Outward: the offset outline encloses more area, by the perimeter × d (+ corners):
  // 5 convex corners add d² each, the one reflex corner takes d² away.
  EXPECT_NEAR(gridshell::signed_area_2d(o),
              gridshell::signed_area_2d(l) + 8 * d + 4 * d * d, 1e-12);
  // A needle-sharp corner is bevelled, not mitred far out.
  const std::vector<Vec2> needle = {{0, 0}, {10, 0.2}, {0, 0.4}};
  const auto b = gridshell::fabrication::offset_outline(needle, d);
  for (const Vec2& p : b) EXPECT_LT(p.x(), 10 + 4 * d);
}

TEST(Exchange, DxfRefusesAnUnlistedLayerAndNonFiniteNumbers) {
  const fs::path file = temp_dir("exchange_refuse") / "x.dxf";
  gridshell::exchange::DxfDrawing d;
  d.layers = {{"A", 1}};
  d.polylines.push_back({"B", {{0, 0}, {1, 0}, {1, 1}}, true});
  EXPECT_THROW(gridshell::exchange::write_dxf(file, d), gridshell::Error);
  d.polylines[0].layer = "A";
  d.polylines[0].points[1].x() = std::nan("");
  EXPECT_THROW(gridshell::exchange::write_dxf(file, d), gridshell::Error);
  EXPECT_FALSE(fs::exists(file));
}

}  // namespace
