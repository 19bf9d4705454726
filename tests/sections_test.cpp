// Steel sections (sections/sections.h): properties of standard sizes against the steel makers'
// published tables, designations, parsing and its errors, the catalogues.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "gridshell/core/error.h"
#include "gridshell/fem/frame_model.h"
#include "gridshell/sections/sections.h"

using namespace gridshell;
using namespace gridshell::sections;

namespace {

/// A tabulated row in the tables' units: kg/m, cm², cm⁴, cm³, cm. NaN = not in that table.
struct Row {
  double M, A, Iy, Iz, Wely, Welz, Wply, Wplz, It, Wt;
};
constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

/// Every property within 0.5 % of the table (which rounds to 3 or 4 significant digits).
void expect_table(const Section& s, const Row& r) {
  SCOPED_TRACE(designation(s));
  const SectionProperties p = properties(s);
  const auto near = [](double computed, double table, const char* what) {
    if (std::isnan(table)) return;
    EXPECT_NEAR(computed, table, 0.005 * table) << what;
  };
  near(p.mass, r.M, "mass");
  near(p.A * 1e4, r.A, "A");
  near(p.Iy * 1e8, r.Iy, "Iy");
  near(p.Iz * 1e8, r.Iz, "Iz");
  near(p.Wel_y * 1e6, r.Wely, "Wel,y");
  near(p.Wel_z * 1e6, r.Welz, "Wel,z");
  near(p.Wpl_y * 1e6, r.Wply, "Wpl,y");
  near(p.Wpl_z * 1e6, r.Wplz, "Wpl,z");
  near(p.It * 1e8, r.It, "It");
  near(p.Wt * 1e6, r.Wt, "Wt");
}

}  // namespace

// Hot-finished SHS, EN 10210-2 (ro = 1.5t, ri = t): Tata Steel "blue book", Celsius 355 SHS,
// dimensions and properties (BS EN 10210-2:2006), and amesweb's EN 10210-2 SHS table (80x80x5).
TEST(Sections, HotFinishedSquareHollowSectionsMatchTheTables) {
  expect_table(rhs(0.040, 0.040, 0.0032), {3.61, 4.60, 10.2, 10.2, 5.11, 5.11, 6.28, 6.28, 16.5, 7.42});
  expect_table(rhs(0.050, 0.050, 0.005), {6.85, 8.73, 28.9, 28.9, 11.6, 11.6, 14.5, 14.5, 47.6, 16.7});
  expect_table(rhs(0.060, 0.060, 0.0063),
               {10.3, 13.1, 61.6, 61.6, 20.5, 20.5, 26.0, 26.0, 102, 29.6});
  expect_table(rhs(0.080, 0.080, 0.005), {11.6, 14.7, 137, 137, 34.2, 34.2, 41.1, 41.1, 217, 49.8});
}

// Cold-formed SHS, EN 10219-2 (ro = 2t for t ≤ 6 mm): SSAB Domex Tube structural hollow
// sections, Table 1 "square hollow sections" (R = 2.0 T, T ≤ 6 mm; Iv, Wv the torsion constants).
TEST(Sections, ColdFormedSquareHollowSectionsMatchTheTables) {
  expect_table(rhs(0.050, 0.050, 0.004, Process::cold),
               {5.45, 6.95, 23.74, 23.74, 9.49, 9.49, 11.73, 11.73, 40.42, 14.43});
  expect_table(rhs(0.060, 0.060, 0.005, Process::cold),
               {8.13, 10.36, 50.49, 50.49, 16.83, 16.83, 20.88, 20.88, 86.42, 25.61});
}

// Cold-formed RHS, EN 10219 (r1 = 2t): b2bmetal.eu "Rectangular structural hollow sections of
// EN 10219" (x = the strong axis = our y, along the height h).
TEST(Sections, ColdFormedRectangularHollowSectionsMatchTheTables) {
  expect_table(rhs(0.060, 0.040, 0.003, Process::cold),
               {4.25, 5.41, 25.38, 13.44, 8.46, 6.72, 10.53, 7.94, 29.28, 11.17});
  expect_table(rhs(0.050, 0.030, 0.004, Process::cold),
               {4.20, 5.35, 15.25, 6.69, 6.10, 4.46, 8.05, 5.58, 16.53, 7.71});
}

// CHS: Tata Steel blue book, Celsius 355 CHS (EN 10210-2); EN 10219-2 tabulates the same
// nominal geometry (a CHS has no corners), so the cold-formed one must agree too.
TEST(Sections, CircularHollowSectionsMatchTheTables) {
  for (Process process : {Process::hot, Process::cold}) {
    expect_table(chs(0.0889, 0.004, process),
                 {8.38, 10.7, 96.3, 96.3, 21.7, 21.7, 28.9, 28.9, 193, 43.3});
    expect_table(chs(0.1143, 0.005, process),
                 {13.5, 17.2, 257, 257, 45.0, 45.0, 59.8, 59.8, 514, 89.9});
  }
}

TEST(Sections, RectangularAxesFollowHeightAndWidth) {
  const SectionProperties p = properties(rhs(0.120, 0.060, 0.004));
  EXPECT_GT(p.Iy, 2.5 * p.Iz);  // height along z: strong axis y
  EXPECT_NEAR(p.Av_z / p.Av_y, 2.0, 1e-12);   // A h/(b+h) over A b/(b+h)
  const SectionProperties q = properties(rhs(0.060, 0.120, 0.004));
  EXPECT_NEAR(q.Iz, p.Iy, 1e-12 * p.Iy);      // the same tube lying flat
}

TEST(Sections, BarIsTheSolidCircle) {
  const SectionProperties p = properties(bar(0.037));
  EXPECT_NEAR(p.A, std::numbers::pi * 0.037 * 0.037 / 4, 1e-15);
  EXPECT_NEAR(p.Wpl_y, std::pow(0.037, 3) / 6, 1e-15);
  const fem::FrameSection f = fem::profile_section(bar(0.037));
  const fem::FrameSection c = fem::circle_section(0.037);
  EXPECT_EQ(f.A, c.A);
  EXPECT_EQ(f.Iy, c.Iy);
  EXPECT_EQ(f.J, c.J);
}

TEST(Sections, CornerRadiiFollowTheStandards) {
  EXPECT_DOUBLE_EQ(corner_radii(0.005, Process::hot).first, 0.0075);
  EXPECT_DOUBLE_EQ(corner_radii(0.005, Process::hot).second, 0.005);
  EXPECT_DOUBLE_EQ(corner_radii(0.006, Process::cold).first, 0.012);   // 2t, t ≤ 6
  EXPECT_DOUBLE_EQ(corner_radii(0.008, Process::cold).first, 0.020);   // 2.5t
  EXPECT_DOUBLE_EQ(corner_radii(0.0125, Process::cold).first, 0.0375); // 3t
  EXPECT_DOUBLE_EQ(corner_radii(0.0125, Process::cold).second, 0.025);
}

TEST(Sections, ParsesTheSeriesDesignations) {
  const Section a = parse_section("CHS 88.9x4.0");
  EXPECT_EQ(a, chs(0.0889, 0.004));
  EXPECT_EQ(designation(a), "CHS 88.9x4.0");
  EXPECT_TRUE(is_standard(a));
  const Section b = parse_section("rhs 120X60x4 cold");
  EXPECT_EQ(b, rhs(0.12, 0.06, 0.004, Process::cold));
  EXPECT_EQ(designation(b), "RHS 120x60x4.0 cold");
  EXPECT_EQ(parse_section("SHS 100x5"), rhs(0.1, 0.1, 0.005));
  EXPECT_EQ(parse_section("SHS 100x100x5.0 hot"), rhs(0.1, 0.1, 0.005));
  EXPECT_EQ(designation(parse_section("SHS 100x5")), "SHS 100x100x5.0");
  EXPECT_EQ(parse_section("bar 37"), bar(0.037));
  EXPECT_EQ(designation(bar(0.037)), "bar 37");
  EXPECT_TRUE(is_standard(bar(0.037)));
  EXPECT_FALSE(is_standard(bar(0.0375)));
  // A geometrically valid size outside the catalogue is accepted and flagged.
  const Section odd = parse_section("CHS 90x4.2");
  EXPECT_FALSE(is_standard(odd));
  EXPECT_FALSE(find_standard("CHS 90x4.2").has_value());
  EXPECT_TRUE(find_standard("SHS 100x100x5").has_value());
  // Designations parse back to the same section.
  for (Shape shape : {Shape::chs, Shape::rhs})
    for (const Section& s : series(shape, Process::cold)) EXPECT_EQ(parse_section(designation(s)), s);
}

TEST(Sections, RejectsBadSectionsWithOneLine) {
  for (const char* bad :
       {"CHS 10x20", "CHS 10x5", "IPE 200", "CHS 88.9", "RHS 120x60", "CHS -88.9x4",
        "CHS 0x4", "CHS nanx4", "CHS 88.9x4x3", "bar 37 cold", "CHS 88.9x4 warm", "",
        "CHS 99999x10", "RHS 40x20x8", "SHS 100x120x5", "bar 1e400", "CHS 88,9x4"}) {
    try {
      parse_section(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const Error& e) {
      EXPECT_EQ(e.subject(), "--section");
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
}

TEST(Sections, CataloguesAreSortedByMassAndValid) {
  for (Shape shape : {Shape::chs, Shape::rhs, Shape::bar})
    for (Process process : {Process::hot, Process::cold}) {
      if (shape == Shape::bar && process == Process::cold) continue;
      const std::vector<Section> list = series(shape, process);
      ASSERT_GT(list.size(), 20u);
      double last = 0;
      for (const Section& s : list) {
        EXPECT_EQ(s.shape, shape);
        EXPECT_EQ(s.process, process);
        const double m = properties(s).mass;
        EXPECT_GE(m, last);
        last = m;
        EXPECT_TRUE(is_standard(s));
      }
    }
  EXPECT_EQ(designation(series(Shape::chs).front()), "CHS 21.3x2.3");
  EXPECT_EQ(parse_series("rhs cold").front().process, Process::cold);
  EXPECT_THROW(parse_series("ipe"), Error);
}
