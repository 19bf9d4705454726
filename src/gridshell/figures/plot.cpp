#include "gridshell/figures/plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"

namespace gridshell::figures {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Piecewise-linear interpolation between equally spaced colour stops.
template <std::size_t N>
Rgb interpolate(const std::array<Rgb, N>& stops, double t) {
  t = std::clamp(t, 0.0, 1.0) * static_cast<double>(N - 1);
  const std::size_t k = std::min(static_cast<std::size_t>(t), N - 2);
  const double s = t - static_cast<double>(k);
  const Rgb& a = stops[k];
  const Rgb& b = stops[k + 1];
  return {a.r + s * (b.r - a.r), a.g + s * (b.g - a.g), a.b + s * (b.b - a.b)};
}

cairo_status_t append_to_string(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

void select_font(cairo_t* cr, const TextStyle& style) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         style.bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, style.size);
}

}  // namespace

// ---- Canvas ------------------------------------------------------------------------------

Canvas::Canvas(int width, int height) : width_(width), height_(height) {
  if (width < 64 || height < 64 || width > 8192 || height > 8192)
    throw Error("figure", fmt::format("size {}x{} is outside 64..8192 pixels", width, height));
  surface_ = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  cr_ = cairo_create(surface_);
  if (cairo_status(cr_) != CAIRO_STATUS_SUCCESS)
    throw Error("figure", fmt::format("cannot create a {}x{} image", width, height));
  cairo_set_source_rgb(cr_, 1, 1, 1);
  cairo_paint(cr_);
  cairo_set_line_cap(cr_, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_join(cr_, CAIRO_LINE_JOIN_ROUND);
}

Canvas::~Canvas() {
  if (cr_) cairo_destroy(cr_);
  if (surface_) cairo_surface_destroy(surface_);
}

Canvas::Canvas(Canvas&& other) noexcept
    : width_(other.width_),
      height_(other.height_),
      surface_(std::exchange(other.surface_, nullptr)),
      cr_(std::exchange(other.cr_, nullptr)) {}

Canvas& Canvas::operator=(Canvas&& other) noexcept {
  if (this != &other) {
    if (cr_) cairo_destroy(cr_);
    if (surface_) cairo_surface_destroy(surface_);
    width_ = other.width_;
    height_ = other.height_;
    surface_ = std::exchange(other.surface_, nullptr);
    cr_ = std::exchange(other.cr_, nullptr);
  }
  return *this;
}

Rgb Canvas::pixel(int x, int y) const {
  if (x < 0 || y < 0 || x >= width_ || y >= height_)
    throw Error("figure",
                fmt::format("pixel ({}, {}) is off the {}x{} image", x, y, width_, height_));
  cairo_surface_flush(surface_);
  const unsigned char* row =
      cairo_image_surface_get_data(surface_) + y * cairo_image_surface_get_stride(surface_);
  std::uint32_t word = 0;
  std::copy_n(row + 4 * x, 4, reinterpret_cast<unsigned char*>(&word));  // native-endian xRGB
  return {((word >> 16) & 0xff) / 255.0, ((word >> 8) & 0xff) / 255.0, (word & 0xff) / 255.0};
}

std::string Canvas::png() const {
  cairo_surface_flush(surface_);
  std::string bytes;
  if (cairo_surface_write_to_png_stream(surface_, append_to_string, &bytes) != CAIRO_STATUS_SUCCESS)
    throw Error("figure", "PNG encoding failed");
  return bytes;
}

void write_png(const Canvas& canvas, const std::filesystem::path& path) {
  io::write_file_atomic(path, canvas.png());
}

// ---- Colours -----------------------------------------------------------------------------

Rgb diverging_color(double t) {
  static const std::array<Rgb, 5> kStops = {Rgb{0.70, 0.05, 0.10}, Rgb{0.93, 0.45, 0.38},
                                            Rgb{0.84, 0.84, 0.84}, Rgb{0.45, 0.65, 0.90},
                                            Rgb{0.05, 0.20, 0.65}};
  return interpolate(kStops, 0.5 * (t + 1));
}

Rgb sequential_color(double t) {
  static const std::array<Rgb, 5> kStops = {Rgb{0.18, 0.12, 0.42}, Rgb{0.16, 0.38, 0.60},
                                            Rgb{0.13, 0.60, 0.55}, Rgb{0.50, 0.80, 0.32},
                                            Rgb{0.98, 0.90, 0.22}};
  return interpolate(kStops, t);
}

Rgb ColorScale::operator()(double v) const {
  if (map == ColorMap::diverging) {
    const double m = std::max(std::abs(lo), std::abs(hi));
    return diverging_color(m > 0 ? v / m : 0.0);
  }
  return sequential_color(hi > lo ? (v - lo) / (hi - lo) : 0.5);
}

// ---- Layout ------------------------------------------------------------------------------

PageLayout page_layout(int width, int height) {
  const double w = width, h = height;
  PageLayout p;
  p.title = {0, 0, w, 0.11 * h};
  p.plot = {0.09 * w, 0.14 * h, 0.74 * w, 0.76 * h};
  p.legend = {0.87 * w, 0.18 * h, 0.03 * w, 0.62 * h};
  return p;
}

double font_size(const Canvas& canvas) {
  return canvas.height() / 55.0;
}

Eigen::Vector2d Axes::to_pixel(double x, double y) const {
  return {box.x + (x - x0) / (x1 - x0) * box.w, box.y + box.h - (y - y0) / (y1 - y0) * box.h};
}

Axes make_axes(const Box& box, double x0, double x1, double y0, double y1, bool equal_scale) {
  if (!(x1 > x0)) x0 -= 0.5, x1 += 0.5;
  if (!(y1 > y0)) y0 -= 0.5, y1 += 0.5;
  if (equal_scale) {
    const double sx = box.w / (x1 - x0), sy = box.h / (y1 - y0);
    if (sx > sy) {  // x range widened
      const double half = 0.5 * box.w / sy, c = 0.5 * (x0 + x1);
      x0 = c - half, x1 = c + half;
    } else {
      const double half = 0.5 * box.h / sx, c = 0.5 * (y0 + y1);
      y0 = c - half, y1 = c + half;
    }
  }
  return {box, x0, x1, y0, y1};
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return {lo};
  const double raw = (hi - lo) / std::max(1, target);
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10 * p;
  for (double m : {1.0, 2.0, 5.0})
    if (m * p >= raw) {
      step = m * p;
      break;
    }
  std::vector<double> ticks;
  for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k += 1)
    ticks.push_back(k * step);
  return ticks;
}

std::string format_tick(double v, double step) {
  const int decimals =
      step > 0 ? std::clamp(static_cast<int>(-std::floor(std::log10(step) + 1e-9)), 0, 6) : 0;
  std::string s = fmt::format("{:.{}f}", v, decimals);
  if (s.find_first_not_of("-0.") == std::string::npos)
    s = decimals > 0 ? s.substr(s[0] == '-') : "0";
  return s;
}

void draw_axes(Canvas& canvas, const Axes& axes, const std::string& x_label,
               const std::string& y_label) {
  cairo_t* cr = canvas.cr();
  const Box& b = axes.box;
  const double fs = font_size(canvas), tick = 0.5 * fs;
  set_color(canvas, {0.25, 0.25, 0.25});
  cairo_set_line_width(cr, 1.5);
  cairo_rectangle(cr, b.x, b.y, b.w, b.h);
  cairo_stroke(cr);
  TextStyle label{.size = 0.85 * fs};
  const std::vector<double> xt = nice_ticks(axes.x0, axes.x1, 8);
  const double xstep = xt.size() > 1 ? xt[1] - xt[0] : 1;
  label.horizontal = Align::middle;
  label.vertical = Align::start;
  for (double x : xt) {
    const double px = axes.to_pixel(x, 0).x();
    draw_line(canvas, {px, b.y + b.h}, {px, b.y + b.h + tick}, {0.25, 0.25, 0.25}, 1.5);
    draw_text(canvas, px, b.y + b.h + 1.6 * tick, format_tick(x, xstep), label);
  }
  const std::vector<double> yt = nice_ticks(axes.y0, axes.y1, 7);
  const double ystep = yt.size() > 1 ? yt[1] - yt[0] : 1;
  label.horizontal = Align::end;
  label.vertical = Align::middle;
  for (double y : yt) {
    const double py = axes.to_pixel(0, y).y();
    draw_line(canvas, {b.x - tick, py}, {b.x, py}, {0.25, 0.25, 0.25}, 1.5);
    draw_text(canvas, b.x - 1.6 * tick, py, format_tick(y, ystep), label);
  }
  TextStyle title{.size = fs, .horizontal = Align::middle, .vertical = Align::start};
  draw_text(canvas, b.x + 0.5 * b.w, b.y + b.h + 2.0 * fs, x_label, title);
  title.vertical = Align::end;
  title.angle = 0.5 * kPi;
  draw_text(canvas, b.x - 4.2 * fs, b.y + 0.5 * b.h, y_label, title);
}

// ---- Text and legends --------------------------------------------------------------------

void draw_text(Canvas& canvas, double x, double y, const std::string& text,
               const TextStyle& style) {
  cairo_t* cr = canvas.cr();
  select_font(cr, style);
  cairo_text_extents_t ext;
  cairo_text_extents(cr, text.c_str(), &ext);
  cairo_font_extents_t font;
  cairo_font_extents(cr, &font);
  const double dx = style.horizontal == Align::start    ? 0
                    : style.horizontal == Align::middle ? -0.5 * ext.x_advance
                                                        : -ext.x_advance;
  // Vertical placement from the font's ascent (stable for any text, unlike its ink extents).
  const double cap = 0.72 * style.size;
  const double dy = style.vertical == Align::start    ? cap
                    : style.vertical == Align::middle ? 0.5 * cap
                                                      : 0.0;
  cairo_save(cr);
  cairo_translate(cr, x, y);
  cairo_rotate(cr, -style.angle);
  cairo_move_to(cr, dx, dy);
  set_color(canvas, style.color);
  cairo_show_text(cr, text.c_str());
  cairo_restore(cr);
}

double text_width(Canvas& canvas, const std::string& text, const TextStyle& style) {
  select_font(canvas.cr(), style);
  cairo_text_extents_t ext;
  cairo_text_extents(canvas.cr(), text.c_str(), &ext);
  return ext.x_advance;
}

std::string fit_text(Canvas& canvas, const std::string& text, TextStyle& style, double room) {
  const double w = text_width(canvas, text, style);
  if (w <= room) return text;
  // Shrink in steps (hinted advances do not scale exactly with the size).
  const double smallest = 0.6 * style.size;
  style.size = std::max(smallest, style.size * room / w);
  while (style.size > smallest && text_width(canvas, text, style) > room)
    style.size = std::max(smallest, 0.97 * style.size);
  if (text_width(canvas, text, style) <= room) return text;
  std::string cut = text;
  while (!cut.empty() && text_width(canvas, cut + "…", style) > room) {
    // Drop the last UTF-8 character: its continuation bytes (10xxxxxx), then its lead byte.
    while (!cut.empty() && (static_cast<unsigned char>(cut.back()) & 0xC0) == 0x80) cut.pop_back();
    if (!cut.empty()) cut.pop_back();
  }
  return cut + "…";
}

void draw_title(Canvas& canvas, const Box& band, const std::string& heading,
                const std::string& subtitle) {
  const double fs = font_size(canvas), margin = 1.5 * fs, room = band.w - 2 * margin;
  TextStyle style{.size = 1.45 * fs, .bold = true};
  draw_text(canvas, band.x + margin, band.y + 0.42 * band.h, fit_text(canvas, heading, style, room),
            style);
  style = {.size = 0.95 * fs, .color = {0.3, 0.3, 0.3}};
  draw_text(canvas, band.x + margin, band.y + 0.80 * band.h,
            fit_text(canvas, subtitle, style, room), style);
}

void draw_colorbar(Canvas& canvas, const Box& strip, const ColorScale& scale,
                   const std::string& label) {
  cairo_t* cr = canvas.cr();
  const int steps = std::max(2, static_cast<int>(strip.h));
  for (int k = 0; k < steps; ++k) {  // one pixel row per colour, top = hi
    const double v = scale.hi - (scale.hi - scale.lo) * (k + 0.5) / steps;
    set_color(canvas, scale(v));
    cairo_rectangle(cr, strip.x, strip.y + strip.h * k / steps, strip.w, strip.h / steps + 0.6);
    cairo_fill(cr);
  }
  set_color(canvas, {0.25, 0.25, 0.25});
  cairo_set_line_width(cr, 1.2);
  cairo_rectangle(cr, strip.x, strip.y, strip.w, strip.h);
  cairo_stroke(cr);
  const double fs = font_size(canvas);
  const std::vector<double> ticks = nice_ticks(scale.lo, scale.hi, 6);
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : 1;
  const TextStyle text{.size = 0.8 * fs, .vertical = Align::middle};
  for (double v : ticks) {
    if (!(scale.hi > scale.lo)) break;
    const double y = strip.y + strip.h * (scale.hi - v) / (scale.hi - scale.lo);
    draw_line(canvas, {strip.x + strip.w, y}, {strip.x + strip.w + 0.4 * fs, y}, {0.25, 0.25, 0.25},
              1.2);
    draw_text(canvas, strip.x + strip.w + 0.6 * fs, y, format_tick(v, step), text);
  }
  if (!(scale.hi > scale.lo))
    draw_text(canvas, strip.x + strip.w + 0.6 * fs, strip.y + 0.5 * strip.h,
              format_tick(scale.lo, std::abs(scale.lo) / 100 + 1e-12), text);
  draw_text(canvas, strip.x - 0.6 * fs, strip.y + 0.5 * strip.h, label,
            {.size = fs, .horizontal = Align::middle, .vertical = Align::end, .angle = 0.5 * kPi});
}

void draw_scale_bar(Canvas& canvas, const Axes& axes, double x, double y) {
  const double ppu = axes.pixels_per_unit_x(), fs = font_size(canvas);
  // The longest round length (1, 2 or 5 × 10^k m) that fits in about 5 font sizes.
  const double room = 5.5 * fs / ppu;
  const double p = std::pow(10.0, std::floor(std::log10(room)));
  double length = p;
  for (double m : {2.0, 5.0})
    if (m * p <= room) length = m * p;
  const double w = length * ppu;
  cairo_t* cr = canvas.cr();
  set_color(canvas, {0.1, 0.1, 0.1});
  cairo_rectangle(cr, x, y - 0.3 * fs, 0.5 * w, 0.3 * fs);
  cairo_fill(cr);
  cairo_set_line_width(cr, 1.5);
  cairo_rectangle(cr, x, y - 0.3 * fs, w, 0.3 * fs);
  cairo_stroke(cr);
  draw_text(canvas, x + w + 0.5 * fs, y, fmt::format("{:g} m", length),
            {.size = 0.85 * fs, .vertical = Align::end});
}

void draw_grid(Canvas& canvas, const Axes& axes) {
  const Rgb grey{0.9, 0.9, 0.9};
  for (double x : nice_ticks(axes.x0, axes.x1, 8))
    draw_line(canvas, axes.to_pixel(x, axes.y0), axes.to_pixel(x, axes.y1), grey, 1);
  for (double y : nice_ticks(axes.y0, axes.y1, 7))
    draw_line(canvas, axes.to_pixel(axes.x0, y), axes.to_pixel(axes.x1, y), grey, 1);
}

double draw_legend(Canvas& canvas, const std::vector<LegendEntry>& entries, double x, double y,
                   double right) {
  const double fs = font_size(canvas);
  for (const LegendEntry& e : entries) {
    if (e.symbol == LegendSymbol::marker)
      draw_marker(canvas, {x + 1.2 * fs, y}, 0.5 * fs, e.color);
    else if (e.symbol == LegendSymbol::dashed)
      draw_dashed_line(canvas, {x, y}, {x + 2.4 * fs, y}, e.color, 2, 0.5 * fs);
    else
      draw_line(canvas, {x, y}, {x + 2.4 * fs, y}, e.color, 3);
    TextStyle style{.size = 0.9 * fs, .vertical = Align::middle};
    const double room = right - (x + 3.2 * fs), w = text_width(canvas, e.text, style);
    if (w > room && room > 0) style.size *= room / w;
    draw_text(canvas, x + 3.2 * fs, y, e.text, style);
    y += 1.8 * fs;
  }
  return y;
}

// ---- Drawing helpers ---------------------------------------------------------------------

void set_color(Canvas& canvas, const Rgb& c, double alpha) {
  cairo_set_source_rgba(canvas.cr(), c.r, c.g, c.b, alpha);
}

void draw_line(Canvas& canvas, const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Rgb& color,
               double width, double alpha) {
  cairo_t* cr = canvas.cr();
  set_color(canvas, color, alpha);
  cairo_set_line_width(cr, width);
  cairo_move_to(cr, a.x(), a.y());
  cairo_line_to(cr, b.x(), b.y());
  cairo_stroke(cr);
}

void draw_dashed_line(Canvas& canvas, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                      const Rgb& color, double width, double dash) {
  const double pattern[] = {dash, 0.6 * dash};
  cairo_set_dash(canvas.cr(), pattern, 2, 0);
  draw_line(canvas, a, b, color, width);
  cairo_set_dash(canvas.cr(), nullptr, 0, 0);
}

namespace {
// Fills the current path with `fill`, then strokes it with `outline` of `width` px.
void fill_and_outline(Canvas& canvas, const Rgb& fill, const Rgb& outline, double width) {
  set_color(canvas, fill);
  cairo_fill_preserve(canvas.cr());
  set_color(canvas, outline);
  cairo_set_line_width(canvas.cr(), width);
  cairo_stroke(canvas.cr());
}
}  // namespace

void draw_marker(Canvas& canvas, const Eigen::Vector2d& p, double radius, const Rgb& fill) {
  cairo_t* cr = canvas.cr();
  cairo_new_sub_path(cr);
  cairo_arc(cr, p.x(), p.y(), radius, 0, 2 * kPi);
  fill_and_outline(canvas, fill, {0.1, 0.1, 0.1}, 1.5);
}

void draw_square(Canvas& canvas, const Eigen::Vector2d& p, double size, const Rgb& fill) {
  cairo_t* cr = canvas.cr();
  cairo_rectangle(cr, p.x() - 0.5 * size, p.y() - 0.5 * size, size, size);
  fill_and_outline(canvas, fill, {0.05, 0.05, 0.05}, 1.2);
}

void draw_support_triangle(Canvas& canvas, const Eigen::Vector2d& p, double size, const Rgb& fill) {
  cairo_t* cr = canvas.cr();
  cairo_move_to(cr, p.x(), p.y());
  cairo_line_to(cr, p.x() + 0.6 * size, p.y() + size);
  cairo_line_to(cr, p.x() - 0.6 * size, p.y() + size);
  cairo_close_path(cr);
  fill_and_outline(canvas, fill, {0.05, 0.05, 0.05}, 1.2);
}

}  // namespace gridshell::figures
