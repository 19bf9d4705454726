#pragma once
/// \file plot.h
/// A small plotting layer on Cairo for the figures a run writes (figures/figures.h): an image
/// canvas of a given pixel size, a page layout (title band, plot box, legend strip), data → pixel
/// axes with nice ticks, colour maps (diverging red – white – blue centred at 0 for axial force,
/// sequential for magnitudes), a colour bar with its label and units, a scale bar, text, and an
/// atomic PNG write.
///
/// Pixels: x to the right, y down, (0, 0) the top-left corner; data axes put y up. Lines are
/// antialiased; text uses Cairo's toy API with the system's sans-serif face. Font sizes scale
/// with the canvas height (`font_size`). Cost: a few ms of drawing per figure; the PNG encoding
/// of a 1600 × 1200 image takes ~30 ms.

#include <cairo.h>

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace gridshell::figures {

/// A colour, components in [0, 1].
struct Rgb {
  double r = 0, g = 0, b = 0;
};

/// An RGB image with a white background and its Cairo drawing context. Move-only.
class Canvas {
 public:
  /// Throws Error("figure", …) for a size outside 64 … 8192 pixels per side.
  Canvas(int width, int height);
  ~Canvas();
  Canvas(Canvas&& other) noexcept;
  Canvas& operator=(Canvas&& other) noexcept;
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  cairo_t* cr() const { return cr_; }  ///< the drawing context

  /// The colour of pixel (x, y) (for tests and checks); throws Error for a pixel off the image.
  Rgb pixel(int x, int y) const;
  /// The image encoded as PNG bytes.
  std::string png() const;

 private:
  int width_ = 0, height_ = 0;
  cairo_surface_t* surface_ = nullptr;
  cairo_t* cr_ = nullptr;
};

/// Writes the canvas as a PNG file atomically (io::write_file_atomic).
void write_png(const Canvas& canvas, const std::filesystem::path& path);

// ---- Colours -----------------------------------------------------------------------------

/// t ∈ [−1, 1]: −1 deep red (compression), 0 a light grey (visible on white), +1 deep blue
/// (tension), as in the paper's force plots; clamped outside.
Rgb diverging_color(double t);
/// t ∈ [0, 1]: dark blue → teal → green → yellow (light = large); clamped outside.
Rgb sequential_color(double t);

enum class ColorMap { diverging, sequential };

/// A value range mapped onto a colour map. Diverging scales are centred at 0: the colour of v
/// is diverging_color(v / max(|lo|, |hi|)).
struct ColorScale {
  ColorMap map = ColorMap::sequential;
  double lo = 0, hi = 1;
  Rgb operator()(double v) const;
};

// ---- Layout ------------------------------------------------------------------------------

/// A rectangle in pixels (x, y: the top-left corner).
struct Box {
  double x = 0, y = 0, w = 0, h = 0;
};

/// The page of every figure: a title band at the top, the plot box, and a legend strip at the
/// right for a colour bar.
struct PageLayout {
  Box title, plot, legend;
};
PageLayout page_layout(int width, int height);

/// The base font size in pixels of a canvas (its height / 55).
double font_size(const Canvas& canvas);

/// Data → pixel mapping of a plot box; data y points up.
struct Axes {
  Box box;
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;  ///< data range shown
  Eigen::Vector2d to_pixel(double x, double y) const;
  double pixels_per_unit_x() const { return box.w / (x1 - x0); }
};

/// Axes showing [x0, x1] × [y0, y1] in `box`. `equal_scale`: one data unit is as many pixels
/// along x as along y, the shorter range widened (about its centre) to fill the box. An empty
/// range is widened to ±0.5.
Axes make_axes(const Box& box, double x0, double x1, double y0, double y1, bool equal_scale);

/// About `target` round tick values (steps of 1, 2 or 5 × 10ᵏ) covering [lo, hi].
std::vector<double> nice_ticks(double lo, double hi, int target = 6);

/// A tick label: `v` with as many decimals as the tick step needs ("-0" printed as "0").
std::string format_tick(double v, double step);

/// Draws the axes' frame, ticks with labels, and the axis titles (e.g. "x [m]").
void draw_axes(Canvas& canvas, const Axes& axes, const std::string& x_label,
               const std::string& y_label);

// ---- Text and legends --------------------------------------------------------------------

enum class Align { start, middle, end };

struct TextStyle {
  double size = 16;  ///< pixels
  bool bold = false;
  Rgb color{0.1, 0.1, 0.1};
  Align horizontal = Align::start;
  Align vertical = Align::end;  ///< start = top at y, middle = centred, end = baseline at y
  double angle = 0;             ///< radians, counter-clockwise on screen
};

/// Draws `text` (UTF-8) at pixel (x, y).
void draw_text(Canvas& canvas, double x, double y, const std::string& text, const TextStyle& style);
/// The width in pixels `text` takes at `style`.
double text_width(Canvas& canvas, const std::string& text, const TextStyle& style);

/// The title band: `heading` (what the figure shows) in bold, `subtitle` (what was run) below;
/// each shrunk to fit the width when too long.
void draw_title(Canvas& canvas, const Box& band, const std::string& heading,
                const std::string& subtitle);

/// A vertical colour bar in `strip` (top to bottom: hi to lo) with ticks and `label` (the
/// quantity and its unit) written vertically beside it.
void draw_colorbar(Canvas& canvas, const Box& strip, const ColorScale& scale,
                   const std::string& label);

/// A scale bar of a round length (1, 2 or 5 × 10ᵏ m, about five font sizes long) with its
/// length written to its right; its left end at pixel (x, y) (y = its bottom).
void draw_scale_bar(Canvas& canvas, const Axes& axes, double x, double y);

// ---- Drawing helpers ---------------------------------------------------------------------

void set_color(Canvas& canvas, const Rgb& c, double alpha = 1);
void draw_line(Canvas& canvas, const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Rgb& color,
               double width, double alpha = 1);
/// A filled square of side `size` centred at p, with a dark outline.
void draw_square(Canvas& canvas, const Eigen::Vector2d& p, double size, const Rgb& fill);
/// A filled triangle pointing up with its apex at p (a support symbol), dark outline.
void draw_support_triangle(Canvas& canvas, const Eigen::Vector2d& p, double size, const Rgb& fill);

}  // namespace gridshell::figures
