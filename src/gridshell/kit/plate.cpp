#include "gridshell/kit/plate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/convex_hull_2.h>

#include "gridshell/core/error.h"
#include "gridshell/fabrication/nesting.h"
#include "gridshell/io/files.h"
#include "gridshell/kit/kit.h"

namespace gridshell::kit {

namespace {
using Point2 = CGAL::Exact_predicates_inexact_constructions_kernel::Point_2;
}  // namespace

void check_print_bed(const PrintBed& bed) {
  if (!(bed.width >= 20 && bed.width <= 2000 && bed.height >= 20 && bed.height <= 2000)) {
    throw Error("--print-bed", "must be WxH with sides between 20mm and 2000mm");
  }
  if (!(bed.gap >= 0 && bed.margin >= 0) || !(bed.width > 2 * bed.margin) ||
      !(bed.height > 2 * bed.margin)) {
    throw Error("--print-bed", "leaves no room inside its margins");
  }
}

PartBase part_base(const HubPlan& hub) {
  PartBase base;
  if (hub.base > 0) {
    base.normal = hub.base_normal;
    base.distance = hub.base;
    base.flat = true;
  }
  return base;
}

LaidPart lay_part(int joint, const PartMesh& mesh, const PartBase& base) {
  LaidPart part;
  part.joint = joint;
  part.tilt = Eigen::Quaterniond::FromTwoVectors(base.normal.normalized(), -Vec3::UnitZ())
                  .toRotationMatrix();
  double low = 1e300;
  std::vector<Point2> plan;
  plan.reserve(mesh.points.size());
  for (const Eigen::Vector3f& c : mesh.points) {
    const Vec3 q = part.tilt * c.cast<double>();
    low = std::min(low, q.z());
    plan.emplace_back(q.x(), q.y());
  }
  part.lift = mesh.points.empty() ? 0 : -low;
  std::vector<Point2> hull;
  CGAL::convex_hull_2(plan.begin(), plan.end(), std::back_inserter(hull));  // counter-clockwise
  for (const Point2& p : hull) part.footprint.emplace_back(p.x(), p.y());
  return part;
}

Plates pack_plates(const std::vector<LaidPart>& parts, const PrintBed& bed) {
  check_print_bed(bed);
  std::vector<std::vector<Eigen::Vector2d>> outlines;
  outlines.reserve(parts.size());
  for (const LaidPart& p : parts) outlines.push_back(p.footprint);
  fabrication::SheetOptions sheet;
  sheet.width = bed.width;
  sheet.height = bed.height;
  sheet.gap = bed.gap;
  sheet.margin = bed.margin;
  const fabrication::Nesting nesting = fabrication::nest_panels(outlines, sheet);
  if (!nesting.oversize.empty()) {
    const LaidPart& p = parts[nesting.oversize.front()];
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = -lo;
    for (const auto& x : p.footprint) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    throw Error("--print-bed",
                fmt::format("joint {} ({:.0f} x {:.0f} mm from above) does not fit a {:g}x{:g} "
                            "mm bed with its {:g} mm margins",
                            p.joint, hi.x() - lo.x(), hi.y() - lo.y(), bed.width, bed.height,
                            bed.margin));
  }
  Plates plates;
  plates.plates = nesting.sheets;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const fabrication::Placement& where = nesting.placements[k];
    PlacedPart placed;
    placed.joint = parts[k].joint;
    placed.plate = std::max(0, where.sheet);  // an empty footprint (no part) lands on plate 0
    placed.turn = where.rotation;
    placed.rotation = Eigen::AngleAxisd(where.rotation, Vec3::UnitZ()).toRotationMatrix() *
                      parts[k].tilt;
    placed.offset = Vec3(where.offset.x(), where.offset.y(), parts[k].lift);
    plates.parts.push_back(placed);
  }
  return plates;
}

namespace {

/// The parts of each plate, joint ids rising.
std::vector<std::vector<const PlacedPart*>> by_plate(const Plates& plates) {
  std::vector<std::vector<const PlacedPart*>> on(plates.plates);
  for (const PlacedPart& p : plates.parts) {
    if (p.plate < plates.plates) on[p.plate].push_back(&p);
  }
  for (auto& v : on) {
    std::sort(v.begin(), v.end(),
              [](const PlacedPart* a, const PlacedPart* b) { return a->joint < b->joint; });
  }
  return on;
}

}  // namespace

std::string plates_csv(const Plates& plates) {
  std::string s = "joint,plate,x_mm,y_mm,rotation_deg\n";
  for (const auto& plate : by_plate(plates)) {
    for (const PlacedPart* p : plate) {
      double deg = p->turn * 180 / std::numbers::pi;
      deg -= 360 * std::floor(deg / 360);
      s += fmt::format("{},{},{},{},{}\n", p->joint, p->plate,
                       io::format_number(std::round(p->offset.x() * 1000) / 1000),
                       io::format_number(std::round(p->offset.y() * 1000) / 1000),
                       io::format_number(std::round(deg * 1000) / 1000));
    }
  }
  return s;
}

void write_plate_stls(const Plates& plates, const std::vector<PartMesh>& meshes,
                      const std::filesystem::path& plates_dir) {
  io::ensure_directory(plates_dir);
  const auto on = by_plate(plates);
  tbb::parallel_for(std::size_t{0}, on.size(), [&](std::size_t k) {
    PartMesh all;
    for (const PlacedPart* p : on[k]) {
      const PartMesh& mesh = meshes[static_cast<std::size_t>(p - plates.parts.data())];
      const auto first = static_cast<std::uint32_t>(all.points.size());
      for (const Eigen::Vector3f& c : mesh.points) {
        all.points.push_back((p->rotation * c.cast<double>() + p->offset).cast<float>());
      }
      for (const auto& t : mesh.triangles) all.triangles.push_back({first + t[0], first + t[1], first + t[2]});
    }
    io::write_file_atomic(plates_dir / fmt::format("plate_{}.stl", k), stl_bytes(all));
  });
}

}  // namespace gridshell::kit
