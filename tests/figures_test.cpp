// The figures (figures/plot.h, figures/figures.h): PNG files of the stated size read back
// independently, non-trivial pictures, colour semantics at known pixels (compression red,
// tension blue), the heatmaps' cells, skipping of absent data, and the CLI's figures/ folder.

#include <cairo.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/core/error.h"
#include "gridshell/figures/figures.h"
#include "test_support.h"

using gridshell::test::slurp;

using namespace gridshell;
using namespace gridshell::figures;
namespace fs = std::filesystem;

namespace {

/// Width and height from the PNG signature and IHDR chunk (big-endian), read byte by byte.
std::pair<int, int> png_size(const fs::path& p) {
  const std::string b = slurp(p);
  if (b.size() < 24 || b.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0 || b.compare(12, 4, "IHDR") != 0)
    return {-1, -1};
  auto be32 = [&](std::size_t at) {
    int v = 0;
    for (std::size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(b[at + k]);
    return v;
  };
  return {be32(16), be32(20)};
}

/// What a PNG holds: size, number of distinct colours, share of pixels that are not white.
struct PngStats {
  int width = 0, height = 0;
  std::size_t colours = 0;
  double inked = 0;
};

PngStats png_stats(const fs::path& p) {
  cairo_surface_t* s = cairo_image_surface_create_from_png(p.c_str());
  PngStats st;
  if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
    cairo_surface_destroy(s);
    return st;
  }
  st.width = cairo_image_surface_get_width(s);
  st.height = cairo_image_surface_get_height(s);
  const int stride = cairo_image_surface_get_stride(s);
  const unsigned char* data = cairo_image_surface_get_data(s);
  std::set<std::uint32_t> colours;
  long inked = 0;
  for (int y = 0; y < st.height; ++y)
    for (int x = 0; x < st.width; ++x) {
      std::uint32_t w = 0;
      std::memcpy(&w, data + y * stride + 4 * x, 4);
      w &= 0xffffff;
      colours.insert(w);
      inked += w != 0xffffff;
    }
  cairo_surface_destroy(s);
  st.colours = colours.size();
  st.inked = static_cast<double>(inked) / (static_cast<double>(st.width) * st.height);
  return st;
}

/// A 5 × 5 quad grid on a shallow paraboloid (10 m square, 1.2 m rise) supported along its
/// boundary: 36 joints, 60 beams.
Surface small_shell(PolyMesh& mesh) {
  const int n = 5;
  mesh.V.resize((n + 1) * (n + 1), 3);
  std::vector<int> supports;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = 2.0 * i - 5, y = 2.0 * j - 5;
      mesh.V.row(j * (n + 1) + i) << x, y, 1.2 * (1 - (x * x + y * y) / 50);
      if (i == 0 || j == 0 || i == n || j == n) supports.push_back(j * (n + 1) + i);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      mesh.faces.push_back({a, a + 1, a + n + 2, a + n + 1});
    }
  return {triangulate(mesh), supports};
}

FigureOptions small_options() {
  return {.width = 640, .height = 480};
}

bool reddish(const Rgb& c) {
  return c.r > 0.5 && c.r > c.b + 0.3 && c.r > c.g + 0.2;
}
bool bluish(const Rgb& c) {
  return c.b > 0.5 && c.b > c.r + 0.3;
}

}  // namespace

TEST(Plot, NiceTicksAreRoundAndCoverTheRange) {
  EXPECT_EQ(nice_ticks(0, 23.7, 6), (std::vector<double>{0, 5, 10, 15, 20}));
  EXPECT_EQ(nice_ticks(-3.73, 3.73, 6), (std::vector<double>{-2, 0, 2}));
  const std::vector<double> t = nice_ticks(0.0123, 0.0987, 5);
  ASSERT_GE(t.size(), 3u);
  EXPECT_NEAR(t[1] - t[0], 0.02, 1e-12);
  EXPECT_GE(t.front(), 0.0123);
  EXPECT_LE(t.back(), 0.0987);
  EXPECT_EQ(format_tick(-1e-17, 0.5), "0.0");
  EXPECT_EQ(format_tick(2.5, 0.5), "2.5");
  EXPECT_EQ(format_tick(20, 5), "20");
}

TEST(Plot, ColourMapsMeanWhatTheLegendsSay) {
  EXPECT_TRUE(reddish(diverging_color(-1)));
  EXPECT_TRUE(bluish(diverging_color(1)));
  const Rgb mid = diverging_color(0);
  EXPECT_NEAR(mid.r, mid.b, 1e-12);  // neutral at zero force
  EXPECT_NEAR(mid.r, mid.g, 1e-12);
  // A diverging scale is centred at 0 whatever the range: -5 of [-5, 20] is a quarter red.
  const ColorScale s{ColorMap::diverging, -5, 20};
  const Rgb quarter = s(-5), expected = diverging_color(-0.25);
  EXPECT_NEAR(quarter.r, expected.r, 1e-12);
  EXPECT_NEAR(quarter.b, expected.b, 1e-12);
  // The sequential map grows lighter from low to high.
  auto luminance = [](const Rgb& c) { return 0.3 * c.r + 0.59 * c.g + 0.11 * c.b; };
  for (int k = 0; k < 10; ++k)
    EXPECT_LT(luminance(sequential_color(0.1 * k)), luminance(sequential_color(0.1 * (k + 1))))
        << k;
}

TEST(Plot, EqualScaleAxesKeepMetresSquare) {
  const Box box{100, 50, 400, 200};
  const Axes a = make_axes(box, 0, 10, 0, 10, true);
  const Eigen::Vector2d o = a.to_pixel(0, 0), x = a.to_pixel(1, 0), y = a.to_pixel(0, 1);
  EXPECT_NEAR((x - o).norm(), (y - o).norm(), 1e-9);
  EXPECT_NEAR((x - o).norm(), 20, 1e-9);  // the 10 m fit the 200 px height
  EXPECT_LT(y.y(), o.y());                // data y points up
  const Eigen::Vector2d c = a.to_pixel(5, 5);
  EXPECT_NEAR(c.x(), 300, 1e-9);
  EXPECT_NEAR(c.y(), 150, 1e-9);
}

TEST(Plot, LongTextIsShrunkThenCutToFit) {
  Canvas canvas(640, 480);
  const std::string text = "First buckling mode: λ₁ = 25561, shown at 10 % of the span";
  TextStyle style{.size = 20};
  const double full = text_width(canvas, text, style);
  // Fits at 80 % of the width: shrunk, not cut.
  std::string fitted = fit_text(canvas, text, style, 0.8 * full);
  EXPECT_EQ(fitted, text);
  EXPECT_LT(style.size, 20);
  EXPECT_LE(text_width(canvas, fitted, style), 0.8 * full);
  // A third of the width: shrunk to 60 %, then cut at a character with an ellipsis.
  style.size = 20;
  fitted = fit_text(canvas, text, style, full / 3);
  EXPECT_DOUBLE_EQ(style.size, 12);
  EXPECT_LE(text_width(canvas, fitted, style), full / 3);
  ASSERT_GE(fitted.size(), 3u);
  EXPECT_EQ(fitted.substr(fitted.size() - 3), "…");
  EXPECT_EQ(text.rfind(fitted.substr(0, fitted.size() - 3), 0), 0u);
}

TEST(Plot, CanvasWritesAPngOfTheStatedSize) {
  const fs::path dir = test::temp_dir("figures_canvas");
  Canvas canvas(320, 200);
  draw_line(canvas, {10, 10}, {300, 190}, {0.8, 0.1, 0.1}, 4);
  EXPECT_TRUE(reddish(canvas.pixel(155, 100)));
  const Rgb white = canvas.pixel(300, 10);
  EXPECT_EQ(white.r + white.g + white.b, 3.0);
  write_png(canvas, dir / "c.png");
  EXPECT_EQ(png_size(dir / "c.png"), (std::pair<int, int>{320, 200}));
  EXPECT_THROW(Canvas(10, 200), Error);
  EXPECT_THROW(canvas.pixel(320, 0), Error);
}

TEST(Figures, FigureOptionsParseSizesAndNone) {
  const FigureOptions o = parse_figure_options("800x600");
  EXPECT_TRUE(o.enabled);
  EXPECT_EQ(o.width, 800);
  EXPECT_EQ(o.height, 600);
  EXPECT_FALSE(parse_figure_options("none").enabled);
  for (const char* bad : {"", "800", "800x", "x600", "10x10", "800x9000", "8e2x600", "big"})
    EXPECT_THROW(parse_figure_options(bad), Error) << bad;
}

TEST(Figures, CompressionIsDrawnRedAndTensionBlue) {
  // Two beams in plan: 0 → 1 in compression, 1 → 2 in tension.
  PolyMesh mesh;
  mesh.V.resize(3, 3);
  mesh.V << 0, 0, 0, 5, 0, 1, 10, 0, 0;
  analysis::FrameResult st;
  st.axial_force = {-2000, 2000};
  FigureInput in{.title = "two beams",
                 .gridshell = &mesh,
                 .beams = {{0, 1}, {1, 2}},
                 .supports = {0, 2},
                 .structure = &st};
  const FigureOptions o = small_options();
  const Axes axes = plan_axes(mesh.V, o);
  auto at = [&](const Canvas& c, double x, double y) {
    const Eigen::Vector2d p = axes.to_pixel(x, y);
    return c.pixel(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
  };
  const Canvas plan = draw_plan(in, o);
  EXPECT_TRUE(reddish(at(plan, 2.5, 0)));
  EXPECT_TRUE(bluish(at(plan, 7.5, 0)));
  const Rgb off = at(plan, 2.5, 2);  // beside the beams: background
  EXPECT_EQ(off.r + off.g + off.b, 3.0);
  const Rgb support = at(plan, 0, 0);  // a support square is dark
  EXPECT_LT(support.r + support.g + support.b, 0.6);
  // Without an analysis the same beams are grey.
  in.structure = nullptr;
  const Rgb grey = at(draw_plan(in, o), 2.5, 0);
  EXPECT_NEAR(grey.r, grey.b, 0.05);
  EXPECT_LT(grey.r, 0.6);
}

// Given the input surface, the plan draws its boundary under the beams and frames it, so a part
// the grid leaves uncovered shows: beams over the left half of a 10 × 4 m plate.
TEST(Figures, ThePlanShowsTheSurfacesEdge) {
  PolyMesh mesh;
  mesh.V.resize(6, 3);
  mesh.V << 0, 0, 0, 2.5, 0, 0, 5, 0, 0, 0, 4, 0, 2.5, 4, 0, 5, 4, 0;
  mesh.faces = {{0, 1, 4, 3}, {1, 2, 5, 4}};
  TriMesh plate;
  plate.V.resize(4, 3);
  plate.V << 0, 0, 0, 10, 0, 0, 10, 4, 0, 0, 4, 0;
  plate.F.resize(2, 3);
  plate.F << 0, 1, 2, 0, 2, 3;
  const FigureOptions o = small_options();
  const Canvas plan = draw_plan({.gridshell = &mesh, .surface = &plate}, o);
  Points both(10, 3);
  both << mesh.V, plate.V;
  const Axes axes = plan_axes(both, o);  // the surface is in the frame
  auto at = [&](double x, double y) {
    const Eigen::Vector2d p = axes.to_pixel(x, y);
    return plan.pixel(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
  };
  const Rgb edge = at(10, 2);  // the plate's right side, far from any beam: green
  EXPECT_GT(edge.g, edge.r + 0.1);
  EXPECT_GT(edge.g, edge.b + 0.1);
  const Rgb inside = at(7.5, 2);  // uncovered: nothing is drawn over the plate itself
  EXPECT_EQ(inside.r + inside.g + inside.b, 3.0);
  const Rgb beam = at(2.5, 2);  // the middle beam, grey
  EXPECT_LT(beam.g, 0.6);
}

TEST(Figures, AnAnalysedShellGetsEveryFigureNonTrivialAndOfTheStatedSize) {
  PolyMesh mesh;
  const Surface surface = small_shell(mesh);
  analysis::FrameAnalysisOptions ao;
  ao.buckling_modes = 2;
  const analysis::FrameResult st =
      analysis::analyze_frame(analysis::gridshell_frame(mesh, surface.supports), ao);
  ASSERT_GE(st.path.size(), 2u);
  ASSERT_FALSE(st.buckling_modes.empty());
  // A field with a density gradient and an anisotropy growing in x.
  const Field field = test::synthetic_field(
      surface.mesh, [](const Vec3& c) { return 1 + 0.1 * (c.y() + 5); },
      [](const Vec3& c) { return 1 + 0.2 * (c.x() + 5); });
  const fs::path dir = test::temp_dir("figures_shell");
  const FigureOptions o = small_options();
  const std::vector<std::string> files = write_figures(dir,
                                                       {.title = "small shell",
                                                        .gridshell = &mesh,
                                                        .supports = surface.supports,
                                                        .structure = &st,
                                                        .surface = &surface.mesh,
                                                        .field = &field},
                                                       o);
  EXPECT_EQ(files, (std::vector<std::string>{"figures/top.png", "figures/perspective.png",
                                             "figures/field.png", "figures/buckling_mode.png",
                                             "figures/load_path.png"}));
  for (const std::string& f : files) {
    EXPECT_EQ(png_size(dir / f), (std::pair<int, int>{640, 480})) << f;
    const PngStats s = png_stats(dir / f);
    EXPECT_EQ(s.width, 640) << f;
    EXPECT_GT(s.colours, 60u) << f;  // colour maps, antialiased lines and text
    EXPECT_GT(s.inked, 0.03) << f;   // more than a frame and a title
    EXPECT_LT(s.inked, 0.85) << f;   // not a flood
  }
  // Deterministic: drawn again, the same bytes.
  EXPECT_EQ(draw_buckling_mode({.title = "small shell",
                                .gridshell = &mesh,
                                .supports = surface.supports,
                                .structure = &st},
                               o)
                .png(),
            slurp(dir / "figures/buckling_mode.png"));
  // The field fills the surface's plan: its share of ink is the largest.
  EXPECT_GT(png_stats(dir / "figures/field.png").inked, png_stats(dir / "figures/top.png").inked);
}

TEST(Figures, AbsentDataSkipsItsFigures) {
  PolyMesh mesh;
  const Surface surface = small_shell(mesh);
  const fs::path dir = test::temp_dir("figures_skip");
  EXPECT_EQ(write_figures(dir, {.gridshell = &mesh, .supports = surface.supports}, small_options()),
            (std::vector<std::string>{"figures/top.png", "figures/perspective.png"}));
  analysis::FrameAnalysisOptions linear;
  linear = analysis::at_level(linear, analysis::AnalysisLevel::linear);
  const analysis::FrameResult st =
      analysis::analyze_frame(analysis::gridshell_frame(mesh, surface.supports), linear);
  EXPECT_EQ(write_figures(dir, {.gridshell = &mesh, .structure = &st}, small_options()).size(), 2u);
  EXPECT_TRUE(write_figures(dir, {}, small_options()).empty());
  EXPECT_THROW(write_figures(dir, {}, {.width = 20, .height = 20}), Error);
}

TEST(Figures, LinearFiguresDrawnDuringTheAnalysisAreTheOnesDrawnAfterIt) {
  // `analyze` draws top.png and perspective.png from the linear result while the LBA runs
  // (FrameAnalysisOptions::after_linear, encode_linear_figures) and writes them with the others:
  // the same files, bytes and order as drawing everything from the finished result.
  PolyMesh mesh;
  const Surface surface = small_shell(mesh);
  analysis::FrameAnalysisOptions ao =
      analysis::at_level({}, analysis::AnalysisLevel::buckling);
  ao.buckling_modes = 2;
  analysis::FrameResult linear_view;
  int calls = 0;
  ao.after_linear = [&](const analysis::FrameResult& linear) {
    ++calls;
    EXPECT_TRUE(linear.buckling_lambdas.empty());  // called before the LBA
    linear_view.axial_force = linear.axial_force;
  };
  const analysis::FrameResult st =
      analysis::analyze_frame(analysis::gridshell_frame(mesh, surface.supports), ao);
  EXPECT_EQ(calls, 1);
  ASSERT_FALSE(st.buckling_modes.empty());
  EXPECT_EQ(linear_view.axial_force, st.axial_force);
  const FigureOptions o = small_options();
  const FigureInput after{
      .title = "small shell", .gridshell = &mesh, .supports = surface.supports, .structure = &st};
  FigureInput during = after;
  during.structure = &linear_view;
  const EncodedFigures early = encode_linear_figures(during, o);
  ASSERT_EQ(early.size(), 2u);
  const fs::path one = test::temp_dir("figures_after"), two = test::temp_dir("figures_during");
  const std::vector<std::string> files = write_figures(one, after, o);
  EXPECT_EQ(write_figures(two, after, o, early), files);
  EXPECT_EQ(files, (std::vector<std::string>{"figures/top.png", "figures/perspective.png",
                                             "figures/buckling_mode.png"}));
  for (const std::string& f : files) EXPECT_EQ(slurp(one / f), slurp(two / f)) << f;
  EXPECT_TRUE(encode_linear_figures(during, {.enabled = false}).empty());
}

TEST(Figures, HeatmapHasOneCellPerDensityAndAnisotropy) {
  // D ∈ {1, 2, 3}, A ∈ {1, 2}, two repeats; (D 3, A 2) missing as in a shard.
  std::vector<SweepRow> rows;
  for (double D : {1.0, 2.0, 3.0})
    for (double A : {1.0, 2.0})
      for (int rep = 0; rep < 2; ++rep) {
        if (D == 3 && A == 2) continue;
        SweepRow r;
        r.c.D = D, r.c.A = A, r.c.repeat = rep;
        r.lambda = 10 * D + A + rep;  // mean 10 D + A + 0.5
        rows.push_back(r);
      }
  const SweepGrid g = sweep_grid(rows, [](const SweepRow& r) { return r.lambda; });
  ASSERT_EQ(g.D, (std::vector<double>{1, 2, 3}));
  ASSERT_EQ(g.A, (std::vector<double>{1, 2}));
  EXPECT_DOUBLE_EQ(g.mean(1, 1), 22.5);  // A = 2, D = 2
  EXPECT_EQ(g.count(0, 2), 2);
  EXPECT_TRUE(std::isnan(g.mean(1, 2)));
  const FigureOptions o = small_options();
  const Canvas c = draw_heatmap(g, {.heading = "h", .subtitle = "s", .value_label = "λ"}, o);
  const Box box = page_layout(o.width, o.height).plot;
  // Along a line through the upper part of each row (above the written values), count the
  // runs of one colour between the white cell borders.
  auto runs_along_row = [&](double y) {
    int runs = 0;
    Rgb last{1, 1, 1};
    int length = 0;
    for (int x = static_cast<int>(box.x) + 3; x < static_cast<int>(box.x + box.w) - 3; ++x) {
      const Rgb p = c.pixel(x, static_cast<int>(y));
      const bool white = p.r + p.g + p.b > 2.95;
      const bool same =
          std::abs(p.r - last.r) + std::abs(p.g - last.g) + std::abs(p.b - last.b) < 0.02;
      if (white || !same) {
        if (length > 20) ++runs;
        length = 0;
      }
      if (!white) ++length;
      last = p;
    }
    return runs + (length > 20);
  };
  const double ch = box.h / 2;
  EXPECT_EQ(runs_along_row(box.y + 0.2 * ch), 3);       // A = 2: two values and a grey cell
  EXPECT_EQ(runs_along_row(box.y + ch + 0.2 * ch), 3);  // A = 1
  // The missing cell is neutral grey; larger means are lighter.
  const Rgb missing =
      c.pixel(static_cast<int>(box.x + 2.5 * box.w / 3), static_cast<int>(box.y + 0.2 * ch));
  EXPECT_NEAR(missing.r, missing.b, 0.01);
  const Rgb low =
      c.pixel(static_cast<int>(box.x + 0.5 * box.w / 3), static_cast<int>(box.y + 1.2 * ch));
  const Rgb high =
      c.pixel(static_cast<int>(box.x + 2.5 * box.w / 3), static_cast<int>(box.y + 1.2 * ch));
  EXPECT_LT(low.r + low.g, high.r + high.g);
}

TEST(FiguresCli, DesignAndSweepWriteTheirFigures) {
  const fs::path d = test::temp_dir("figures_cli");
  test::RunResult r =
      test::run_gridshell("design builtin:dome:res=12 --cells 30 -D 2 -A 2 --seed 2 --quiet -o " +
                          (d / "design").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto report = nlohmann::json::parse(slurp(d / "design" / "report.json"));
  const std::vector<std::string> expected = {"figures/top.png", "figures/perspective.png",
                                             "figures/field.png", "figures/buckling_mode.png",
                                             "figures/load_path.png"};
  EXPECT_EQ(report["figures"].get<std::vector<std::string>>(), expected);
  for (const std::string& f : expected) {
    EXPECT_EQ(png_size(d / "design" / f), (std::pair<int, int>{1600, 1200})) << f;
    EXPECT_GT(png_stats(d / "design" / f).colours, 100u) << f;
  }
  EXPECT_GT(report["timings_s"]["figures"].get<double>(), 0.0);

  r = test::run_gridshell(
      "sweep builtin:dome:res=12 --D 1:2 --A 1:3 --repeats 1 --cells 20 --analyze linear "
      "--quiet -o " +
      (d / "sweep").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto sweep = nlohmann::json::parse(slurp(d / "sweep" / "report.json"));
  EXPECT_EQ(sweep["figures"].get<std::vector<std::string>>(),
            (std::vector<std::string>{"figures/lambda_heatmap.png", "figures/delta_heatmap.png"}));
  EXPECT_EQ(png_size(d / "sweep" / "figures" / "delta_heatmap.png"),
            (std::pair<int, int>{1600, 1200}));
}

TEST(FiguresCli, FiguresOptionSetsTheSizeOrTurnsThemOff) {
  const fs::path d = test::temp_dir("figures_cli_size");
  const std::string base =
      "baseline builtin:dome:res=12 --kind quad --spacing 4 --analyze linear "
      "--quiet -o ";
  test::RunResult r = test::run_gridshell(base + (d / "small").string() + " --figures 640x480");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto report = nlohmann::json::parse(slurp(d / "small" / "report.json"));
  EXPECT_EQ(report["figures"].get<std::vector<std::string>>(),
            (std::vector<std::string>{"figures/top.png", "figures/perspective.png"}));
  EXPECT_EQ(png_size(d / "small" / "figures" / "top.png"), (std::pair<int, int>{640, 480}));
  r = test::run_gridshell(base + (d / "none").string() + " --figures none");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(d / "none" / "figures"));
  EXPECT_TRUE(nlohmann::json::parse(slurp(d / "none" / "report.json"))["figures"].empty());
  r = test::run_gridshell(base + (d / "bad").string() + " --figures 20x20");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--figures"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "bad" / "report.json"));
}
