// Fabrication: joints, beams and panels of a grid-shell, flattened panels, nesting on sheets, and
// the files design / baseline / analyze write (joints.csv, beams.csv, panels.csv, panels.svg,
// report.json's `fabrication` block).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "gridshell/core/error.h"
#include "gridshell/core/rng.h"
#include "gridshell/fabrication/fabrication.h"
#include "gridshell/fabrication/fabrication_files.h"
#include "gridshell/fabrication/nesting.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/topology.h"
#include "test_support.h"

using gridshell::test::slurp;

using gridshell::PolyMesh;
using gridshell::Vec3;
using gridshell::fabrication::Vec2;
using gridshell::test::run_gridshell;
using gridshell::test::temp_dir;
namespace fs = std::filesystem;
namespace fab = gridshell::fabrication;

namespace {

constexpr double kPi = 3.14159265358979323846;

using Table = std::vector<std::vector<std::string>>;

/// Header + rows of a plain CSV (no quoting: the files never need it).
Table read_csv(const std::string& text, std::string* header) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  *header = line;
  Table t;
  while (std::getline(in, line)) {
    std::vector<std::string> cols;
    std::size_t start = 0;
    for (;;) {
      const std::size_t c = line.find(',', start);
      cols.push_back(line.substr(start, c - start));
      if (c == std::string::npos) break;
      start = c + 1;
    }
    t.push_back(cols);
  }
  return t;
}

std::vector<double> numbers(const std::string& field) {
  std::istringstream in(field);
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return v;
}

/// XML well-formedness, enough for the SVG we write: a prolog, balanced tags, one root, no stray
/// '<' or '&' in text. Returns an empty string or what is wrong.
std::string xml_problem(const std::string& s) {
  std::vector<std::string> stack;
  int roots = 0;
  std::size_t i = 0;
  while (i < s.size()) {
    if (s[i] != '<') {
      if (s[i] == '&') return "unescaped & at " + std::to_string(i);
      if (stack.empty() && !std::isspace(static_cast<unsigned char>(s[i])))
        return "text outside the root at " + std::to_string(i);
      ++i;
      continue;
    }
    const std::size_t j = s.find('>', i);
    if (j == std::string::npos) return "unterminated tag";
    const std::string tag = s.substr(i + 1, j - i - 1);
    if (tag.find('<') != std::string::npos) return "'<' inside a tag at " + std::to_string(i);
    i = j + 1;
    if (tag.front() == '?') {
      if (tag.back() != '?') return "bad processing instruction";
      continue;
    }
    // Quotes in attributes must balance.
    if (std::count(tag.begin(), tag.end(), '"') % 2) return "unbalanced quotes in <" + tag + ">";
    if (tag.front() == '/') {
      const std::string name = tag.substr(1);
      if (stack.empty() || stack.back() != name) return "mismatched </" + name + ">";
      stack.pop_back();
      continue;
    }
    const std::string name = tag.substr(0, tag.find_first_of(" \t\n/"));
    if (stack.empty() && ++roots > 1) return "more than one root element";
    if (tag.back() != '/') stack.push_back(name);
  }
  return stack.empty() ? "" : "unclosed <" + stack.back() + ">";
}

/// The values of the VTK DataArray called `name` in `vtp` (empty when absent).
std::vector<double> vtk_array(const std::string& vtp, const std::string& name) {
  const std::size_t at = vtp.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return {};
  const std::size_t begin = vtp.find('>', at) + 1, end = vtp.find('<', begin);
  return numbers(vtp.substr(begin, end - begin));
}

/// gridshell.vtp of a grid-shell with `t`'s edges as beams and `m`'s faces as panels: well-formed,
/// beams then panels, axial forces as in beams.csv, displacements per joint as in joints' count.
void expect_gridshell_vtp(const std::string& vtp, const PolyMesh& m, const gridshell::Topology& t,
                          const Table& beams) {
  EXPECT_EQ(xml_problem(vtp), "");
  EXPECT_NE(vtp.find(fmt::format("NumberOfPoints=\"{}\" NumberOfLines=\"{}\" NumberOfPolys=\"{}\"",
                                 m.num_vertices(), t.num_edges(), m.num_faces())),
            std::string::npos);
  const std::size_t ne = t.edges.size(), nf = m.faces.size();
  const std::vector<double> is_beam = vtk_array(vtp, "is_beam"),
                            axial = vtk_array(vtp, "axial_force");
  ASSERT_EQ(is_beam.size(), ne + nf);
  ASSERT_EQ(axial.size(), ne + nf);
  for (std::size_t e = 0; e < ne; ++e) {
    EXPECT_EQ(is_beam[e], 1.0);
    EXPECT_NEAR(axial[e], std::stod(beams[e][4]), 1e-9 * std::abs(std::stod(beams[e][4])) + 1e-9);
  }
  for (std::size_t f = 0; f < nf; ++f) EXPECT_EQ(is_beam[ne + f], 0.0);
  const std::vector<double> panel_id = vtk_array(vtp, "panel_id");
  ASSERT_EQ(panel_id.size(), ne + nf);
  EXPECT_EQ(panel_id[ne + nf - 1], static_cast<double>(nf - 1));
  EXPECT_EQ(vtk_array(vtp, "displacement").size(), 3 * static_cast<std::size_t>(m.num_vertices()));
}

/// A planar regular honeycomb: hexagons of side `s` around the origin within `rings` rings,
/// rotated by `R` into 3D and shifted; shared corners welded.
PolyMesh honeycomb(int rings, double s, const Eigen::Matrix3d& R) {
  PolyMesh m;
  std::map<std::pair<long long, long long>, int> index;
  std::vector<Vec3> V;
  const double w = std::sqrt(3.0) * s;  // distance between neighbouring centres
  for (int q = -rings; q <= rings; ++q)
    for (int r = -rings; r <= rings; ++r) {
      if (std::abs(q + r) > rings) continue;
      const Vec3 c(w * (q + 0.5 * r), w * std::sqrt(3.0) / 2 * r, 0);
      std::vector<int> face;
      for (int k = 0; k < 6; ++k) {
        const double a = kPi / 6 + k * kPi / 3;
        const Vec3 p = c + s * Vec3(std::cos(a), std::sin(a), 0);
        const auto key = std::make_pair(std::llround(p.x() * 1e6), std::llround(p.y() * 1e6));
        auto it = index.find(key);
        if (it == index.end()) {
          it = index.emplace(key, static_cast<int>(V.size())).first;
          V.push_back(p);
        }
        face.push_back(it->second);
      }
      m.faces.push_back(face);
    }
  m.V.resize(static_cast<Eigen::Index>(V.size()), 3);
  for (std::size_t v = 0; v < V.size(); ++v) m.V.row(v) = (R * V[v] + Vec3(3, -2, 5)).transpose();
  return m;
}

Eigen::Matrix3d some_rotation() {
  return (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()) *
          Eigen::AngleAxisd(-0.4, Vec3::UnitX()))
      .toRotationMatrix();
}

double edge_error(const std::vector<Vec3>& p, const std::vector<Vec2>& q) {
  double e = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double L = (p[(k + 1) % p.size()] - p[k]).norm();
    e = std::max(e, std::abs((q[(k + 1) % q.size()] - q[k]).norm() - L) / L);
  }
  return e;
}

}  // namespace

TEST(Fabrication, HexagonalGridJointsMeet120Degrees) {
  const PolyMesh m = honeycomb(2, 0.8, some_rotation());
  const gridshell::Topology t = gridshell::build_topology(m);
  const fab::Fabrication f = fab::fabrication_parts(m, t, {0});
  ASSERT_EQ(f.joints.size(), static_cast<std::size_t>(m.num_vertices()));
  ASSERT_EQ(f.beams.size(), static_cast<std::size_t>(t.num_edges()));
  ASSERT_EQ(f.panels.size(), m.faces.size());
  EXPECT_TRUE(f.joints[0].support);
  EXPECT_FALSE(f.joints[1].support);
  int inner = 0;
  for (const fab::Joint& j : f.joints) {
    double sum = 0;
    for (double a : j.angles_deg) sum += a;
    EXPECT_NEAR(sum, 360, 1e-9) << j.id;
    ASSERT_EQ(j.beams.size(), j.angles_deg.size());
    if (t.on_boundary[j.id]) continue;
    ++inner;
    ASSERT_EQ(j.valence, 3);
    for (double a : j.angles_deg) EXPECT_NEAR(a, 120, 1e-9) << j.id;
  }
  EXPECT_EQ(inner, 24);  // 19 hexagons: 54 joints, 30 of them on the boundary
  // Boundary joints of valence 2 have 120° between their beams, 240° across the open side.
  for (const fab::Joint& j : f.joints)
    if (j.valence == 2) {
      EXPECT_NEAR(std::min(j.angles_deg[0], j.angles_deg[1]), 120, 1e-9);
    }
  // One length everywhere: one length class; total length = edges × side.
  EXPECT_EQ(f.distinct_lengths, 1);
  EXPECT_NEAR(f.total_length, t.num_edges() * 0.8, 1e-9);
  // Every panel planar, a regular hexagon of side 0.8 (area 3√3/2 s²).
  for (const fab::Panel& p : f.panels) {
    EXPECT_NEAR(p.area, 1.5 * std::sqrt(3.0) * 0.64, 1e-9);
    EXPECT_LT(p.flat.planarity, 1e-12);
    EXPECT_LT(p.flat.edge_length_error, 1e-9);
  }
}

TEST(Fabrication, NonPlanarQuadPlanarityHasItsClosedForm) {
  // A unit square with its corners lifted ±h alternately: the best-fit plane is z = 0, every
  // corner is h from it, the perimeter 4 √(s² + 4h²): planarity = h / (2 √(s² + 4h²)).
  for (const double h : {0.001, 0.02, 0.1}) {
    const double s = 1.3;
    const Eigen::Matrix3d R = some_rotation();
    std::vector<Vec3> p = {{0, 0, h}, {s, 0, -h}, {s, s, h}, {0, s, -h}};
    for (Vec3& x : p) x = R * x + Vec3(1, 2, 3);
    const double expected = h / (2 * std::sqrt(s * s + 4 * h * h));
    EXPECT_NEAR(fab::panel_planarity(p), expected, 1e-12 * expected + 1e-15) << h;
    const fab::FlatPanel f = fab::flatten_panel(p);
    EXPECT_NEAR(f.planarity, expected, 1e-12 * expected + 1e-15);
    // The flattened outline keeps its edge lengths (4 lengths, 5 degrees of freedom).
    EXPECT_LT(f.edge_length_error, 1e-9) << h;
    EXPECT_LT(edge_error(p, f.outline), 1e-9) << h;
  }
}

TEST(Fabrication, FlatteningKeepsPlanarPanelsExactly) {
  gridshell::Rng rng(7);
  const Eigen::Matrix3d R = some_rotation();
  for (int trial = 0; trial < 50; ++trial) {
    // A convex polygon of 3..9 corners with random radii, rotated into 3D.
    const int n = 3 + trial % 7;
    std::vector<Vec3> p;
    std::vector<Vec2> flat;
    for (int k = 0; k < n; ++k) {
      const double a = 2 * kPi * (k + 0.3 * rng.uniform()) / n, r = 0.5 + rng.uniform();
      flat.emplace_back(r * std::cos(a), r * std::sin(a));
      p.push_back(R * Vec3(flat.back().x(), flat.back().y(), 0) + Vec3(0, 0, 4));
    }
    const fab::FlatPanel f = fab::flatten_panel(p);
    ASSERT_EQ(f.outline.size(), p.size());
    EXPECT_LT(f.planarity, 1e-12);
    // An isometry: every distance (edges and diagonals) kept to 1e-9.
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b)
        EXPECT_NEAR((f.outline[a] - f.outline[b]).norm(), (p[a] - p[b]).norm(), 1e-9);
    // Counter-clockwise seen from the normal side, first edge along +x.
    double area = 0;
    for (int k = 0; k < n; ++k)
      area += f.outline[k].x() * f.outline[(k + 1) % n].y() -
              f.outline[k].y() * f.outline[(k + 1) % n].x();
    EXPECT_GT(area, 0);
    EXPECT_NEAR(f.outline[1].y(), f.outline[0].y(), 1e-12);
    EXPECT_GT(f.outline[1].x(), f.outline[0].x());
  }
}

TEST(Fabrication, NestedPanelsStayOnTheirSheetsAndApart) {
  gridshell::Rng rng(11);
  std::vector<std::vector<Vec2>> outlines;
  for (int i = 0; i < 120; ++i) {
    const int n = 3 + i % 5;
    const double size = 0.05 + 0.35 * rng.uniform(), turn = 2 * kPi * rng.uniform();
    std::vector<Vec2> q;
    for (int k = 0; k < n; ++k) {
      const double a = turn + 2 * kPi * k / n;
      q.emplace_back(size * (1 + 0.8 * (k % 2)) * std::cos(a), size * std::sin(a));
    }
    outlines.push_back(q);
  }
  outlines.push_back({{0, 0}, {3, 0}, {3, 2}, {0, 2}});          // larger than a sheet
  outlines.push_back({{0, 0}, {0.5, 0}, {0.5, 2.0}, {0, 2.0}});  // fits only turned
  fab::SheetOptions sheet;  // 2.5 × 1.25, 10 mm gap and margin
  const fab::Nesting nest = fab::nest_panels(outlines, sheet);
  ASSERT_EQ(nest.oversize, std::vector<int>{120});
  EXPECT_EQ(nest.placements[120].sheet, -1);
  EXPECT_GE(nest.placements[121].sheet, 0);
  struct Box {
    int sheet;
    Vec2 lo, hi;
  };
  std::vector<Box> boxes;
  for (std::size_t i = 0; i < outlines.size(); ++i) {
    const fab::Placement& pl = nest.placements[i];
    if (pl.sheet < 0) continue;
    ASSERT_LT(pl.sheet, nest.sheets);
    Box b{pl.sheet, Vec2::Constant(1e300), Vec2::Constant(-1e300)};
    const auto q = fab::placed_outline(outlines[i], pl);
    for (const Vec2& x : q) b.lo = b.lo.cwiseMin(x), b.hi = b.hi.cwiseMax(x);
    // Inside the sheet, margin kept.
    EXPECT_GE(b.lo.x(), sheet.margin - 1e-9) << i;
    EXPECT_GE(b.lo.y(), sheet.margin - 1e-9) << i;
    EXPECT_LE(b.hi.x(), sheet.width - sheet.margin + 1e-9) << i;
    EXPECT_LE(b.hi.y(), sheet.height - sheet.margin + 1e-9) << i;
    // A rigid motion: the edge lengths are those of the outline.
    for (std::size_t k = 0; k < q.size(); ++k)
      EXPECT_NEAR((q[(k + 1) % q.size()] - q[k]).norm(),
                  (outlines[i][(k + 1) % q.size()] - outlines[i][k]).norm(), 1e-12);
    boxes.push_back(b);
  }
  EXPECT_EQ(boxes.size(), outlines.size() - 1);
  // No two placed outlines' bounding boxes on one sheet come closer than the gap.
  for (std::size_t a = 0; a < boxes.size(); ++a)
    for (std::size_t b = a + 1; b < boxes.size(); ++b) {
      if (boxes[a].sheet != boxes[b].sheet) continue;
      const bool apart = boxes[a].hi.x() + sheet.gap <= boxes[b].lo.x() + 1e-9 ||
                         boxes[b].hi.x() + sheet.gap <= boxes[a].lo.x() + 1e-9 ||
                         boxes[a].hi.y() + sheet.gap <= boxes[b].lo.y() + 1e-9 ||
                         boxes[b].hi.y() + sheet.gap <= boxes[a].lo.y() + 1e-9;
      EXPECT_TRUE(apart) << a << " and " << b << " overlap";
    }
  // The sheets are used: more than a third of their area is panel.
  EXPECT_GT(nest.used_area / (nest.sheets * sheet.width * sheet.height), 0.33);
  EXPECT_THROW(fab::parse_sheet("2.5"), gridshell::Error);
  EXPECT_THROW(fab::parse_sheet("0x1"), gridshell::Error);
  EXPECT_THROW(fab::parse_sheet("2x1m"), gridshell::Error);
  EXPECT_DOUBLE_EQ(fab::parse_sheet("3.21x1.6").width, 3.21);
  EXPECT_DOUBLE_EQ(fab::parse_sheet("3.21x1.6").height, 1.6);
}

TEST(Fabrication, DesignAnalyzeAndBaselineWriteTheFiles) {
  const fs::path d = temp_dir("design");
  const auto r = run_gridshell(
      "design builtin:dome --cells 60 --seed 5 --field uniform --analyze linear --quiet "
      "--sheet 6x3.21 -o " +
      d.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto file = gridshell::io::read_mesh(d / "gridshell.obj");
  const PolyMesh& m = file.mesh;
  const gridshell::Topology t = gridshell::build_topology(m);
  std::string header;
  // joints.csv: one row per vertex, positions as in the mesh.
  const Table joints = read_csv(slurp(d / "joints.csv"), &header);
  EXPECT_EQ(header, "joint,x,y,z,valence,support,beams,angles_deg");
  ASSERT_EQ(joints.size(), static_cast<std::size_t>(m.num_vertices()));
  for (const auto& row : joints) {
    ASSERT_EQ(row.size(), 8u);
    const int v = std::stoi(row[0]);
    EXPECT_NEAR(std::stod(row[1]), m.V(v, 0), 1e-9);
    EXPECT_EQ(std::stoi(row[4]), static_cast<int>(t.vertex_neighbors[v].size()));
    EXPECT_EQ(numbers(row[6]).size(), t.vertex_neighbors[v].size());
    double sum = 0;
    for (double a : numbers(row[7])) sum += a;
    EXPECT_NEAR(sum, 360, 1e-6);
  }
  // beams.csv: the CONTRACT's analyze columns first, one row per topology edge, forces present.
  const Table beams = read_csv(slurp(d / "beams.csv"), &header);
  EXPECT_EQ(header.rfind("beam,node_i,node_j,length,axial_force,utilisation,", 0), 0u) << header;
  ASSERT_EQ(beams.size(), static_cast<std::size_t>(t.num_edges()));
  for (std::size_t e = 0; e < beams.size(); ++e) {
    EXPECT_EQ(std::stoi(beams[e][1]), t.edges[e][0]);
    EXPECT_EQ(std::stoi(beams[e][2]), t.edges[e][1]);
    EXPECT_NEAR(std::stod(beams[e][3]), (m.vertex(t.edges[e][0]) - m.vertex(t.edges[e][1])).norm(),
                1e-9);
    EXPECT_FALSE(beams[e][4].empty());
    // Member checks: a cross-section utilisation is at least the axial part |N| / (A fy).
    const double A = std::numbers::pi * 0.037 * 0.037 / 4;
    EXPECT_GE(std::stod(beams[e][5]), std::abs(std::stod(beams[e][4])) / (A * 355e6) * (1 - 1e-9));
    EXPECT_GE(std::stod(beams[e][6]), 0.0);
  }
  // panels.csv: one row per face, joints in face order, outline edges = 3D edges within 1 %
  // (or the panel says how non-planar it is).
  const Table panels = read_csv(slurp(d / "panels.csv"), &header);
  EXPECT_EQ(header,
            "panel,sides,joints,area,planarity,edge_length_error,sheet,rotation_deg,offset_x,"
            "offset_y,outline,out_of_plane_mm");
  ASSERT_EQ(panels.size(), m.faces.size());
  int placed = 0;
  for (std::size_t f = 0; f < panels.size(); ++f) {
    const auto& row = panels[f];
    ASSERT_EQ(row.size(), 12u);
    std::vector<int> ids;
    for (double x : numbers(row[2])) ids.push_back(static_cast<int>(x));
    EXPECT_EQ(ids, m.faces[f]);
    const std::vector<double> xy = numbers(row[10]);
    ASSERT_EQ(xy.size(), 2 * ids.size());
    std::vector<Vec3> p;
    std::vector<Vec2> q;
    for (std::size_t k = 0; k < ids.size(); ++k) {
      p.push_back(m.vertex(ids[k]));
      q.emplace_back(xy[2 * k], xy[2 * k + 1]);
    }
    const double err = edge_error(p, q), planarity = std::stod(row[4]);
    EXPECT_TRUE(err < 0.01 || planarity > 0) << f;
    EXPECT_NEAR(err, std::stod(row[5]), 1e-6);
    placed += std::stoi(row[6]) >= 0;
  }
  // report.json's bill of materials agrees with the files.
  const auto report = nlohmann::json::parse(slurp(d / "report.json"));
  const auto& bom = report.at("fabrication");
  EXPECT_EQ(bom.at("joints").get<int>(), m.num_vertices());
  EXPECT_EQ(bom.at("beams").get<int>(), t.num_edges());
  EXPECT_EQ(bom.at("panels").get<int>(), m.num_faces());
  EXPECT_NEAR(bom.at("total_length_m").get<double>(),
              report.at("mesh").at("total_length_m").get<double>(), 1e-9);
  EXPECT_NEAR(bom.at("mass_kg").get<double>(), report.at("structure").at("mass_kg").get<double>(),
              1e-6 * bom.at("mass_kg").get<double>());
  EXPECT_EQ(bom.at("sheet_m"), nlohmann::json({6.0, 3.21}));
  EXPECT_GE(bom.at("sheets_used").get<int>(), 1);
  EXPECT_EQ(placed + static_cast<int>(bom.at("oversize_panels").size()), m.num_faces());
  EXPECT_GE(bom.at("distinct_beam_lengths").get<int>(), 1);
  EXPECT_LE(bom.at("distinct_beam_lengths").get<int>(), t.num_edges());
  // panels.svg: well-formed, one polygon per panel.
  const std::string svg = slurp(d / "panels.svg");
  EXPECT_EQ(xml_problem(svg), "");
  std::size_t polygons = 0;
  for (std::size_t at = 0; (at = svg.find("<polygon", at)) != std::string::npos; ++at) ++polygons;
  EXPECT_EQ(polygons, m.faces.size());

  // gridshell.vtp: beams with their forces, panels, joints with displacements, one numbering.
  expect_gridshell_vtp(slurp(d / "gridshell.vtp"), m, t, beams);

  // analyze: the CONTRACT's beams.csv with the fabrication columns after it, same forces.
  const fs::path a = temp_dir("analyze");
  const auto ra = run_gridshell("analyze " + (d / "gridshell.obj").string() +
                                " --analyze linear --quiet -o " + a.string());
  ASSERT_EQ(ra.status, 0) << ra.err;
  EXPECT_EQ(slurp(a / "beams.csv"), slurp(d / "beams.csv"));
  EXPECT_EQ(slurp(a / "joints.csv"), slurp(d / "joints.csv"));
  EXPECT_TRUE(fs::exists(a / "panels.csv"));
  EXPECT_TRUE(fs::exists(a / "panels.svg"));
  expect_gridshell_vtp(slurp(a / "gridshell.vtp"), m, t, beams);
  const auto ra_report = nlohmann::json::parse(slurp(a / "report.json"));
  EXPECT_EQ(ra_report.at("fabrication").at("beams").get<int>(), t.num_edges());
  EXPECT_EQ(ra_report.at("fabrication").at("sheet_m"), nlohmann::json({2.5, 1.25}));

  // baseline without analysis: the axial_force column is there but empty.
  const fs::path b = temp_dir("baseline");
  const auto rb = run_gridshell(
      "baseline builtin:dome --kind quad --length 400 --analyze none "
      "--quiet -o " +
      b.string());
  ASSERT_EQ(rb.status, 0) << rb.err;
  const Table bb = read_csv(slurp(b / "beams.csv"), &header);
  ASSERT_FALSE(bb.empty());
  EXPECT_TRUE(bb[0][4].empty());
  EXPECT_TRUE(bb[0][5].empty());
  const auto rb_report = nlohmann::json::parse(slurp(b / "report.json"));
  EXPECT_EQ(rb_report.at("fabrication").at("beams").get<std::size_t>(), bb.size());
  EXPECT_EQ(xml_problem(slurp(b / "panels.svg")), "");

  // A bad sheet is a usage error.
  const auto bad = run_gridshell("design builtin:dome --sheet 2.5 -o " + d.string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--sheet"), std::string::npos) << bad.err;
}
