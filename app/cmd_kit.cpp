// gridshell kit DIR -o OUT [--scale 1:50] [--rod 3mm] [--clearance 0.1mm] [--min-socket MM]
// [--label-stroke 0.6mm] [--bed 600x400mm] [--kerf 0.15mm] [--print-bed 200x200mm]: a desk
// model of a design folder's grid-shell: a printable hub per joint with its id engraved in its
// base (OUT/joints/J<id>.stl) and all of them on print plates (OUT/plates/plate_<k>.stl,
// OUT/plates.csv), the rods' cut list (OUT/rods.csv), the beams printed as glued bridges
// (OUT/bridges.csv) and the panels for a laser cutter (OUT/panels.svg, OUT/panels.dxf).
// docs/fabrication.md "Model kit".

#include <cmath>
#include <iostream>
#include <regex>
#include <tuple>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common.h"
#include "gridshell/core/error.h"
#include "gridshell/kit/kit.h"

namespace gridshell::app {

namespace {

struct KitArgs {
  std::string dir;
  std::string out;
  std::string scale = "1:50";
  std::string rod = "3mm";
  std::string clearance = "0.1mm";
  std::string min_socket;  // empty: one rod diameter
  std::string label_stroke = "0.6mm";
  std::string bed = "600x400mm";
  std::string kerf = "0.15mm";
  std::string print_bed = "200x200mm";
  bool quiet = false;
};

/// "1:N" (or "N") → N; Error naming --scale otherwise.
double parse_scale(const std::string& s) {
  static const std::regex form(R"(^\s*(?:1\s*:\s*)?([0-9]+(?:\.[0-9]+)?)\s*$)");
  std::smatch m;
  if (!std::regex_match(s, m, form)) {
    throw Error("--scale", fmt::format("'{}' is not a scale like 1:50", s));
  }
  return std::stod(m[1].str());
}

/// "3mm", "3" (mm) or "0.3cm" → millimetres; Error naming `option` otherwise.
double parse_length_mm(const std::string& option, const std::string& s) {
  static const std::regex form(R"(^\s*([0-9]+(?:\.[0-9]+)?|\.[0-9]+)\s*(mm|cm|m)?\s*$)");
  std::smatch m;
  if (!std::regex_match(s, m, form)) {
    throw Error(option, fmt::format("'{}' is not a length like 3mm", s));
  }
  const double x = std::stod(m[1].str());
  const std::string unit = m[2].str();
  return unit == "cm" ? 10 * x : unit == "m" ? 1000 * x : x;
}

/// "600x400mm" (or "600x400", "0.6x0.4m") → {width, height} in millimetres; Error naming
/// `option` otherwise.
std::pair<double, double> parse_bed_mm(const std::string& option, const std::string& s) {
  static const std::regex form(R"(^\s*([0-9.]+)\s*x\s*([0-9.]+)\s*(mm|cm|m)?\s*$)");
  std::smatch m;
  if (!std::regex_match(s, m, form)) {
    throw Error(option, fmt::format("'{}' is not a size like 600x400mm", s));
  }
  const std::string unit = m[3].str();
  return {parse_length_mm(option, m[1].str() + unit), parse_length_mm(option, m[2].str() + unit)};
}

int run_kit(const KitArgs& a) {
  kit::KitOptions options;
  options.scale = parse_scale(a.scale);
  options.rod_diameter = parse_length_mm("--rod", a.rod);
  options.clearance = parse_length_mm("--clearance", a.clearance);
  if (!a.min_socket.empty()) {
    options.min_socket = parse_length_mm("--min-socket", a.min_socket);
    if (!(options.min_socket > 0)) throw Error("--min-socket", "must be more than 0");
  }
  options.label_stroke = parse_length_mm("--label-stroke", a.label_stroke);
  std::tie(options.bed_width, options.bed_height) = parse_bed_mm("--bed", a.bed);
  std::tie(options.print_bed.width, options.print_bed.height) =
      parse_bed_mm("--print-bed", a.print_bed);
  options.kerf = parse_length_mm("--kerf", a.kerf);
  kit::check_kit_options(options);
  if (a.quiet) spdlog::set_level(spdlog::level::warn);
  const std::filesystem::path out =
      a.out.empty() ? std::filesystem::path(a.dir) / "kit" : std::filesystem::path(a.out);
  const kit::KitResult r = kit::write_kit(a.dir, out, options);
  spdlog::info("kit: {} joints in {}, {} rods ({:.0f} mm in all) in {}, {} beams printed as "
               "glued bridges in {}",
               r.joints, (out / "joints").string(), r.rods, r.rod_total_mm,
               (out / "rods.csv").string(), r.bridges, (out / "bridges.csv").string());
  if (r.unglued > 0)
    spdlog::info("kit: {} bridges meet at so sharp an angle that their parts join only through "
                 "their neighbours (glue_radius_mm 0 in bridges.csv)",
                 r.unglued);
  if (r.uncut_plates > 0)
    spdlog::warn("kit: {} joints keep their id plate whole across a bridge: trim it where it "
                 "meets the glued neighbour's",
                 r.uncut_plates);
  spdlog::info("kit: the joints on {} print plates of {:g} x {:g} mm in {}", r.plates,
               options.print_bed.width, options.print_bed.height, (out / "plates").string());
  if (r.panels > 0)
    spdlog::info("kit: {} panels on {} laser beds in {}", r.panels, r.panel_sheets,
                 (out / "panels.dxf").string());
  return 0;
}

}  // namespace

void register_kit(CLI::App& app, Action& action) {
  auto a = std::make_shared<KitArgs>();
  CLI::App* sub = app.add_subcommand(
      "kit", "A desk model of a design folder: printable joints (STL) and the rods' cut list");
  sub->add_option("dir", a->dir, "a design / baseline / analyze output folder")->required();
  sub->add_option("-o,--out", a->out, "output folder (created if missing; default DIR/kit)");
  sub->add_option("--scale", a->scale, "model scale 1:N")->default_str(a->scale);
  sub->add_option("--rod", a->rod, "rod diameter (mm unless cm or m is given)")
      ->default_str(a->rod);
  sub->add_option("--clearance", a->clearance, "radial play between rod and socket")
      ->default_str(a->clearance);
  sub->add_option("--min-socket", a->min_socket,
                  "least socket depth; a beam too short for two is a printed, glued bridge")
      ->default_str("one rod diameter");
  sub->add_option("--label-stroke", a->label_stroke,
                  "stroke of the id engraved in each joint's base (>= 0.6mm)")
      ->default_str(a->label_stroke);
  sub->add_option("--bed", a->bed, "the laser cutter's bed WxH for the panels")
      ->default_str(a->bed);
  sub->add_option("--kerf", a->kerf, "width the laser burns away (outlines offset by half)")
      ->default_str(a->kerf);
  sub->add_option("--print-bed", a->print_bed,
                  "the 3-D printer's bed WxH for the plates of joints (OUT/plates)")
      ->default_str(a->print_bed);
  sub->add_flag("--quiet", a->quiet, "only warnings and errors on stderr");
  sub->callback([a, &action] { action = [a] { return run_kit(*a); }; });
}

}  // namespace gridshell::app
