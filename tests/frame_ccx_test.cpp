// Cross-check of the grid-shell deflection δ and buckling factor λ_LBA against CalculiX (ccx) on
// a real mesh: the triangulation of ../shared/data/surfaces/Shell.ply with its edges as beams,
// the paper's load.
// CalculiX set-up (pitfalls measured by the project): its CIRC beam section is wrong, so both
// models use the same solid square (RECT) section; B32R with 4 elements per member; the section
// 1-direction given per member. Skipped when `ccx` or the shared data is missing.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/fem/frame_element.h"
#include "gridshell/fem/frame_solver.h"
#include "gridshell/io/frame_model_json.h"
#include "gridshell/surfaces/load.h"
#include "ccx_support.h"
#include "test_support.h"

using namespace gridshell;
using test::have_ccx;
using test::read_ccx_displacements;

namespace {
// Calls `row` with every line of a ccx .dat file after the first one containing `header`, until
// `row` returns false.
void for_each_line_after(const std::filesystem::path& dat, const std::string& header,
                         const std::function<bool(const std::string& line)>& row) {
  std::ifstream in(dat);
  std::string line;
  bool in_block = false;
  while (std::getline(in, line)) {
    if (!in_block) {
      in_block = line.find(header) != std::string::npos;
      continue;
    }
    if (!row(line)) return;
  }
}

}  // namespace

namespace {

// Shell.ply's triangulation as a frame with the paper's load, and the same solid square section
// in both codes (A and I of a square of side b; Saint-Venant J): CalculiX's CIRC is wrong.
struct ShellFrame {
  fem::FrameModel model;
  std::vector<int> supports;
  double b = 0.032;
};
// A grid-shell as the frame both solvers analyse: 2 elements per bar, the solid square section.
ShellFrame square_section_frame(const PolySurface& s) {
  ShellFrame f;
  analysis::GridshellFrameOptions go;
  go.elements = 2;
  f.model = analysis::gridshell_frame(s.mesh, s.supports, go);
  f.supports = s.supports;
  auto& sec = f.model.sections[0];
  sec.A = f.b * f.b;
  sec.Iy = sec.Iz = f.b * f.b * f.b * f.b / 12;
  sec.J = 0.1406 * f.b * f.b * f.b * f.b;
  return f;
}
ShellFrame shell_frame() {
  return square_section_frame(
      load_poly_surface(test::shared_file("surfaces/Shell.ply").string()));
}

// CalculiX deck of the frame: per member 4 B32R elements, one ELSET and section card each; the
// step card (`*STATIC` or `*BUCKLE\nN`) with the loads; node displacements printed.
std::string ccx_deck(const ShellFrame& f, const std::string& step) {
  return test::ccx_frame_deck(f.model, f.supports, f.b, "*STEP\n" + step);
}

// Runs ccx on `deck` in a fresh folder; returns the folder (the .dat is job.dat).
std::filesystem::path run_ccx(const std::string& name, const std::string& deck) {
  const test::CcxRun run = test::run_ccx(name, deck);
  EXPECT_TRUE(run.ok) << "ccx failed, see " << run.dir;
  return run.dir;
}

// The buckling factors of a ccx .dat file (the table after "B U C K L I N G   F A C T O R").
std::vector<double> read_ccx_buckling_factors(const std::filesystem::path& dat) {
  std::vector<double> out;
  for_each_line_after(dat, "B U C K L I N G", [&](const std::string& line) {
    if (line.find("displacements") != std::string::npos) return false;
    std::istringstream ss(line);
    int mode;
    double factor;
    if (ss >> mode >> factor) out.push_back(factor);
    return true;
  });
  return out;
}

}  // namespace

TEST(FrameCcx, ShellDeflectionMatchesCalculix) {
  SKIP_WITHOUT_SHARED_DATA();
  if (!have_ccx()) SKIP_OR_FAIL_IN_CI("ccx not installed");
  const ShellFrame f = shell_frame();
  const fem::FrameModel& m = f.model;
  analysis::FrameAnalysisOptions o;
  o.buckling = o.nonlinear = false;
  const analysis::FrameResult ours = analysis::analyze_frame(m, o);
  const auto dir = run_ccx("frame_ccx", ccx_deck(f, "*STATIC"));
  const int n = m.num_nodes();
  const auto u = read_ccx_displacements(dir / "job.dat");
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

// λ_LBA of the same grid-shell frame against CalculiX's *BUCKLE (linearised buckling about the
// stress state of the load): the figure the objective search ranks designs by.
TEST(FrameCcx, ShellBucklingFactorMatchesCalculix) {
  SKIP_WITHOUT_SHARED_DATA();
  if (!have_ccx()) SKIP_OR_FAIL_IN_CI("ccx not installed");
  const ShellFrame f = shell_frame();
  analysis::FrameAnalysisOptions o;
  o.nonlinear = false;
  o.buckling_modes = 3;
  const analysis::FrameResult ours = analysis::analyze_frame(f.model, o);
  // Ours is converged in the element count: 4 elements per member instead of 2 move λ by 0.3 %.
  fem::FrameModel fine = f.model;
  for (auto& mb : fine.members) mb.elements = 4;
  const analysis::FrameResult ours4 = analysis::analyze_frame(fine, o);
  EXPECT_NEAR(*ours4.lambda_linear_buckling / *ours.lambda_linear_buckling, 1.0, 0.005);
  const auto dir = run_ccx("frame_ccx_buckle", ccx_deck(f, "*BUCKLE\n3"));
  const std::vector<double> factors = read_ccx_buckling_factors(dir / "job.dat");
  ASSERT_FALSE(factors.empty()) << "no buckling factors in " << dir;
  std::printf("lambda_LBA: ours %.6g, CalculiX %.6g (ratio %.4f); second modes %.6g / %.6g\n",
              *ours.lambda_linear_buckling, factors[0], *ours.lambda_linear_buckling / factors[0],
              ours.buckling_lambdas.size() > 1 ? ours.buckling_lambdas[1] : 0.0,
              factors.size() > 1 ? factors[1] : 0.0);
  // Measured: 364.9 against 384.7 (−5.1 %), the second mode 477.3 against 500.5 (−4.6 %). CalculiX
  // expands its beams into 20-node bricks of the section, a stiffer model of the same bar (its
  // static δ is 2.5 % smaller, test above): the two spectra agree up to that scale, so the
  // test holds the first factor within 6 % and the ratio of the first two within 1.5 %.
  ASSERT_GE(factors.size(), 2u);
  ASSERT_GE(ours.buckling_lambdas.size(), 2u);
  EXPECT_NEAR(*ours.lambda_linear_buckling / factors[0], 1.0, 0.06);
  EXPECT_NEAR((ours.buckling_lambdas[1] / ours.buckling_lambdas[0]) / (factors[1] / factors[0]),
              1.0, 0.015);
}

namespace {
// Axial stress e1ᵀ S e1 at the 2 × 2 × 2 Gauss points of each B32R's expanded brick in a ccx .dat
// (`stresses (elem, integ.pnt.,sxx,syy,szz,sxy,sxz,syz)`), per element id: the largest
// magnitude. CalculiX 2.20 prints 50 points per B32R with a RECT section; points 1–8 are the
// brick's Gauss points (checked by hand on a cantilever: pure N gives N/A at all eight, a tip
// load F gives F (L − x) (b / 2√3) / I at x = (1 ∓ 1/√3) l / 2 to 5 digits).
std::map<int, double> read_ccx_max_axial_stress(const std::filesystem::path& dat,
                                                const std::map<int, Vec3>& axis) {
  std::map<int, double> out;
  for_each_line_after(dat, "stresses", [&](const std::string& line) {
    std::istringstream ss(line);
    int e, ip;
    double s[6];
    if (!(ss >> e >> ip >> s[0] >> s[1] >> s[2] >> s[3] >> s[4] >> s[5])) return true;
    if (ip > 8) return true;  // 1–8: the brick's 2 × 2 × 2 Gauss points; then section points
    fem::Mat3 S;
    S << s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2];
    const Vec3& a = axis.at(e);
    out[e] = std::max(out[e], std::abs(a.dot(S * a)));
    return true;
  });
  return out;
}
}  // namespace

// The member checks' section forces against CalculiX on a Voronoi grid-shell (the built-in dome
// designed with 60 cells, the paper's load, the solid square section of the tests above): at
// each of CalculiX's integration points (B32R → 20-node bricks, 2 × 2 points in the section at
// ±b/(2√3), two stations per element along the axis) beam theory gives the axial stress
// N/A ± My z/I ± Mz y/I; the largest over a member's points is |N|/A + (|My(s)| + |Mz(s)|) c / I
// at its worst station. Ours from our N, My, Mz (moments linear along each of our elements),
// CalculiX's read from its stresses: compared member by member.
TEST(FrameCcx, GridshellSectionForcesMatchCalculixStresses) {
  if (!have_ccx()) SKIP_OR_FAIL_IN_CI("ccx not installed");
  const auto design_dir = test::temp_dir("checks_ccx_design");
  const auto run = test::run_gridshell(
      "design builtin:dome --cells 60 --field uniform --seed 5 --analyze none --quiet -o " +
      design_dir.string());
  ASSERT_EQ(run.status, 0) << run.err;
  const auto obj = design_dir / "gridshell.obj";
  PolySurface s = load_poly_surface(obj.string());
  s.supports = io::read_obj_supports_comment(obj);
  ASSERT_FALSE(s.supports.empty());
  const ShellFrame f = square_section_frame(s);
  const fem::FrameModel& m = f.model;
  const int members = static_cast<int>(m.members.size());

  // Ours: section forces per element end of the linear solution.
  const fem::FrameMesh mesh = fem::discretize(m);
  const fem::FrameAssembler assembler(mesh);
  const fem::LinearResult lin = fem::linear_static(mesh, assembler);
  const auto forces = fem::element_section_forces(mesh, assembler, lin.u);
  const fem::FrameSection& sec = m.sections[0];
  const double c = f.b / (2 * std::sqrt(3.0)), A = sec.A, I = sec.Iy;
  // Largest |σ| over the section points at position t ∈ [0, 1] along member k.
  const auto ours_at = [&](int k, double t) {
    const auto& els = mesh.member_elements[k];
    const double x = t * els.size();
    const int q = std::min(static_cast<int>(x), static_cast<int>(els.size()) - 1);
    const double u = x - q;
    const fem::ElementSectionForces& e = forces[els[q]];
    // Internal moment along the element: −m_i at its start, m_j at its end (end-force signs).
    const double My = -e.My[0] * (1 - u) + e.My[1] * u, Mz = -e.Mz[0] * (1 - u) + e.Mz[1] * u;
    return std::abs(e.N) / A + (std::abs(My) + std::abs(Mz)) * c / I;
  };

  // CalculiX: the deck of the tests above with the stresses printed.
  std::string deck = ccx_deck(f, "*STATIC");
  const std::string print = "*NODE PRINT, NSET=NALL\nU\n";
  deck.replace(deck.find(print), print.size(), "*EL PRINT, ELSET=EALL\nS\n");
  deck.insert(deck.find("*MATERIAL"),
              fmt::format("*ELSET, ELSET=EALL, GENERATE\n1,{},1\n", 4 * members));
  const auto dir = run_ccx("checks_ccx", deck);
  std::map<int, Vec3> axis;
  for (int k = 0; k < members; ++k)
    for (int q = 0; q < 4; ++q)
      axis[4 * k + q + 1] =
          (m.nodes.row(m.members[k].j) - m.nodes.row(m.members[k].i)).transpose().normalized();
  const auto ccx = read_ccx_max_axial_stress(dir / "job.dat", axis);
  ASSERT_EQ(static_cast<int>(ccx.size()), 4 * members) << "stresses missing in " << dir;

  std::vector<double> theirs(members, 0.0), ours(members, 0.0);
  const double g = 0.5 / std::sqrt(3.0);
  for (int k = 0; k < members; ++k)
    for (int q = 0; q < 4; ++q) {
      theirs[k] = std::max(theirs[k], ccx.at(4 * k + q + 1));
      for (double t : {(q + 0.5 - g) / 4, (q + 0.5 + g) / 4})
        ours[k] = std::max(ours[k], ours_at(k, t));
    }
  const double peak = *std::max_element(theirs.begin(), theirs.end());
  std::vector<double> err;
  double worst = 0;
  for (int k = 0; k < members; ++k) {
    if (theirs[k] < 0.1 * peak) continue;
    err.push_back(std::abs(ours[k] / theirs[k] - 1));
    worst = std::max(worst, err.back());
  }
  std::sort(err.begin(), err.end());
  const double median = err[err.size() / 2], p90 = err[err.size() * 9 / 10];
  const double ours_peak = *std::max_element(ours.begin(), ours.end());
  std::printf(
      "section stresses on %d members (%zu above 10 %% of the peak): peak ours %.5g, CalculiX "
      "%.5g Pa (ratio %.4f); per member |ratio − 1| median %.4f, 90th percentile %.4f, worst "
      "%.4f\n",
      members, err.size(), ours_peak, peak, ours_peak / peak, median, p90, worst);
  // Measured: peak 4.487e7 against 4.505e7 Pa (−0.4 %); per member median 0.6 %, 90th
  // percentile 1.8 %, worst 11 % (one member; CalculiX's brick has shear deformation and 3D
  // effects that our Euler–Bernoulli element lacks).
  EXPECT_NEAR(ours_peak / peak, 1.0, 0.02);
  EXPECT_LT(median, 0.015);
  EXPECT_LT(p90, 0.04);
}
