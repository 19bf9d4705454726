#include "gridshell/figures/figures.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <numeric>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/mesh/topology.h"

namespace gridshell::figures {

namespace {

using Vec2 = Eigen::Vector2d;

constexpr double kPi = 3.14159265358979323846;

constexpr Rgb kBeamGrey{0.35, 0.35, 0.38};
constexpr Rgb kSupport{0.08, 0.08, 0.08};
constexpr Rgb kGlass{0.80, 0.87, 0.93};
constexpr Rgb kSurfaceEdge{0.42, 0.62, 0.42};  ///< the input surface's boundary in plan

std::vector<std::array<int, 2>> beams_of(const FigureInput& in) {
  if (!in.beams.empty()) return in.beams;
  return build_topology(*in.gridshell).edges;
}

/// The supported joints that exist (a support list never indexes off the joints).
std::vector<int> supports_of(const FigureInput& in) {
  std::vector<int> out;
  for (int v : in.supports)
    if (v >= 0 && v < in.gridshell->num_vertices()) out.push_back(v);
  return out;
}

/// The linear axial forces per beam [N] when the analysis has one per beam, else null.
const std::vector<double>* forces_of(const FigureInput& in, std::size_t beams) {
  if (!in.structure || in.structure->axial_force.size() != beams || beams == 0) return nullptr;
  return &in.structure->axial_force;
}

/// Diverging scale in kN centred at 0, symmetric about the 95th percentile of |N| (a few
/// heavily loaded beams at the supports would otherwise leave all others pale); beams beyond it
/// take the end colours.
ColorScale force_scale(const std::vector<double>& force) {
  std::vector<double> magnitude;
  magnitude.reserve(force.size());
  for (double n : force) magnitude.push_back(std::abs(n));
  const std::size_t k = (magnitude.size() * 95) / 100;
  std::nth_element(magnitude.begin(), magnitude.begin() + k, magnitude.end());
  double m = magnitude.empty() ? 0 : magnitude[std::min(k, magnitude.size() - 1)];
  m = m > 0 ? m / 1000 : 1;
  return {ColorMap::diverging, -m, m};
}

/// The colour bar of axial forces and, under it, the range of all forces.
void draw_force_legend(Canvas& canvas, const PageLayout& page, const ColorScale& scale,
                       const std::vector<double>& force) {
  draw_colorbar(canvas, page.legend, scale, "axial force [kN]  (− compression, + tension)");
  double lo = 0, hi = 0;
  for (double n : force) lo = std::min(lo, n / 1000), hi = std::max(hi, n / 1000);
  const double fs = font_size(canvas);
  const TextStyle small{.size = 0.7 * fs, .color = {0.3, 0.3, 0.3}};
  const double x = page.legend.x - 1.6 * fs, y = page.legend.y + page.legend.h + 1.6 * fs;
  // Round-off forces (e.g. 1e-17 kN in an unloaded beam) print as 0.
  const double tiny = 1e-9 * std::max(-lo, hi);
  if (std::abs(lo) < tiny) lo = 0;
  if (std::abs(hi) < tiny) hi = 0;
  draw_text(canvas, x, y, fmt::format("range {:.3g} … {:.3g} kN", lo, hi), small);
  draw_text(canvas, x, y + 1.0 * fs, fmt::format("(colours end at ±{:.3g})", scale.hi), small);
}

/// Largest plan extent of the points (the analysis' "span").
double plan_span(const Points& V) {
  if (V.rows() == 0) return 1;
  const Eigen::RowVector3d lo = V.colwise().minCoeff(), hi = V.colwise().maxCoeff();
  return std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-9});
}

/// Line width of beams: about an eighth of the median beam length on screen, within 1.5 … 5 px.
double beam_width(const std::vector<std::array<int, 2>>& beams, const std::vector<Vec2>& pixel) {
  if (beams.empty()) return 2;
  std::vector<double> len;
  len.reserve(beams.size());
  for (const auto& b : beams) len.push_back((pixel[b[0]] - pixel[b[1]]).norm());
  std::nth_element(len.begin(), len.begin() + len.size() / 2, len.end());
  return std::clamp(len[len.size() / 2] / 8, 1.5, 5.0);
}

void draw_supports_legend(Canvas& canvas, const PageLayout& page, bool triangle) {
  const double fs = font_size(canvas);
  const Vec2 p(page.legend.x - 1.0 * fs, page.legend.y + page.legend.h + 5.0 * fs);
  if (triangle)
    draw_support_triangle(canvas, p - Vec2(0, 0.5 * fs), fs, kSupport);
  else
    draw_square(canvas, p, 0.8 * fs, kSupport);
  draw_text(canvas, p.x() + 1.2 * fs, p.y(), "support",
            {.size = 0.85 * fs, .vertical = Align::middle});
}

std::string force_heading(const char* view, bool coloured) {
  if (!coloured) return fmt::format("{} of the grid-shell (not analysed)", view);
  return fmt::format(
      "{}: beams by axial force of the linear analysis (λ = 1; compression red, "
      "tension blue)",
      view);
}

/// A fixed perspective camera looking at the points' bounding box from azimuth −60° and
/// elevation 30° at 2.8 × its half diagonal.
struct Camera {
  Vec3 eye, right, up, forward;
  Vec2 screen(const Vec3& p) const {
    const Vec3 d = p - eye;
    const double z = std::max(d.dot(forward), 1e-9);
    return {d.dot(right) / z, d.dot(up) / z};
  }
  double depth(const Vec3& p) const { return (p - eye).dot(forward); }
};

Camera view_camera(const Points& V) {
  const Vec3 lo = V.colwise().minCoeff().transpose(), hi = V.colwise().maxCoeff().transpose();
  const Vec3 centre = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * (hi - lo).norm(), 1e-6);
  const double az = -60 * kPi / 180, el = 30 * kPi / 180;
  Camera c;
  const Vec3 dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  c.eye = centre + 2.8 * radius * dir;
  c.forward = -dir;
  c.right = c.forward.cross(Vec3::UnitZ()).normalized();
  c.up = c.right.cross(c.forward);
  return c;
}

/// Axes for the projected points `s` in the 3D views' box (no frame drawn), equal scale.
Axes screen_axes(const std::vector<Vec2>& s, const Box& box) {
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const Vec2& p : s) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  if (s.empty()) lo.setZero(), hi.setOnes();
  const Vec2 pad = 0.04 * (hi - lo);
  return make_axes(box, lo.x() - pad.x(), hi.x() + pad.x(), lo.y() - pad.y(), hi.y() + pad.y(),
                   true);
}

Box view_box(const Canvas& canvas) {
  const double w = canvas.width(), h = canvas.height();
  return {0.03 * w, 0.13 * h, 0.80 * w, 0.84 * h};
}

/// Pixel positions of 3D points through a camera and screen axes.
std::vector<Vec2> to_pixels(const Points& V, const Camera& cam, const Axes& axes) {
  std::vector<Vec2> px(V.rows());
  for (int v = 0; v < V.rows(); ++v) {
    const Vec2 s = cam.screen(V.row(v).transpose());
    px[v] = axes.to_pixel(s.x(), s.y());
  }
  return px;
}

/// Beam indices from far to near (painter's order) by the depth of their midpoints.
std::vector<int> far_to_near(const std::vector<std::array<int, 2>>& beams, const Points& V,
                             const Camera& cam) {
  std::vector<double> depth(beams.size());
  for (std::size_t k = 0; k < beams.size(); ++k)
    depth[k] = cam.depth(0.5 * (V.row(beams[k][0]) + V.row(beams[k][1])).transpose());
  std::vector<int> order(beams.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return depth[a] > depth[b]; });
  return order;
}

/// x with 4 significant digits, written out (no exponent) from 10⁴ to 10⁷.
std::string number(double x) {
  const double a = std::abs(x);
  return a >= 1e4 && a < 1e7 ? fmt::format("{:.0f}", x) : fmt::format("{:.4g}", x);
}

/// n in Unicode subscript digits ("₁₂").
std::string subscript(std::size_t n) {
  static const char* kDigits[] = {"₀", "₁", "₂", "₃", "₄", "₅", "₆", "₇", "₈", "₉"};
  std::string s = n >= 10 ? subscript(n / 10) : "";
  return s + kDigits[n % 10];
}

/// A figure to make: its file name and how to draw it.
using FigureJob = std::pair<std::string, std::function<Canvas()>>;

/// Draws and encodes the figures in parallel (each reads only its own input; the PNG compression
/// is most of a figure's cost) and writes them, after the already encoded `first`, into
/// DIR/figures/ in order; returns their paths relative to DIR.
std::vector<std::string> write_pngs(const std::filesystem::path& dir, EncodedFigures first,
                                    const std::vector<FigureJob>& jobs) {
  std::vector<std::string> bytes(jobs.size()), written;
  tbb::parallel_for(std::size_t{0}, jobs.size(),
                    [&](std::size_t k) { bytes[k] = jobs[k].second().png(); });
  for (std::size_t k = 0; k < jobs.size(); ++k)
    first.push_back({jobs[k].first, std::move(bytes[k])});
  if (first.empty()) return written;
  const std::filesystem::path folder = dir / "figures";
  io::ensure_directory(folder);
  for (const auto& [name, png] : first) {
    io::write_file_atomic(folder / name, png);
    written.push_back("figures/" + name);
  }
  return written;
}

void check_size(const FigureOptions& o) {
  Canvas probe(o.width, o.height);
}

}  // namespace

FigureOptions parse_figure_options(const std::string& word) {
  FigureOptions o;
  if (word == "none") {
    o.enabled = false;
    return o;
  }
  const std::size_t x = word.find_first_of("xX");
  const auto bad = [&] {
    return Error(
        "--figures",
        fmt::format("'{}' is not WxH in pixels (64..8192 each, e.g. 1600x1200) or none", word));
  };
  if (x == std::string::npos) throw bad();
  const std::string ws = word.substr(0, x), hs = word.substr(x + 1);
  char* end = nullptr;
  const long w = std::strtol(ws.c_str(), &end, 10);
  if (ws.empty() || *end != '\0') throw bad();
  const long h = std::strtol(hs.c_str(), &end, 10);
  if (hs.empty() || *end != '\0') throw bad();
  if (w < 64 || h < 64 || w > 8192 || h > 8192) throw bad();
  o.width = static_cast<int>(w);
  o.height = static_cast<int>(h);
  return o;
}

Axes plan_axes(const Points& V, const FigureOptions& options) {
  const PageLayout page = page_layout(options.width, options.height);
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (V.rows() > 0) {
    x0 = V.col(0).minCoeff(), x1 = V.col(0).maxCoeff();
    y0 = V.col(1).minCoeff(), y1 = V.col(1).maxCoeff();
  }
  const double pad = 0.04 * std::max(x1 - x0, y1 - y0);
  return make_axes(page.plot, x0 - pad, x1 + pad, y0 - pad, y1 + pad, true);
}

Canvas draw_plan(const FigureInput& in, const FigureOptions& options) {
  Canvas canvas(options.width, options.height);
  const PageLayout page = page_layout(options.width, options.height);
  const Points& V = in.gridshell->V;
  const auto beams = beams_of(in);
  const auto* force = forces_of(in, beams.size());
  // The input surface's boundary, when given, is drawn under the beams (and kept in view), so
  // what the grid leaves uncovered shows.
  std::vector<std::vector<int>> edge_loops;
  Points framed = V;
  if (in.surface && in.surface->num_faces() > 0) {
    edge_loops = build_topology(*in.surface).boundary_loops;
    framed.resize(V.rows() + in.surface->num_vertices(), 3);
    framed << V, in.surface->V;
  }
  const Axes axes = plan_axes(framed, options);
  for (const auto& loop : edge_loops)
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const auto a = in.surface->V.row(loop[k]), b = in.surface->V.row(loop[(k + 1) % loop.size()]);
      draw_line(canvas, axes.to_pixel(a(0), a(1)), axes.to_pixel(b(0), b(1)), kSurfaceEdge, 2.0);
    }
  std::vector<Vec2> px(V.rows());
  for (int v = 0; v < V.rows(); ++v) px[v] = axes.to_pixel(V(v, 0), V(v, 1));
  // Lowest beams first, so that what is on top in plan is drawn on top.
  std::vector<int> order(beams.size());
  std::iota(order.begin(), order.end(), 0);
  auto height = [&](int k) { return V(beams[k][0], 2) + V(beams[k][1], 2); };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return height(a) < height(b); });
  const double width = beam_width(beams, px);
  const ColorScale scale = force ? force_scale(*force) : ColorScale{};
  for (int k : order)
    draw_line(canvas, px[beams[k][0]], px[beams[k][1]],
              force ? scale((*force)[k] / 1000) : kBeamGrey, width);
  for (int v : supports_of(in)) draw_square(canvas, px[v], 2 * width + 6, kSupport);
  draw_axes(canvas, axes, "x [m]", "y [m]");
  const double fs = font_size(canvas);
  if (force) draw_force_legend(canvas, page, scale, *force);
  draw_supports_legend(canvas, page, false);
  if (!edge_loops.empty()) {
    const Vec2 p(page.legend.x - 1.4 * fs, page.legend.y + page.legend.h + 7.0 * fs);
    draw_line(canvas, p, p + Vec2(0.8 * fs, 0), kSurfaceEdge, 2.0);
    draw_text(canvas, p.x() + 1.6 * fs, p.y(), "surface edge",
              {.size = 0.85 * fs, .vertical = Align::middle});
  }
  draw_scale_bar(canvas, axes, page.legend.x - 1.0 * fs, page.legend.y + page.legend.h + 9.0 * fs);
  draw_title(canvas, page.title, force_heading("Plan view", force != nullptr), in.title);
  return canvas;
}

Canvas draw_perspective(const FigureInput& in, const FigureOptions& options) {
  Canvas canvas(options.width, options.height);
  const PageLayout page = page_layout(options.width, options.height);
  const PolyMesh& mesh = *in.gridshell;
  const Points& V = mesh.V;
  const auto beams = beams_of(in);
  const auto* force = forces_of(in, beams.size());
  const Camera cam = view_camera(V);
  std::vector<Vec2> s(V.rows());
  for (int v = 0; v < V.rows(); ++v) s[v] = cam.screen(V.row(v).transpose());
  const Axes axes = screen_axes(s, view_box(canvas));
  const std::vector<Vec2> px = to_pixels(V, cam, axes);
  const double width = beam_width(beams, px);
  const ColorScale scale = force ? force_scale(*force) : ColorScale{};
  // Panels and beams in one far-to-near list: panels as light glass under their beams.
  struct Item {
    double depth;
    int index;  ///< ≥ 0 beam, < 0 panel −1 − index
  };
  std::vector<Item> items;
  items.reserve(beams.size() + mesh.faces.size());
  for (std::size_t k = 0; k < beams.size(); ++k)
    items.push_back({cam.depth(0.5 * (V.row(beams[k][0]) + V.row(beams[k][1])).transpose()),
                     static_cast<int>(k)});
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    Vec3 c = Vec3::Zero();
    for (int v : mesh.faces[f]) c += V.row(v).transpose();
    if (!mesh.faces[f].empty()) c /= static_cast<double>(mesh.faces[f].size());
    items.push_back({cam.depth(c) + 1e-9, -1 - static_cast<int>(f)});
  }
  std::stable_sort(items.begin(), items.end(),
                   [](const Item& a, const Item& b) { return a.depth > b.depth; });
  cairo_t* cr = canvas.cr();
  for (const Item& it : items) {
    if (it.index >= 0) {
      const auto& b = beams[it.index];
      draw_line(canvas, px[b[0]], px[b[1]], force ? scale((*force)[it.index] / 1000) : kBeamGrey,
                width);
      continue;
    }
    const auto& face = mesh.faces[-1 - it.index];
    if (face.size() < 3) continue;
    cairo_move_to(cr, px[face[0]].x(), px[face[0]].y());
    for (std::size_t k = 1; k < face.size(); ++k)
      cairo_line_to(cr, px[face[k]].x(), px[face[k]].y());
    cairo_close_path(cr);
    set_color(canvas, kGlass, 0.45);
    cairo_fill(cr);
  }
  for (int v : supports_of(in)) draw_support_triangle(canvas, px[v], 2 * width + 8, kSupport);
  if (force) draw_force_legend(canvas, page, scale, *force);
  draw_supports_legend(canvas, page, true);
  draw_title(canvas, page.title, force_heading("Perspective", force != nullptr), in.title);
  return canvas;
}

namespace {

/// One direction segment of the field figure: the triangle whose field it shows and where (plan).
struct DirectionSample {
  int face = -1;
  double x = 0, y = 0;
};

/// The field figure's direction segments on a plan grid of square cells of side `cell`: at a
/// cell's centre, the highest triangle that covers it in plan; where none does (a cell on the
/// boundary), at the centroid of the triangle whose centroid is nearest the centre among those
/// in the cell. The segments then stand on a regular grid however coarse the triangles are.
std::vector<DirectionSample> direction_samples(const TriMesh& M, const Axes& axes, double cell) {
  const int nx = static_cast<int>(std::ceil((axes.x1 - axes.x0) / cell));
  const int ny = static_cast<int>(std::ceil((axes.y1 - axes.y0) / cell));
  const auto centre = [&](int i, int j) {
    return Vec2(axes.x0 + (i + 0.5) * cell, axes.y0 + (j + 0.5) * cell);
  };
  std::vector<DirectionSample> pick(static_cast<std::size_t>(nx) * ny);
  std::vector<double> best(pick.size(), 1e300), top(pick.size(), -1e300);
  std::vector<char> covered(pick.size(), 0);
  for (int f = 0; f < M.num_faces(); ++f) {
    const Vec3 a = M.vertex(M.F(f, 0)), b = M.vertex(M.F(f, 1)), c = M.vertex(M.F(f, 2));
    const Vec3 g = (a + b + c) / 3;
    const int ci = std::clamp(static_cast<int>((g.x() - axes.x0) / cell), 0, nx - 1);
    const int cj = std::clamp(static_cast<int>((g.y() - axes.y0) / cell), 0, ny - 1);
    const std::size_t own = static_cast<std::size_t>(cj) * nx + ci;
    const double dist = (g.head<2>() - centre(ci, cj)).norm();
    if (!covered[own] && dist < best[own]) best[own] = dist, pick[own] = {f, g.x(), g.y()};
    // The cell centres inside the triangle's plan bounding box, tested by their barycentric
    // coordinates (a triangle seen edge-on in plan covers none).
    const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (!(std::abs(det) > 0)) continue;
    const auto index = [&](double v, double v0, int n) {
      return std::clamp(static_cast<int>(std::floor((v - v0) / cell - 0.5)), -1, n - 1);
    };
    const int i0 = index(std::min({a.x(), b.x(), c.x()}), axes.x0, nx) + 1;
    const int i1 = index(std::max({a.x(), b.x(), c.x()}), axes.x0, nx);
    const int j0 = index(std::min({a.y(), b.y(), c.y()}), axes.y0, ny) + 1;
    const int j1 = index(std::max({a.y(), b.y(), c.y()}), axes.y0, ny);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const Vec2 p = centre(i, j);
        const double s =
            ((b.x() - p.x()) * (c.y() - p.y()) - (c.x() - p.x()) * (b.y() - p.y())) / det;
        const double t =
            ((c.x() - p.x()) * (a.y() - p.y()) - (a.x() - p.x()) * (c.y() - p.y())) / det;
        if (s < 0 || t < 0 || s + t > 1) continue;
        const double z = s * a.z() + t * b.z() + (1 - s - t) * c.z();
        const std::size_t slot = static_cast<std::size_t>(j) * nx + i;
        if (covered[slot] && z <= top[slot]) continue;
        covered[slot] = 1, top[slot] = z, pick[slot] = {f, p.x(), p.y()};
      }
  }
  std::erase_if(pick, [](const DirectionSample& d) { return d.face < 0; });
  return pick;
}

}  // namespace

Canvas draw_field(const FigureInput& in, const FigureOptions& options) {
  Canvas canvas(options.width, options.height);
  const PageLayout page = page_layout(options.width, options.height);
  const TriMesh& M = *in.surface;
  const Field& field = *in.field;
  const Axes axes = plan_axes(M.V, options);
  cairo_t* cr = canvas.cr();
  double d_max = 1, a_max = 1;
  for (double d : field.d) d_max = std::max(d_max, d);
  for (double a : field.a) a_max = std::max(a_max, a);
  const ColorScale scale{ColorMap::sequential, 1, d_max};
  // Triangles lowest first; each also stroked in its colour so no seams show between them.
  std::vector<int> order(M.num_faces());
  std::iota(order.begin(), order.end(), 0);
  auto height = [&](int f) { return M.V(M.F(f, 0), 2) + M.V(M.F(f, 1), 2) + M.V(M.F(f, 2), 2); };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return height(a) < height(b); });
  cairo_set_line_width(cr, 0.8);
  for (int f : order) {
    for (int k = 0; k < 3; ++k) {
      const Vec2 p = axes.to_pixel(M.V(M.F(f, k), 0), M.V(M.F(f, k), 1));
      k == 0 ? cairo_move_to(cr, p.x(), p.y()) : cairo_line_to(cr, p.x(), p.y());
    }
    cairo_close_path(cr);
    set_color(canvas, scale(field.d[f]));
    cairo_fill_preserve(cr);
    cairo_stroke(cr);
  }
  // The grid-shell's beams, faint, to compare the cells with the field.
  if (in.gridshell) {
    const auto beams = beams_of(in);
    const Points& V = in.gridshell->V;
    for (const auto& b : beams)
      draw_line(canvas, axes.to_pixel(V(b[0], 0), V(b[0], 1)),
                axes.to_pixel(V(b[1], 0), V(b[1], 1)), {1, 1, 1}, 1.2, 0.6);
  }
  // Direction segments on a plan grid (direction_samples).
  const double cell = std::max(axes.x1 - axes.x0, axes.y1 - axes.y0) / 48;
  const double cell_px = cell * axes.pixels_per_unit_x();
  const bool isotropic = a_max <= 1 + 1e-9;  // no stretch, so u means nothing
  for (const DirectionSample& sample :
       isotropic ? std::vector<DirectionSample>{} : direction_samples(M, axes, cell)) {
    const int f = sample.face;
    const Vec2 u(field.u[f].x(), field.u[f].y());
    if (u.norm() < 1e-6) continue;
    const double t = (field.a[f] - 1) / (a_max - 1);
    const Vec2 p = axes.to_pixel(sample.x, sample.y);
    // u in plan keeps its foreshortening: a steep u draws a short segment.
    const Vec2 half = 0.5 * cell_px * (0.35 + 0.6 * t) * Vec2(u.x(), -u.y());
    draw_line(canvas, p - half, p + half, {0.05, 0.05, 0.05}, 2.0, 0.4 + 0.6 * t);
  }
  draw_axes(canvas, axes, "x [m]", "y [m]");
  const double fs = font_size(canvas);
  draw_scale_bar(canvas, axes, page.legend.x - 1.0 * fs, page.legend.y + page.legend.h + 3.0 * fs);
  draw_colorbar(canvas, page.legend, scale, "density d  (cells 1/d across; 1 … D)");
  draw_title(canvas, page.title,
             isotropic ? std::string("Design field: density d (colour); isotropic cells (a = 1), "
                                     "no stretch direction")
                       : fmt::format("Design field: density d (colour), stretch direction u "
                                     "(segments; longer and darker = more anisotropic, a up to "
                                     "{:.3g})",
                                     a_max),
             in.title);
  return canvas;
}

Canvas draw_buckling_mode(const FigureInput& in, const FigureOptions& options) {
  Canvas canvas(options.width, options.height);
  const PageLayout page = page_layout(options.width, options.height);
  const analysis::FrameResult& st = *in.structure;
  const Points& V = in.gridshell->V;
  const Points& mode = st.buckling_modes.front();
  const auto beams = beams_of(in);
  const double span = plan_span(V), amplitude = 0.1 * span;
  const Points W = V + amplitude * mode;
  const Camera cam = view_camera(V);
  std::vector<Vec2> s;
  s.reserve(2 * V.rows());
  for (const Points* P : {&V, &W})
    for (int v = 0; v < P->rows(); ++v) s.push_back(cam.screen(P->row(v).transpose()));
  const Axes axes = screen_axes(s, view_box(canvas));
  const std::vector<Vec2> p0 = to_pixels(V, cam, axes), p1 = to_pixels(W, cam, axes);
  const double width = beam_width(beams, p0);
  for (const auto& b : beams) draw_line(canvas, p0[b[0]], p0[b[1]], {0.78, 0.78, 0.80}, 1.2);
  const ColorScale scale{ColorMap::sequential, 0, 1};
  const Eigen::VectorXd magnitude = mode.rowwise().norm();
  for (int k : far_to_near(beams, W, cam)) {
    const auto& b = beams[k];
    draw_line(canvas, p1[b[0]], p1[b[1]], scale(0.5 * (magnitude[b[0]] + magnitude[b[1]])), width);
  }
  for (int v : supports_of(in)) draw_support_triangle(canvas, p0[v], 2 * width + 8, kSupport);
  draw_colorbar(canvas, page.legend, scale, "mode displacement  (largest = 1)");
  draw_supports_legend(canvas, page, true);
  // The next factors under the legend: close ones mean a near-degenerate (symmetric) mode.
  const double fs = font_size(canvas);
  for (std::size_t k = 1; k < std::min<std::size_t>(st.buckling_lambdas.size(), 4); ++k)
    draw_text(canvas, page.legend.x - 1.0 * fs,
              page.legend.y + page.legend.h + (6.5 + 1.1 * static_cast<double>(k)) * fs,
              fmt::format("λ{} = {}", subscript(k + 1), number(st.buckling_lambdas[k])),
              {.size = 0.8 * fs, .color = {0.3, 0.3, 0.3}});
  draw_title(canvas, page.title,
             fmt::format("First buckling mode: λ₁ = {} (linearised buckling), at 10 % of the "
                         "span ({:.3g} m) over the undeformed grid (grey)",
                         number(st.buckling_lambdas.front()), amplitude),
             in.title);
  return canvas;
}

Canvas draw_load_path(const FigureInput& in, const FigureOptions& options) {
  Canvas canvas(options.width, options.height);
  const PageLayout page = page_layout(options.width, options.height);
  const analysis::FrameResult& st = *in.structure;
  const std::vector<fem::PathPoint>& path = st.path;
  const double limit_mm = st.displacement_limit_m * 1000;
  double x_max = 0, y_max = 0;
  for (const auto& p : path)
    x_max = std::max(x_max, p.displacement * 1000), y_max = std::max(y_max, p.lambda);
  const bool show_limit = limit_mm > 0 && limit_mm < 1.5 * x_max;
  if (show_limit) x_max = std::max(x_max, limit_mm);
  if (st.lambda_linear_buckling && *st.lambda_linear_buckling < 1.5 * y_max)
    y_max = std::max(y_max, *st.lambda_linear_buckling);
  Box box = page.plot;
  box.w = 0.62 * options.width;  // room for the legend at the right
  const Axes axes = make_axes(box, 0, x_max * 1.05, 0, y_max * 1.08, false);
  const double fs = font_size(canvas);
  cairo_t* cr = canvas.cr();
  cairo_save(cr);
  cairo_rectangle(cr, box.x, box.y, box.w, box.h);
  cairo_clip(cr);
  draw_grid(canvas, axes);
  const Rgb path_color{0.10, 0.25, 0.60}, lba_color{0.75, 0.10, 0.10},
      limit_color{0.45, 0.45, 0.45}, linear_color{0.25, 0.60, 0.30}, delta_color{0.95, 0.55, 0.05},
      critical_color{0.85, 0.15, 0.60};
  std::vector<LegendEntry> legend;
  if (st.delta_max_m > 0) {  // the linear response λ δ_lin
    draw_dashed_line(canvas, axes.to_pixel(0, 0),
                     axes.to_pixel(axes.x1, axes.x1 / (st.delta_max_m * 1000)), linear_color, 2, 3);
    legend.push_back({linear_color, LegendSymbol::dashed,
                      fmt::format("linear (δ = {:.3g} mm at λ = 1)", st.delta_max_m * 1000)});
  }
  if (st.lambda_linear_buckling) {
    const double l = *st.lambda_linear_buckling;
    draw_dashed_line(canvas, axes.to_pixel(axes.x0, l), axes.to_pixel(axes.x1, l), lba_color, 2,
                     14);
    legend.push_back({lba_color, LegendSymbol::dashed, "λ_LBA = " + number(l)});
  }
  if (show_limit) {
    draw_dashed_line(canvas, axes.to_pixel(limit_mm, axes.y0), axes.to_pixel(limit_mm, axes.y1),
                     limit_color, 2, 8);
    legend.push_back(
        {limit_color, LegendSymbol::dashed, fmt::format("displacement limit {:.3g} mm", limit_mm)});
  }
  cairo_set_line_width(cr, 3);
  set_color(canvas, path_color);
  for (std::size_t k = 0; k < path.size(); ++k) {
    const Vec2 p = axes.to_pixel(path[k].displacement * 1000, path[k].lambda);
    k == 0 ? cairo_move_to(cr, p.x(), p.y()) : cairo_line_to(cr, p.x(), p.y());
  }
  cairo_stroke(cr);
  for (const auto& pt : path) {  // the converged points, while they stay apart
    if (path.size() > 60) break;
    const Vec2 p = axes.to_pixel(pt.displacement * 1000, pt.lambda);
    cairo_new_sub_path(cr);
    cairo_arc(cr, p.x(), p.y(), 4, 0, 2 * kPi);
    cairo_fill(cr);
  }
  legend.push_back(
      {path_color, LegendSymbol::line, fmt::format("non-linear path ({} points)", path.size())});
  if (st.lambda_displacement_limit && show_limit) {
    draw_marker(canvas, axes.to_pixel(limit_mm, *st.lambda_displacement_limit), 0.5 * fs,
                delta_color);
    legend.push_back(
        {delta_color, LegendSymbol::marker, "λ_δ = " + number(*st.lambda_displacement_limit)});
  }
  if (st.lambda_nonlinear && st.limit_type != fem::LimitType::none) {
    // At the path point nearest the critical factor.
    std::size_t best = 0;
    for (std::size_t k = 1; k < path.size(); ++k)
      if (std::abs(path[k].lambda - *st.lambda_nonlinear) <
          std::abs(path[best].lambda - *st.lambda_nonlinear))
        best = k;
    draw_marker(canvas, axes.to_pixel(path[best].displacement * 1000, *st.lambda_nonlinear),
                0.5 * fs, critical_color);
    legend.push_back(
        {critical_color, LegendSymbol::marker,
         fmt::format("λ = {} ({})", number(*st.lambda_nonlinear), fem::to_string(st.limit_type))});
  }
  cairo_restore(cr);
  draw_axes(canvas, axes, "largest displacement [mm]", "load factor λ  (× reference load)");
  const double lx = box.x + box.w + 2.0 * fs;
  const double ly = draw_legend(canvas, legend, lx, box.y + fs, options.width - 0.8 * fs);
  if (!st.nonlinear_stop_reason.empty())
    draw_text(canvas, lx, ly + 0.5 * fs, "path ended: " + st.nonlinear_stop_reason,
              {.size = 0.75 * fs, .color = {0.35, 0.35, 0.35}, .vertical = Align::middle});
  draw_title(canvas, page.title,
             "Load–displacement path of the geometrically non-linear analysis (arc-length)",
             in.title);
  return canvas;
}

Canvas draw_heatmap(const SweepGrid& grid, const HeatmapLabels& labels,
                    const FigureOptions& options) {
  Canvas canvas(options.width, options.height);
  const PageLayout page = page_layout(options.width, options.height);
  const int nd = static_cast<int>(grid.D.size()), na = static_cast<int>(grid.A.size());
  double lo = 1e300, hi = -1e300;
  for (int j = 0; j < na; ++j)
    for (int i = 0; i < nd; ++i)
      if (std::isfinite(grid.mean(j, i))) {
        lo = std::min(lo, labels.scale * grid.mean(j, i));
        hi = std::max(hi, labels.scale * grid.mean(j, i));
      }
  if (lo > hi) lo = 0, hi = 1;
  const ColorScale scale{ColorMap::sequential, lo, hi};
  const Box& box = page.plot;
  const double cw = box.w / std::max(nd, 1), ch = box.h / std::max(na, 1);
  const double fs = font_size(canvas);
  cairo_t* cr = canvas.cr();
  const double value_size = std::clamp(std::min(cw / 4.5, ch / 2.5), 0.5 * fs, 1.3 * fs);
  for (int j = 0; j < na; ++j)
    for (int i = 0; i < nd; ++i) {
      const double x = box.x + i * cw, y = box.y + (na - 1 - j) * ch;  // A grows upwards
      const double v = labels.scale * grid.mean(j, i);
      const bool has = std::isfinite(v);
      const Rgb c = has ? scale(v) : Rgb{0.85, 0.85, 0.85};
      cairo_rectangle(cr, x, y, cw, ch);
      set_color(canvas, c);
      cairo_fill_preserve(cr);
      set_color(canvas, {1, 1, 1});
      cairo_set_line_width(cr, 2);
      cairo_stroke(cr);
      const double luminance = 0.3 * c.r + 0.59 * c.g + 0.11 * c.b;
      draw_text(canvas, x + 0.5 * cw, y + 0.5 * ch, has ? fmt::format("{:.3g}", v) : "–",
                {.size = value_size,
                 .bold = true,
                 .color = luminance > 0.55 ? Rgb{0.05, 0.05, 0.05} : Rgb{1, 1, 1},
                 .horizontal = Align::middle,
                 .vertical = Align::middle});
    }
  set_color(canvas, {0.25, 0.25, 0.25});
  cairo_set_line_width(cr, 1.5);
  cairo_rectangle(cr, box.x, box.y, box.w, box.h);
  cairo_stroke(cr);
  const TextStyle tick{.size = 0.9 * fs, .horizontal = Align::middle, .vertical = Align::start};
  for (int i = 0; i < nd; ++i)
    draw_text(canvas, box.x + (i + 0.5) * cw, box.y + box.h + 0.6 * fs,
              fmt::format("{:g}", grid.D[i]), tick);
  for (int j = 0; j < na; ++j)
    draw_text(canvas, box.x - 0.6 * fs, box.y + (na - 1 - j + 0.5) * ch,
              fmt::format("{:g}", grid.A[j]),
              {.size = 0.9 * fs, .horizontal = Align::end, .vertical = Align::middle});
  draw_text(canvas, box.x + 0.5 * box.w, box.y + box.h + 2.2 * fs, "density ratio D",
            {.size = fs, .horizontal = Align::middle, .vertical = Align::start});
  draw_text(canvas, box.x - 2.6 * fs, box.y + 0.5 * box.h, "anisotropy ratio A",
            {.size = fs, .horizontal = Align::middle, .angle = 0.5 * kPi});
  draw_colorbar(canvas, page.legend, scale, labels.value_label);
  draw_title(canvas, page.title, labels.heading, labels.subtitle);
  return canvas;
}

EncodedFigures encode_linear_figures(const FigureInput& in, const FigureOptions& options) {
  if (!options.enabled) return {};
  check_size(options);
  EncodedFigures out;
  if (!in.gridshell || in.gridshell->num_vertices() == 0) return out;
  out.push_back({"top.png", draw_plan(in, options).png()});
  out.push_back({"perspective.png", draw_perspective(in, options).png()});
  return out;
}

std::vector<std::string> write_figures(const std::filesystem::path& dir, const FigureInput& in,
                                       const FigureOptions& options,
                                       std::optional<EncodedFigures> linear) {
  if (!options.enabled) return {};
  check_size(options);
  std::vector<FigureJob> jobs;
  const auto add = [&](const char* name, Canvas (*draw)(const FigureInput&, const FigureOptions&)) {
    jobs.emplace_back(name, [&in, &options, draw] { return draw(in, options); });
  };
  const bool mesh = in.gridshell && in.gridshell->num_vertices() > 0;
  const analysis::FrameResult* st = in.structure;
  if (mesh && !linear) {
    add("top.png", draw_plan);
    add("perspective.png", draw_perspective);
  }
  if (in.surface && in.field && in.field->size() == in.surface->num_faces() &&
      in.field->size() > 0 && static_cast<int>(in.field->d.size()) == in.field->size() &&
      static_cast<int>(in.field->a.size()) == in.field->size())
    add("field.png", draw_field);
  if (mesh && st && !st->buckling_modes.empty() && !st->buckling_lambdas.empty() &&
      st->buckling_modes.front().rows() == in.gridshell->V.rows())
    add("buckling_mode.png", draw_buckling_mode);
  if (st && st->path.size() >= 2) add("load_path.png", draw_load_path);
  return write_pngs(dir, linear ? std::move(*linear) : EncodedFigures{}, jobs);
}

std::vector<std::string> write_sweep_figures(const std::filesystem::path& dir,
                                             const std::vector<SweepRow>& rows,
                                             const std::string& title,
                                             const FigureOptions& options) {
  if (!options.enabled) return {};
  check_size(options);
  if (rows.empty()) return {};
  int repeats = 0;
  for (const auto& r : rows) repeats = std::max(repeats, r.c.repeat + 1);
  const std::string per_cell =
      fmt::format("mean of {} repeat{} per cell", repeats, repeats == 1 ? "" : "s");
  const HeatmapLabels lambda{
      fmt::format("Buckling factor λ over density ratio D and anisotropy ratio A ({})", per_cell),
      title, "λ  (non-linear; else λ_LBA)", 1};
  const HeatmapLabels delta{
      fmt::format("Largest deflection δ over density ratio D and anisotropy ratio A ({})",
                  per_cell),
      title, "δ [mm]  (linear, λ = 1)", 1000};
  std::vector<FigureJob> jobs;
  jobs.emplace_back("lambda_heatmap.png", [&] {
    return draw_heatmap(sweep_grid(rows, [](const SweepRow& r) { return r.lambda; }), lambda,
                        options);
  });
  jobs.emplace_back("delta_heatmap.png", [&] {
    return draw_heatmap(sweep_grid(rows, [](const SweepRow& r) { return r.delta; }), delta,
                        options);
  });
  return write_pngs(dir, {}, jobs);
}

}  // namespace gridshell::figures
