// Member sizing (sizing/sizing.h, `--size`): a sized design passes every check of every
// combination, also when its frame.json is analysed again; its figures agree with CalculiX; its
// mass is Σ length × the series' mass per metre; a list that cannot carry the loads ends with
// "sized": false and the failing check named — never a design that looks safe.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "ccx_support.h"
#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/fem/frame_solver.h"
#include "gridshell/io/frame_model_json.h"
#include "gridshell/sections/sections.h"
#include "gridshell/sizing/sizing.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace gridshell;
using test::read_json;

namespace {

/// A small dome (60 cells), eurocode loads, sized to the hot-finished CHS series at LBA level.
constexpr const char* kDome =
    "design builtin:dome --cells 60 -D 1 -A 1 --seed 1 --analyze buckling --quiet --figures none ";

const fs::path& sized_dome() {
  static const fs::path dir = [] {
    const fs::path d = test::temp_dir("sized_dome");
    const auto r = test::run_gridshell(std::string(kDome) + "--size -o " + d.string());
    EXPECT_EQ(r.status, 0) << r.err;
    return d;
  }();
  return dir;
}

struct BeamRow {
  double length = 0, utilisation = 0, buckling = 0;
  std::string section, governing;
};
std::vector<BeamRow> read_beams(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in,
               line);  // beam,node_i,node_j,length,axial_force,utilisation,buckling_utilisation,
                       // length_class,panels,section,governing
  std::vector<BeamRow> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (cells.size() < 10) continue;
    rows.push_back({std::stod(cells[3]), std::stod(cells[5]), std::stod(cells[6]), cells[9],
                    cells.size() > 10 ? cells[10] : std::string()});
  }
  return rows;
}

}  // namespace

TEST(Sizing, SizedDomePassesEveryCombinationAndItsOwnReanalysis) {
  const fs::path d = sized_dome();
  const auto report = read_json(d / "report.json");
  ASSERT_TRUE(report.contains("sizing"));
  const auto& s = report["sizing"];
  EXPECT_TRUE(s["sized"].get<bool>()) << s.value("failure", "");
  EXPECT_EQ(report["structure"]["loads"], "eurocode");  // --size without --loads
  const auto& g = report["structure"]["governing"];
  EXPECT_TRUE(g["pass"].get<bool>());
  // Every combination's own figures, not just the governing summary.
  for (const auto& [name, c] : report["structure"]["combinations"].items()) {
    EXPECT_LE(c["utilisation_max"].get<double>(), 1.0) << name;
    EXPECT_LE(c["buckling_utilisation_max"].get<double>(), 1.0) << name;
    if (!c.value("uls", false)) {
      EXPECT_LE(c["delta_max_m"].get<double>(), c["delta_limit_m"].get<double>() * (1 + 1e-12))
          << name;
    } else {
      EXPECT_GE(c["lambda"].get<double>(), 1.0) << name;
    }
  }
  // Re-analysed from its own frame.json: the same verdicts and figures.
  const fs::path a = test::temp_dir("sized_dome_analyze");
  const auto r = test::run_gridshell("analyze " + (d / "frame.json").string() +
                                     " --analyze buckling --quiet --figures none -o " + a.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto ga = read_json(a / "report.json")["structure"]["governing"];
  EXPECT_TRUE(ga["pass"].get<bool>());
  EXPECT_NEAR(ga["utilisation_value"].get<double>(), g["utilisation_value"].get<double>(),
              1e-6 * g["utilisation_value"].get<double>());
  EXPECT_NEAR(ga["delta_m"].get<double>(), g["delta_m"].get<double>(),
              1e-6 * g["delta_m"].get<double>());
  EXPECT_NEAR(ga["lambda_value"].get<double>(), g["lambda_value"].get<double>(),
              1e-4 * g["lambda_value"].get<double>());
}

TEST(Sizing, MassIsLengthTimesTheSeriesMassPerMetre) {
  const fs::path d = sized_dome();
  const auto report = read_json(d / "report.json");
  const std::vector<BeamRow> beams = read_beams(d / "beams.csv");
  ASSERT_FALSE(beams.empty());
  // CHS of outside diameter D and wall t: A = π (D − t) t, 7850 kg/m³ (the tables' density).
  double mass = 0;
  std::set<std::string> distinct;
  for (const BeamRow& b : beams) {
    const sections::Section s = sections::parse_section(b.section);
    ASSERT_EQ(s.shape, sections::Shape::chs) << b.section;
    EXPECT_TRUE(sections::is_standard(s)) << b.section;
    mass += std::numbers::pi * (s.h - s.t) * s.t * 7850 * b.length;
    distinct.insert(b.section);
    EXPECT_LE(std::max(b.utilisation, b.buckling), 1.0) << b.section;
    // The envelope over the ULS combinations names its clause and combination.
    EXPECT_NE(b.governing.find(" under ULS"), std::string::npos) << b.governing;
  }
  EXPECT_NEAR(report["sizing"]["mass_kg"].get<double>(), mass, 1e-9 * mass);
  EXPECT_NEAR(report["mass"]["mass_kg"].get<double>(), mass, 1e-9 * mass);
  EXPECT_NEAR(report["fabrication"]["mass_kg"].get<double>(), mass, 1e-9 * mass);
  EXPECT_EQ(report["sizing"]["distinct_sections"].get<int>(), static_cast<int>(distinct.size()));
  EXPECT_EQ(report["sizing"]["sections_distinct"].get<int>(), static_cast<int>(distinct.size()));
  EXPECT_EQ(report["buildability"]["sections_distinct"].get<int>(),
            static_cast<int>(distinct.size()));
  EXPECT_GT(distinct.size(), 1u);  // sized per member: not one section for all
  EXPECT_NEAR(report["sizing"]["carbon_kgCO2e"].get<double>(), 1.55 * mass, 1e-9 * mass);
  EXPECT_NEAR(report["sizing"]["carbon_kgco2e"].get<double>(), 1.55 * mass, 1e-9 * mass);
  const double plan = report["sizing"]["plan_area_m2"].get<double>();
  EXPECT_NEAR(report["sizing"]["mass_kg_per_m2"].get<double>(), mass / plan, 1e-9 * mass / plan);
}

TEST(Sizing, SizedDomeAgreesWithCalculix) {
  if (!test::have_ccx()) SKIP_OR_FAIL_IN_CI("ccx not installed");
  const fs::path d = sized_dome();
  // The ULS combination of the sized frame, each member its own CHS (a PIPE section in ccx).
  const io::FrameModelFile f = io::read_frame_model(d / "frame.json", 2);
  std::vector<int> supports;
  for (const auto& s : f.model.supports) supports.push_back(s.node);
  const auto card = [&](std::size_t k) {
    const sections::Section& p = *f.model.sections[f.model.members[k].section].profile;
    return fmt::format("PIPE\n{:.12g},{:.12g}", p.h / 2, p.t);
  };
  analysis::FrameAnalysisOptions o;
  o.nonlinear = false;
  const analysis::FrameResult ours = analysis::analyze_frame(f.model, o);
  const test::CcxRun stat =
      test::run_ccx("sized_ccx", test::ccx_frame_deck(f.model, supports, card, "*STEP\n*STATIC"));
  ASSERT_TRUE(stat.ok) << stat.dir;
  const auto u = test::read_ccx_displacements(stat.dir / "job.dat");
  double dccx = 0;
  for (int v = 0; v < f.model.num_nodes(); ++v) dccx = std::max(dccx, u.at(v + 1).norm());
  std::printf("sized dome delta: ours %.6g m, CalculiX %.6g m\n", ours.delta_max_m, dccx);
  // CalculiX expands a PIPE into brick elements around an approximate ring: a cantilever
  // CHS 88.9x4.0 (2 B32R) deflects 12.45 mm where the closed form P L³ / 3EI (which our
  // element reproduces exactly) gives 13.18 mm — 5.5 % stiff. Hence 8 % here; measured 6.0 %.
  EXPECT_GT(ours.delta_max_m, dccx);
  EXPECT_NEAR(ours.delta_max_m / dccx, 1.0, 0.08);
  const test::CcxRun buck = test::run_ccx(
      "sized_ccx_buckle", test::ccx_frame_deck(f.model, supports, card, "*STEP\n*BUCKLE\n3"));
  ASSERT_TRUE(buck.ok) << buck.dir;
  std::ifstream dat(buck.dir / "job.dat");
  std::string line;
  double lambda_ccx = 0;
  bool table = false;
  while (std::getline(dat, line) && lambda_ccx == 0) {
    if (line.find("B U C K L I N G") != std::string::npos) table = true;
    std::istringstream ss(line);
    int mode = 0;
    double factor = 0;
    if (table && ss >> mode >> factor && mode == 1) lambda_ccx = factor;
  }
  ASSERT_TRUE(ours.lambda_linear_buckling);
  std::printf("sized dome lambda_LBA: ours %.6g, CalculiX %.6g\n", *ours.lambda_linear_buckling,
              lambda_ccx);
  EXPECT_NEAR(*ours.lambda_linear_buckling / lambda_ccx, 1.0, 0.05);
}

// The sized frame's member forces against CalculiX: each member's axial force N under the ULS
// combination of frame.json. CalculiX expands a PIPE into bricks with 16 integration points per
// B32R on rings of the section; bending cancels in their mean (the points lie symmetrically
// around the axis and N is constant along a member loaded at its ends), so N = A × the mean
// axial stress e₁ᵀ S e₁ over the member's points. Checked by hand on one CHS 88.9x4.0 in
// tension: the mean is F / A to 5 digits.
TEST(Sizing, SizedDomeMemberForcesAgreeWithCalculix) {
  if (!test::have_ccx()) SKIP_OR_FAIL_IN_CI("ccx not installed");
  const io::FrameModelFile f = io::read_frame_model(sized_dome() / "frame.json", 2);
  const fem::FrameModel& m = f.model;
  std::vector<int> supports;
  for (const auto& s : m.supports) supports.push_back(s.node);
  const auto profile = [&](std::size_t k) -> const sections::Section& {
    return *m.sections[m.members[k].section].profile;
  };
  const auto card = [&](std::size_t k) {
    return fmt::format("PIPE\n{:.12g},{:.12g}", profile(k).h / 2, profile(k).t);
  };
  // Ours: the linear solution's axial force per member (constant along it).
  const fem::FrameMesh mesh = fem::discretize(m);
  const fem::FrameAssembler assembler(mesh);
  const fem::LinearResult lin = fem::linear_static(mesh, assembler);
  const auto forces = fem::element_section_forces(mesh, assembler, lin.u);
  const int members = static_cast<int>(m.members.size());
  std::vector<double> ours(members);
  for (int k = 0; k < members; ++k) ours[k] = forces[mesh.member_elements[k].front()].N;

  std::string deck = test::ccx_frame_deck(m, supports, card, "*STEP\n*STATIC");
  const std::string print = "*NODE PRINT, NSET=NALL\nU\n";
  deck.replace(deck.find(print), print.size(), "*EL PRINT, ELSET=EALL\nS\n");
  deck.insert(deck.find("*MATERIAL"),
              fmt::format("*ELSET, ELSET=EALL, GENERATE\n1,{},1\n", 4 * members));
  const test::CcxRun run = test::run_ccx("sized_ccx_forces", deck);
  ASSERT_TRUE(run.ok) << run.dir;
  std::vector<double> sum(members, 0.0);
  std::vector<int> count(members, 0);
  std::ifstream dat(run.dir / "job.dat");
  std::string line;
  bool table = false;
  while (std::getline(dat, line)) {
    if (line.find("stresses") != std::string::npos) table = true;
    std::istringstream ss(line);
    int e, ip;
    double s[6];
    if (!table || !(ss >> e >> ip >> s[0] >> s[1] >> s[2] >> s[3] >> s[4] >> s[5])) continue;
    const int k = (e - 1) / 4;
    const auto& mb = m.members[k];
    const Vec3 a = (m.nodes.row(mb.j) - m.nodes.row(mb.i)).transpose().normalized();
    fem::Mat3 S;
    S << s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2];
    sum[k] += a.dot(S * a);
    ++count[k];
  }
  double peak = 0;
  for (int k = 0; k < members; ++k) {
    ASSERT_EQ(count[k], 4 * 16) << "member " << k << ": stresses missing in " << run.dir;
    peak = std::max(peak, std::abs(ours[k]));
  }
  std::vector<double> err;
  double worst = 0;
  for (int k = 0; k < members; ++k) {
    const double theirs = m.sections[m.members[k].section].A * sum[k] / count[k];
    if (std::abs(theirs) < 0.1 * peak) continue;  // small forces: relative error meaningless
    EXPECT_GT(ours[k] * theirs, 0) << "member " << k << ": tension and compression disagree";
    err.push_back(std::abs(ours[k] / theirs - 1));
    worst = std::max(worst, err.back());
  }
  ASSERT_GT(err.size(), 30u);
  std::sort(err.begin(), err.end());
  const double median = err[err.size() / 2], p90 = err[err.size() * 9 / 10];
  std::printf("sized dome axial forces, %zu members above 10 %% of the peak %.4g N: |ratio - 1| "
              "median %.4f, 90th percentile %.4f, worst %.4f\n",
              err.size(), peak, median, p90, worst);
  // The frame is statically indeterminate: CalculiX's bricks are 5.5 % stiffer in bending and
  // 0.7 % softer axially than the Euler–Bernoulli bar (a single CHS, checked by hand), which
  // moves a little force between members. Measured on 156 members: median 0.11 %, 90th
  // percentile 0.39 %, worst 1.0 %.
  EXPECT_LT(median, 0.01);
  EXPECT_LT(p90, 0.02);
}

TEST(Sizing, SectionGroupsBoundTheDistinctSections) {
  const fs::path d = test::temp_dir("sized_groups");
  const auto r =
      test::run_gridshell(std::string(kDome) + "--size --section-groups 2 -o " + d.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto report = read_json(d / "report.json");
  EXPECT_TRUE(report["sizing"]["sized"].get<bool>()) << report["sizing"].value("failure", "");
  EXPECT_LE(report["sizing"]["distinct_sections"].get<int>(), 2);
  EXPECT_TRUE(report["structure"]["governing"]["pass"].get<bool>());
  // Fewer sections cost steel: never lighter than each member its own.
  EXPECT_GE(
      report["sizing"]["mass_kg"].get<double>(),
      read_json(sized_dome() / "report.json")["sizing"]["mass_kg"].get<double>() * (1 - 1e-9));
}

TEST(Sizing, AListThatCannotCarryTheLoadsSaysSoAndWhere) {
  const fs::path d = test::temp_dir("sized_fail");
  const fs::path list = d / "sections.txt";
  std::ofstream(list) << "# too small for a 20 m dome\nCHS 21.3x2.0\nCHS 26.9x2.3\n";
  const fs::path out = d / "out";
  const auto r = test::run_gridshell(std::string(kDome) + "--size --sections " + list.string() +
                                     " -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto report = read_json(out / "report.json");
  EXPECT_FALSE(report["sizing"]["sized"].get<bool>());
  const std::string failure = report["sizing"]["failure"];
  EXPECT_FALSE(failure.empty());
  EXPECT_EQ(report["sizing"]["failing_check"], failure);  // CONTRACT.md's key
  EXPECT_NE(r.err.find("not sized"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(failure), std::string::npos) << r.err;
  EXPECT_FALSE(report["structure"]["governing"]["pass"].get<bool>());
}

TEST(Sizing, BadSizingOptionsAreOneLineErrors) {
  const fs::path d = test::temp_dir("sized_bad");
  for (const std::string& bad : {std::string("--sections ") + (d / "missing.txt").string(),
                                 std::string("--section-groups -1"), std::string("--lambda-min 0"),
                                 std::string("--carbon-factor -2")}) {
    const auto r =
        test::run_gridshell(std::string(kDome) + "--size " + bad + " -o " + (d / "out").string());
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << bad << ": " << r.err;
  }
  const fs::path bad_list = d / "bad.txt";
  std::ofstream(bad_list) << "CHS 88.9x4.0\nHEB 200\n";
  const auto r = test::run_gridshell(std::string(kDome) + "--size --sections " + bad_list.string() +
                                     " -o " + (d / "out").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(":2"), std::string::npos) << r.err;  // names the line
}

TEST(Sizing, SectionListsParse) {
  EXPECT_EQ(sizing::parse_section_list("chs"), sections::series(sections::Shape::chs));
  EXPECT_EQ(sizing::parse_section_list("rhs cold"),
            sections::series(sections::Shape::rhs, sections::Process::cold));
}

TEST(Sizing, AnalyzeSizesAGridshellMeshAsDesignDoes) {
  const fs::path d = sized_dome();
  const fs::path a = test::temp_dir("sized_analyze_mesh");
  const auto r = test::run_gridshell("analyze " + (d / "gridshell.obj").string() +
                                     " --size --analyze buckling --quiet --figures none -o " +
                                     a.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto mine = read_json(a / "report.json");
  const auto designed = read_json(d / "report.json");
  EXPECT_TRUE(mine["sizing"]["sized"].get<bool>());
  EXPECT_NEAR(mine["sizing"]["mass_kg"].get<double>(), designed["sizing"]["mass_kg"].get<double>(),
              1e-9 * designed["sizing"]["mass_kg"].get<double>());
  // A MODEL.json keeps its own sections.
  const auto j = test::run_gridshell("analyze " + (d / "frame.json").string() + " --size -o " +
                                     (a / "json").string());
  EXPECT_EQ(j.status, 2);
  EXPECT_NE(j.err.find("--size"), std::string::npos) << j.err;
}

TEST(Sizing, ConfigRepeatsASizedDesign) {
  // config.json leaves the implied --loads out, so --config sizes under the same loads.
  const fs::path d = sized_dome();
  const fs::path again = test::temp_dir("sized_again");
  const auto r = test::run_gridshell("design --config " + (d / "config.json").string() +
                                     " --quiet --figures none -o " + again.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto a = read_json(d / "report.json"), b = read_json(again / "report.json");
  EXPECT_EQ(b["structure"]["loads"], "eurocode");
  EXPECT_EQ(a["sizing"]["mass_kg"].get<double>(), b["sizing"]["mass_kg"].get<double>());
}

TEST(Sizing, ASizedBaselineChecksTheImperfectPathAsDesignDoes) {
  // At the non-linear level, --size holds λ ≥ λ_min with the unfavourable imperfection
  // (docs/sizing.md) for a baseline as for a design; unsized, a baseline follows the perfect
  // path only.
  const fs::path d = test::temp_dir("sized_baseline");
  const std::string quad = "baseline builtin:dome --kind quad --length 150 --quiet --figures none ";
  const auto r = test::run_gridshell(quad + "--size -o " + d.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto report = read_json(d / "report.json");
  ASSERT_TRUE(report["sizing"]["sized"].get<bool>());
  const auto& governing = report["structure"]["governing"];
  const auto& weakest = report["structure"]["combinations"][governing["lambda"].get<std::string>()];
  ASSERT_TRUE(weakest["lambda_imperfect"].is_number()) << weakest.dump();
  const double imperfect = weakest["lambda_imperfect"].get<double>();
  const double perfect = weakest["lambda_perfect"].get<double>();
  EXPECT_DOUBLE_EQ(governing["lambda_value"].get<double>(), std::min(imperfect, perfect));
  EXPECT_GE(governing["lambda_value"].get<double>(), 1.0);
  EXPECT_TRUE(report["structure"]["imperfection"]["tried"].is_array());  // the signs and modes

  const fs::path u = test::temp_dir("unsized_baseline");
  const auto plain = test::run_gridshell(quad + "-o " + u.string());
  ASSERT_EQ(plain.status, 0) << plain.err;
  const auto unsized = read_json(u / "report.json")["structure"];
  EXPECT_TRUE(unsized["lambda_imperfect"].is_null());
  EXPECT_TRUE(unsized["lambda_perfect"].is_number());
}
