#include "gridshell/kit/kit.h"

#include "gridshell/kit/assembly.h"
#include "gridshell/kit/label.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include "gridshell/core/error.h"
#include "gridshell/exchange/dxf.h"
#include "gridshell/io/files.h"

namespace gridshell::kit {

namespace {

/// Splits one CSV line at commas (the fabrication files never quote a field).
std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

/// The lines of a CSV file without the trailing '\r'; Error when missing.
std::vector<std::string> csv_lines(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw Error(path.string(),
                "missing (not a design folder: gridshell kit needs joints.csv "
                "and beams.csv)");
  }
  std::istringstream in(io::read_file(path));
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty()) lines.push_back(line);
  }
  if (lines.empty()) throw Error(path.string(), "empty file");
  return lines;
}

/// Index of `name` in the header; Error when absent.
int column(const std::vector<std::string>& header, const std::string& name,
           const std::filesystem::path& path) {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end()) throw Error(path.string(), "header has no column '" + name + "'");
  return static_cast<int>(it - header.begin());
}

double to_number(const std::string& s, const std::filesystem::path& path, std::size_t row) {
  std::size_t used = 0;
  double x = 0;
  try {
    x = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != s.size() || !std::isfinite(x)) {
    throw Error(path.string(), fmt::format("line {}: '{}' is not a number", row + 1, s));
  }
  return x;
}

int to_id(const std::string& s, const std::filesystem::path& path, std::size_t row) {
  const double x = to_number(s, path, row);
  if (x < 0 || x != std::floor(x) || x > 1e8) {
    throw Error(path.string(), fmt::format("line {}: '{}' is not an id", row + 1, s));
  }
  return static_cast<int>(x);
}

/// Reads joints.csv: ids must be 0..n-1 in order (as fabrication writes them).
std::vector<KitJoint> read_joints(const std::filesystem::path& path) {
  const auto lines = csv_lines(path);
  const auto header = split_csv(lines[0]);
  const int cj = column(header, "joint", path), cx = column(header, "x", path),
            cy = column(header, "y", path), cz = column(header, "z", path),
            cs = column(header, "support", path), cb = column(header, "beams", path);
  const int need = std::max({cj, cx, cy, cz, cs, cb}) + 1;
  std::vector<KitJoint> joints;
  for (std::size_t r = 1; r < lines.size(); ++r) {
    const auto f = split_csv(lines[r]);
    if (static_cast<int>(f.size()) < need) {
      throw Error(path.string(), fmt::format("line {}: too few fields", r + 1));
    }
    KitJoint j;
    j.id = to_id(f[cj], path, r);
    if (j.id != static_cast<int>(joints.size())) {
      throw Error(path.string(), fmt::format("line {}: joint ids must be 0, 1, … in order", r + 1));
    }
    j.position =
        Vec3(to_number(f[cx], path, r), to_number(f[cy], path, r), to_number(f[cz], path, r));
    j.support = to_number(f[cs], path, r) != 0;
    std::istringstream beams(f[cb]);
    std::string b;
    while (beams >> b) j.beams.push_back(to_id(b, path, r));
    joints.push_back(std::move(j));
  }
  return joints;
}

/// Reads beams.csv: ids 0..m-1 in order, end joints that exist and differ, positive lengths.
std::vector<KitBeam> read_beams(const std::filesystem::path& path, int num_joints) {
  const auto lines = csv_lines(path);
  const auto header = split_csv(lines[0]);
  const int cb = column(header, "beam", path), ci = column(header, "node_i", path),
            cj = column(header, "node_j", path), cl = column(header, "length", path);
  const int need = std::max({cb, ci, cj, cl}) + 1;
  std::vector<KitBeam> beams;
  for (std::size_t r = 1; r < lines.size(); ++r) {
    const auto f = split_csv(lines[r]);
    if (static_cast<int>(f.size()) < need) {
      throw Error(path.string(), fmt::format("line {}: too few fields", r + 1));
    }
    KitBeam b{to_id(f[cb], path, r), to_id(f[ci], path, r), to_id(f[cj], path, r),
              to_number(f[cl], path, r)};
    if (b.id != static_cast<int>(beams.size())) {
      throw Error(path.string(), fmt::format("line {}: beam ids must be 0, 1, … in order", r + 1));
    }
    if (b.joint_i >= num_joints || b.joint_j >= num_joints || b.joint_i == b.joint_j ||
        !(b.length > 0)) {
      throw Error(path.string(), fmt::format("line {}: bad end joints or length", r + 1));
    }
    beams.push_back(b);
  }
  return beams;
}

}  // namespace

std::vector<std::vector<Eigen::Vector2d>> read_panel_outlines(const std::filesystem::path& path) {
  const auto lines = csv_lines(path);
  const auto header = split_csv(lines[0]);
  const int cp = column(header, "panel", path), co = column(header, "outline", path);
  const int need = std::max(cp, co) + 1;
  std::vector<std::vector<Eigen::Vector2d>> outlines;
  for (std::size_t r = 1; r < lines.size(); ++r) {
    const auto f = split_csv(lines[r]);
    if (static_cast<int>(f.size()) < need) {
      throw Error(path.string(), fmt::format("line {}: too few fields", r + 1));
    }
    if (to_id(f[cp], path, r) != static_cast<int>(outlines.size())) {
      throw Error(path.string(), fmt::format("line {}: panel ids must be 0, 1, … in order", r + 1));
    }
    std::istringstream in(f[co]);
    std::vector<double> xy;
    std::string word;
    while (in >> word) xy.push_back(to_number(word, path, r));
    if (xy.size() < 6 || xy.size() % 2) {
      throw Error(path.string(), fmt::format("line {}: an outline needs x y pairs of 3 corners or more", r + 1));
    }
    std::vector<Eigen::Vector2d> q;
    for (std::size_t k = 0; k < xy.size(); k += 2) q.emplace_back(xy[k], xy[k + 1]);
    outlines.push_back(std::move(q));
  }
  return outlines;
}

namespace {

/// The seat of a joint's sockets: every pair of holes at least a wall apart, floor off-centre.
double joint_seat(const std::vector<Vec3>& axes, double r, double wall) {
  double seat = r;
  for (std::size_t a = 0; a < axes.size(); ++a) {
    for (std::size_t b = a + 1; b < axes.size(); ++b) {
      const double theta = std::acos(std::clamp(axes[a].dot(axes[b]), -1.0, 1.0));
      const double s = std::sin(theta / 2), c = std::cos(theta / 2);
      if (s < 1e-3) {
        throw Error("joint", "two beams of a joint are parallel; no hub can hold both");
      }
      seat = std::max(seat, (wall / 2 + r * c) / s);
    }
  }
  return seat;
}

}  // namespace

void check_kit_options(const KitOptions& o) {
  if (!(o.scale >= 1 && o.scale <= 1e4)) throw Error("--scale", "must be 1:N with 1 <= N <= 10000");
  if (!(o.rod_diameter >= 0.5 && o.rod_diameter <= 50)) {
    throw Error("--rod", "must be between 0.5mm and 50mm");
  }
  if (!(o.clearance >= 0 && o.clearance <= o.rod_diameter)) {
    throw Error("--clearance", "must be between 0 and the rod's diameter");
  }
  if (!(o.depth_factor > 0 && o.depth_factor <= 20)) throw Error("depth", "must be in (0, 20]");
  if (!(o.wall > 0 && o.wall <= 20)) throw Error("wall", "must be in (0, 20] mm");
  if (!(o.gap >= 0)) throw Error("gap", "must be >= 0");
  if (!(o.min_socket >= 0 && o.min_socket <= o.depth_factor * o.rod_diameter)) {
    throw Error("--min-socket", "must be between 0 (one rod diameter) and the full socket depth");
  }
  if (!(o.label_stroke >= 0.6 && o.label_stroke <= 5)) {
    throw Error("--label-stroke",
                "must be between 0.6mm (the finest stroke that prints readably) and 5mm");
  }
  if (!(o.label_depth > 0 && o.label_depth < o.wall)) {
    throw Error("label depth", "must be more than 0 and less than the wall");
  }
  if (o.segments != 0 && (o.segments < 8 || o.segments > 256))
    throw Error("segments", "must be 0 (from the tolerance) or in [8, 256]");
  if (!(o.tolerance >= 1e-4 && o.tolerance <= 1)) throw Error("tolerance", "must be in [1e-4, 1] mm");
  if (!(o.bed_width >= 50 && o.bed_width <= 5000 && o.bed_height >= 50 && o.bed_height <= 5000))
    throw Error("--bed", "must be WxH with sides between 50mm and 5000mm");
  if (!(o.kerf >= 0 && o.kerf <= 2)) throw Error("--kerf", "must be between 0 and 2mm");
  check_print_bed(o.print_bed);
}

int polygon_sides(const KitOptions& o) {
  if (o.segments > 0) return o.segments;
  const double r = o.rod_diameter / 2 + o.clearance;
  const double x = 1 - std::min(o.tolerance / r, 1.0);
  return std::clamp(static_cast<int>(std::ceil(std::numbers::pi / std::acos(x) - 1e-9)), 12, 256);
}

KitFrame read_kit_frame(const std::filesystem::path& dir) {
  if (!std::filesystem::is_directory(dir)) throw Error(dir.string(), "not a folder");
  KitFrame frame;
  frame.joints = read_joints(dir / "joints.csv");
  frame.beams = read_beams(dir / "beams.csv", static_cast<int>(frame.joints.size()));
  for (const KitJoint& j : frame.joints) {
    for (int b : j.beams) {
      if (b >= static_cast<int>(frame.beams.size()) ||
          (frame.beams[b].joint_i != j.id && frame.beams[b].joint_j != j.id)) {
        throw Error((dir / "joints.csv").string(),
                    fmt::format("joint {} lists beam {}, which does not end at it", j.id, b));
      }
    }
  }
  return frame;
}

namespace {

/// How far the hole of socket h (floor to mouth) reaches along the unit direction a.
double hole_reach(const Socket& h, const Vec3& a) {
  const double c = h.axis.dot(a), side = std::sqrt(std::max(0.0, 1 - c * c));
  return std::max(h.seat * c, (h.seat + h.depth) * c) + h.radius * side;
}

/// Makes socket s of `beam` a printed bridge (both halves cut by the mid-plane of the joints'
/// centres at scale).
void make_bridge(Socket& s, const KitFrame& frame, const KitBeam& beam, const KitOptions& o) {
  const Vec3 along = frame.joints[beam.joint_j].position - frame.joints[beam.joint_i].position;
  s.bridge = true;
  s.depth = 0;
  s.mid = along.norm() * 1000 / o.scale / 2;
  const Vec3 helper = std::abs(along.x()) < 0.9 * along.norm() ? Vec3::UnitX() : Vec3::UnitY();
  s.disc_u = along.cross(helper).normalized();
}

/// The largest glue disc radius of bridge b at a hub that keeps clear of the hub's other
/// bridges' cuts and of its holes (run-out included) by a tenth of a wall.
double disc_room(const HubPlan& hub, const Socket& b, const KitOptions& o) {
  const double relief = kReliefWalls * o.wall, margin = 0.1 * o.wall;
  double room = hub.sleeve_radius - relief;
  for (const Socket& k : hub.sockets) {
    if (&k == &b) continue;
    const double c = k.axis.dot(b.axis), side = std::sqrt(std::max(1e-12, 1 - c * c));
    if (k.bridge) {  // the disc's points x: x·k.axis ≤ k.mid − relief − margin
      room = std::min(room, (k.mid - relief - margin - b.mid * c) / side);
      continue;
    }
    // The hole: a cylinder of k.radius about its axis, sampled every 0.1 mm or finer; its axis'
    // points near the glue plane keep their radius and a margin off the disc.
    const double t0 = k.seat, t1 = k.seat + k.depth + o.rod_diameter;
    const int n = 16 + static_cast<int>((t1 - t0) / 0.1);
    for (int i = 0; i <= n; ++i) {
      const Vec3 x = (t0 + (t1 - t0) * i / n) * k.axis;
      const double along = x.dot(b.axis);
      if (along < b.mid - relief - k.radius - margin || along > b.mid + k.radius + margin) continue;
      room = std::min(room, (x - along * b.axis).norm() - k.radius - margin - 0.1);
    }
  }
  return room;
}

/// Marks the sockets of beams too short for a rod with two sockets of `min_socket` as bridges
/// (Socket::bridge), then those whose hole would reach another bridge's cut, until none does;
/// the others' depths full or shortened. Error when a bridge is too short to cut (its relief
/// would reach the joint's centre).
void plan_sockets(const KitFrame& frame, const std::vector<double>& seats,
                  std::vector<HubPlan>& hubs, const KitOptions& o) {
  const double min_socket = o.min_socket > 0 ? o.min_socket : o.rod_diameter;
  const double relief = kReliefWalls * o.wall;
  std::vector<char> bridged(frame.beams.size(), 0);
  for (HubPlan& hub : hubs) {
    for (Socket& s : hub.sockets) {
      const KitBeam& beam = frame.beams[s.beam];
      const double free = beam.length * 1000 / o.scale - seats[beam.joint_i] - seats[beam.joint_j];
      s.seat = seats[hub.joint];
      s.depth = std::min(o.depth_factor * o.rod_diameter, (free - o.gap) / 2);
      bridged[s.beam] = bridged[s.beam] || s.depth < min_socket;
    }
  }
  for (bool grew = true; grew;) {
    grew = false;
    for (HubPlan& hub : hubs) {
      for (Socket& s : hub.sockets)
        if (bridged[s.beam] && !s.bridge) make_bridge(s, frame, frame.beams[s.beam], o);
      for (const Socket& b : hub.sockets) {
        if (!b.bridge) continue;
        for (const Socket& h : hub.sockets) {
          if (h.bridge || bridged[h.beam] || hole_reach(h, b.axis) <= b.mid - relief) continue;
          bridged[h.beam] = 1;
          grew = true;
        }
      }
    }
  }
  // The glue discs: the same radius at both ends.
  std::vector<double> disc(frame.beams.size(), 1e300);
  for (const HubPlan& hub : hubs)
    for (const Socket& s : hub.sockets)
      if (s.bridge) disc[s.beam] = std::min(disc[s.beam], disc_room(hub, s, o));
  int too_short = 0, worst = -1;
  for (HubPlan& hub : hubs) {
    for (Socket& s : hub.sockets) {
      if (!s.bridge) continue;
      // Too little room: the parts do not meet on this beam (their cells touch elsewhere).
      s.disc = disc[s.beam] >= 0.25 * hub.sleeve_radius ? disc[s.beam] : 0;
      if (s.mid < 2 * relief) {
        const KitBeam& beam = frame.beams[s.beam];
        if (worst < 0 || beam.length < frame.beams[worst].length) worst = beam.id;
        ++too_short;
      }
    }
  }
  if (too_short > 0) {
    const KitBeam& b = frame.beams[worst];
    const double shortest = 4 * relief;  // [mm] at scale
    throw Error("--scale", fmt::format("{} beams too short at 1:{:g} even for a printed bridge "
                                       "(beam {}: {:.2f} mm, least {:.2f} mm); 1:N with N <= {} "
                                       "fits",
                                       (too_short + 1) / 2, o.scale, b.id,
                                       b.length * 1000 / o.scale, shortest,
                                       static_cast<long>(std::floor(b.length * 1000 / shortest))));
  }
}

/// The sleeves' start and the sphere that covers it (HubPlan::sleeve_start); the sphere stays a
/// wall short of every socket's mouth and every bridge's mid-plane.
void plan_core(HubPlan& hub, const KitOptions& o) {
  const double R = hub.sleeve_radius;
  double start = 0.5 * R, mouth = 1e300;
  for (std::size_t a = 0; a < hub.sockets.size(); ++a) {
    const Socket& s = hub.sockets[a];
    mouth = std::min(mouth, s.bridge ? s.mid : s.seat + s.depth);
    for (std::size_t b = a + 1; b < hub.sockets.size(); ++b) {
      const double theta = std::acos(std::clamp(s.axis.dot(hub.sockets[b].axis), -1.0, 1.0));
      start = std::max(start, R * (1 / std::tan(theta / 2) + 0.1));
    }
  }
  const double radius = std::max(1.25 * R, 1.02 * std::hypot(start, R) / kSphereInscribed);
  if (radius < mouth - o.wall) {
    hub.sleeve_start = start;
    hub.hub_radius = radius;
  }
}

}  // namespace

std::vector<HubPlan> plan_hubs(const KitFrame& frame, const KitOptions& o) {
  const double r = o.rod_diameter / 2 + o.clearance;
  std::vector<HubPlan> hubs(frame.joints.size());
  std::vector<double> seats(frame.joints.size(), 0);
  for (const KitJoint& j : frame.joints) {
    HubPlan& hub = hubs[j.id];
    hub.joint = j.id;
    hub.sleeve_radius = r + o.wall;
    hub.hub_radius = 1.25 * hub.sleeve_radius;
    std::vector<Vec3> axes;
    for (int b : j.beams) {
      const KitBeam& beam = frame.beams[b];
      const int other = beam.joint_i == j.id ? beam.joint_j : beam.joint_i;
      const Vec3 d = frame.joints[other].position - j.position;
      if (!(d.norm() > 0)) throw Error(fmt::format("beam {}", b), "its joints coincide");
      axes.push_back(d.normalized());
      Socket socket;
      socket.beam = b;
      socket.axis = axes.back();
      socket.radius = r;
      hub.sockets.push_back(socket);
    }
    try {
      seats[j.id] = joint_seat(axes, r, o.wall);
    } catch (const Error&) {
      throw Error(fmt::format("joint {}", j.id), "two of its beams are parallel");
    }
  }
  plan_sockets(frame, seats, hubs, o);
  for (HubPlan& hub : hubs) {
    if (hub.sockets.empty()) continue;
    plan_core(hub, o);
    plan_base(hub, frame.joints[hub.joint].support, o);
  }
  return hubs;
}

std::vector<Rod> cut_list(const KitFrame& frame, const std::vector<HubPlan>& hubs,
                          const KitOptions& o) {
  std::vector<double> seat(hubs.size(), 0);
  for (const HubPlan& h : hubs) {
    if (!h.sockets.empty()) seat[h.joint] = h.sockets.front().seat;
  }
  const std::vector<char> bridged = bridged_beams(frame, hubs);
  std::vector<Rod> rods;
  for (const KitBeam& b : frame.beams) {
    if (bridged[b.id]) continue;
    rods.push_back(
        Rod{b.id, b.joint_i, b.joint_j, b.length * 1000 / o.scale - seat[b.joint_i] - seat[b.joint_j]});
  }
  std::stable_sort(rods.begin(), rods.end(),
                   [](const Rod& a, const Rod& b) { return a.length_mm > b.length_mm; });
  return rods;
}

std::vector<char> bridged_beams(const KitFrame& frame, const std::vector<HubPlan>& hubs) {
  std::vector<char> bridged(frame.beams.size(), 0);
  for (const HubPlan& h : hubs) {
    for (const Socket& s : h.sockets) bridged[s.beam] = bridged[s.beam] || s.bridge;
  }
  return bridged;
}

std::string bridges_csv(const KitFrame& frame, const std::vector<HubPlan>& hubs) {
  std::vector<double> disc(frame.beams.size(), -1);
  for (const HubPlan& h : hubs)
    for (const Socket& s : h.sockets)
      if (s.bridge) disc[s.beam] = s.disc;
  std::string s = "beam,joint_i,joint_j,glue_radius_mm\n";
  for (const KitBeam& b : frame.beams) {
    if (disc[b.id] < 0) continue;
    s += fmt::format("{},{},{},{}\n", b.id, b.joint_i, b.joint_j, io::format_number(disc[b.id]));
  }
  return s;
}

std::string rods_csv(const std::vector<Rod>& rods) {
  std::string s = "rod,joint_i,joint_j,length_mm\n";
  for (const Rod& r : rods) {
    s += fmt::format("{},{},{},{}\n", r.beam, r.joint_i, r.joint_j, io::format_number(r.length_mm));
  }
  return s;
}

fabrication::PanelSheets kit_panel_sheets(
    const std::vector<std::vector<Eigen::Vector2d>>& outlines, const KitOptions& o) {
  std::vector<std::vector<Eigen::Vector2d>> model;  // [m] of the model
  for (const auto& q : outlines) {
    std::vector<Eigen::Vector2d> m;
    for (const auto& x : q) m.push_back(x / o.scale);
    model.push_back(std::move(m));
  }
  fabrication::SheetOptions bed;
  bed.width = o.bed_width / 1000;
  bed.height = o.bed_height / 1000;
  bed.gap = 0.003;
  bed.margin = 0.005;
  const fabrication::Nesting nesting = fabrication::nest_panels(model, bed);
  fabrication::PanelSheetOptions drawing;
  drawing.kerf = o.kerf / 1000;
  drawing.label_min = 0.0015;
  drawing.label_max = 0.004;
  drawing.title = 0.006;
  drawing.space = 0.02;
  drawing.stroke = 0.0001;
  return fabrication::panel_sheets(model, nesting, bed, drawing);
}

KitResult write_kit(const std::filesystem::path& dir, const std::filesystem::path& out,
                    const KitOptions& options) {
  check_kit_options(options);
  const KitFrame frame = read_kit_frame(dir);
  const std::vector<HubPlan> hubs = plan_hubs(frame, options);
  const std::vector<Rod> rods = cut_list(frame, hubs, options);
  const std::vector<char> bridged = bridged_beams(frame, hubs);
  KitResult result;
  const double full = options.depth_factor * options.rod_diameter;
  for (const HubPlan& h : hubs) {
    for (const Socket& s : h.sockets) result.short_sockets += !s.bridge && s.depth < full - 1e-9;
    result.uncut_plates += h.sockets.empty() ? 0 : !h.plate_cut;
    for (const Socket& s : h.sockets) result.unglued += s.bridge && s.disc == 0 ? 1 : 0;
  }
  result.bridges = static_cast<int>(std::count(bridged.begin(), bridged.end(), 1));
  result.unglued /= 2;
  if (result.short_sockets > 0) {
    spdlog::warn("kit: {} sockets shallower than {:.3g} mm (beams short at 1:{:g})",
                 result.short_sockets, full, options.scale);
  }
  io::ensure_directory(out / "joints");
  // Each joint's solid is independent of the others (and the same whatever the thread).
  std::vector<LaidPart> laid(hubs.size());
  std::vector<PartMesh> meshes(hubs.size());
  tbb::parallel_for(std::size_t{0}, hubs.size(), [&](std::size_t k) {
    const HubPlan& h = hubs[k];
    if (h.sockets.empty()) return;
    meshes[k] = hub_part(h, options);
    io::write_file_atomic(out / "joints" / fmt::format("J{}.stl", h.joint), stl_bytes(meshes[k]));
    laid[k] = lay_part(h.joint, meshes[k], part_base(h));
  });
  std::size_t kept = 0;
  for (std::size_t k = 0; k < hubs.size(); ++k) {
    if (laid[k].footprint.empty()) continue;
    if (kept != k) {
      laid[kept] = std::move(laid[k]);
      meshes[kept] = std::move(meshes[k]);
    }
    ++kept;
  }
  laid.resize(kept);
  meshes.resize(kept);
  result.joints = static_cast<int>(laid.size());
  const Plates plates = pack_plates(laid, options.print_bed);
  write_plate_stls(plates, meshes, out / "plates");
  io::write_file_atomic(out / "plates.csv", plates_csv(plates));
  result.plates = plates.plates;
  io::write_file_atomic(out / "rods.csv", rods_csv(rods));
  io::write_file_atomic(out / "bridges.csv", bridges_csv(frame, hubs));
  io::write_file_atomic(out / "assembly.html",
                        assembly_html(frame, assembly_order(frame, bridged), rods, options));
  result.rods = static_cast<int>(rods.size());
  if (std::filesystem::is_regular_file(dir / "panels.csv")) {
    const fabrication::PanelSheets sheets =
        kit_panel_sheets(read_panel_outlines(dir / "panels.csv"), options);
    io::write_file_atomic(out / "panels.svg", fabrication::panels_svg(sheets));
    exchange::write_dxf(out / "panels.dxf", fabrication::panels_dxf(sheets));
    result.panels = static_cast<int>(sheets.outlines.size());
    result.panel_sheets = static_cast<int>(sheets.sheets.size());
  }
  for (const Rod& r : rods) result.rod_total_mm += r.length_mm;
  return result;
}

}  // namespace gridshell::kit
