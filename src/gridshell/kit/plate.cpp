#include "gridshell/kit/plate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "gridshell/core/error.h"
#include "gridshell/fabrication/nesting.h"
#include "gridshell/io/files.h"
#include "gridshell/kit/kit.h"

namespace gridshell::kit {

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

LaidPart lay_part(int joint, const std::vector<Triangle>& triangles, const PartBase& base) {
  LaidPart part;
  part.joint = joint;
  part.tilt = Eigen::Quaterniond::FromTwoVectors(base.normal.normalized(), -Vec3::UnitZ())
                  .toRotationMatrix();
  double low = 1e300;
  std::vector<Eigen::Vector2d> plan;
  plan.reserve(3 * triangles.size());
  for (const Triangle& t : triangles) {
    for (const Eigen::Vector3f& c : t) {
      const Vec3 q = part.tilt * c.cast<double>();
      low = std::min(low, q.z());
      plan.emplace_back(q.x(), q.y());
    }
  }
  part.lift = triangles.empty() ? 0 : -low;
  // Andrew's monotone chain: the footprint's convex hull, counter-clockwise.
  std::sort(plan.begin(), plan.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  plan.erase(std::unique(plan.begin(), plan.end()), plan.end());
  if (plan.size() < 3) {
    part.footprint = plan;
    return part;
  }
  const auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a,
                        const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Eigen::Vector2d> hull(2 * plan.size());
  std::size_t k = 0;
  for (const auto& p : plan) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 0) --k;
    hull[k++] = p;
  }
  for (std::size_t i = plan.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], plan[i]) <= 0) --k;
    hull[k++] = plan[i];
  }
  hull.resize(k - 1);
  part.footprint = std::move(hull);
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

void write_plate_stls(const Plates& plates, const std::filesystem::path& joints_dir,
                      const std::filesystem::path& plates_dir) {
  io::ensure_directory(plates_dir);
  const auto on = by_plate(plates);
  tbb::parallel_for(std::size_t{0}, on.size(), [&](std::size_t k) {
    std::vector<Triangle> all;
    for (const PlacedPart* p : on[k]) {
      const auto path = joints_dir / fmt::format("J{}.stl", p->joint);
      for (const Triangle& t : read_stl(io::read_file(path), path.string())) {
        Triangle moved;
        for (int c = 0; c < 3; ++c) {
          moved[c] = (p->rotation * t[c].cast<double>() + p->offset).cast<float>();
        }
        all.push_back(moved);
      }
    }
    io::write_file_atomic(plates_dir / fmt::format("plate_{}.stl", k),
                          stl_bytes(all, fmt::format("gridshell kit plate {} (mm)", k)));
  });
}

}  // namespace gridshell::kit
