// Cross-check of the grid-shell deflection δ against CalculiX (ccx) on a real mesh: the
// triangulation of ../shared/data/surfaces/Shell.ply with its edges as beams, the paper's load.
// CalculiX set-up (pitfalls measured by the project): its CIRC beam section is wrong, so both
// models use the same solid square (RECT) section; B32R with 4 elements per member; the section
// 1-direction given per member. Skipped when `ccx` or the shared data is missing.

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/fem/frame_element.h"
#include "gridshell/surfaces/load.h"
#include "test_support.h"

using namespace gridshell;

namespace {
bool have_ccx() {
  return std::system("command -v ccx > /dev/null 2>&1") == 0;
}

// Displacements per node id from a ccx .dat file.
std::map<int, Vec3> read_ccx_displacements(const std::filesystem::path& dat) {
  std::ifstream in(dat);
  std::map<int, Vec3> u;
  std::string line;
  bool in_block = false;
  while (std::getline(in, line)) {
    if (line.find("displacements") != std::string::npos) {
      in_block = true;
      continue;
    }
    if (!in_block) continue;
    std::istringstream ss(line);
    int id;
    double x, y, z;
    if (ss >> id >> x >> y >> z) u[id] = Vec3(x, y, z);
  }
  return u;
}
}  // namespace

TEST(FrameCcx, ShellDeflectionMatchesCalculix) {
  SKIP_WITHOUT_SHARED_DATA();
  if (!have_ccx()) GTEST_SKIP() << "ccx not installed";
  const auto path = test::shared_file("surfaces/Shell.ply");
  ASSERT_FALSE(path.empty());
  const PolySurface s = load_poly_surface(path.string());
  analysis::GridshellFrameOptions go;
  go.elements = 2;
  fem::FrameModel m = analysis::gridshell_frame(s.mesh, s.supports, go);
  // The same solid square in both codes (A and I of a square of side b; Saint-Venant J).
  const double b = 0.032;
  m.sections[0].A = b * b;
  m.sections[0].Iy = m.sections[0].Iz = b * b * b * b / 12;
  m.sections[0].J = 0.1406 * b * b * b * b;
  analysis::FrameAnalysisOptions o;
  o.buckling = o.nonlinear = false;
  const analysis::FrameResult ours = analysis::analyze_frame(m, o);

  // CalculiX deck: per member 4 B32R elements, one ELSET and section card each.
  const auto dir = test::temp_dir("frame_ccx");
  std::ostringstream inp;
  inp << "*NODE, NSET=NALL\n";
  const int n = m.num_nodes();
  for (int v = 0; v < n; ++v)
    inp << fmt::format("{},{:.12g},{:.12g},{:.12g}\n", v + 1, m.nodes(v, 0), m.nodes(v, 1),
                       m.nodes(v, 2));
  int next = n + 1;
  std::ostringstream elems, sections;
  int eid = 1;
  for (size_t k = 0; k < m.members.size(); ++k) {
    const auto& mb = m.members[k];
    const Vec3 a = m.nodes.row(mb.i).transpose(), c = m.nodes.row(mb.j).transpose();
    constexpr int kNe = 4;  // B32R elements per member in the CalculiX model
    int ids[2 * kNe + 1];
    ids[0] = mb.i + 1;
    ids[2 * kNe] = mb.j + 1;
    for (int q = 1; q < 2 * kNe; ++q) {
      const Vec3 p = a + (c - a) * (q / (2.0 * kNe));
      ids[q] = next++;
      inp << fmt::format("{},{:.12g},{:.12g},{:.12g}\n", ids[q], p.x(), p.y(), p.z());
    }
    elems << fmt::format("*ELEMENT, TYPE=B32R, ELSET=M{}\n", k);
    for (int e = 0; e < kNe; ++e)
      elems << fmt::format("{},{},{},{}\n", eid++, ids[2 * e], ids[2 * e + 1], ids[2 * e + 2]);
    const fem::Mat3 R = fem::element_frame(a, c, Vec3::Zero());
    sections << fmt::format(
        "*BEAM SECTION, ELSET=M{}, MATERIAL=STEEL, SECTION=RECT\n{},{}\n"
        "{:.12g},{:.12g},{:.12g}\n",
        k, b, b, R(0, 1), R(1, 1), R(2, 1));
  }
  inp << elems.str() << sections.str();
  inp << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11,0.3\n";
  inp << "*BOUNDARY\n";
  for (int v : s.supports) inp << fmt::format("{},1,3\n", v + 1);
  inp << "*STEP\n*STATIC\n*CLOAD\n";
  for (const auto& l : m.loads)
    for (int c = 0; c < 3; ++c)
      if (l.force(c) != 0) inp << fmt::format("{},{},{:.12g}\n", l.node + 1, c + 1, l.force(c));
  inp << "*NODE PRINT, NSET=NALL\nU\n*END STEP\n";
  {
    std::ofstream f(dir / "shell.inp");
    f << inp.str();
  }
  const std::string cmd =
      fmt::format("cd '{}' && OMP_NUM_THREADS=2 ccx -i shell > ccx.log 2>&1", dir.string());
  ASSERT_EQ(std::system(cmd.c_str()), 0) << "ccx failed, see " << dir;
  const auto u = read_ccx_displacements(dir / "shell.dat");
  ASSERT_GE(static_cast<int>(u.size()), n);
  double dccx = 0, dours = 0;
  for (int v = 0; v < n; ++v) {
    dccx = std::max(dccx, u.at(v + 1).norm());
    dours = std::max(dours, ours.displacement.row(v).norm());
  }
  RecordProperty("delta_ours_m", fmt::format("{:.6g}", dours));
  RecordProperty("delta_ccx_m", fmt::format("{:.6g}", dccx));
  std::printf("delta over joints: ours %.6g m, CalculiX %.6g m (ratio %.4f)\n", dours, dccx,
              dours / dccx);
  EXPECT_NEAR(dours / dccx, 1.0, 0.03);
}
