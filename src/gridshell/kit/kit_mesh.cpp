// The printable hub of a joint: primitives (sphere, cylinders) as CGAL surface meshes and the
// corefinement booleans that join them. The only file of the kit with the (slow to compile)
// corefinement headers.

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Surface_mesh.h>
#include <fmt/format.h>

#include "gridshell/core/error.h"
#include "gridshell/kit/kit.h"
#include "gridshell/kit/label.h"

namespace gridshell::kit {

namespace {

// Exact constructions: the intersection points of one boolean are the input of the next (a chain
// of booleans on rounded points once met faces coplanar up to rounding).
using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using VertexIndex = Mesh::Vertex_index;
namespace PMP = CGAL::Polygon_mesh_processing;

/// Where the sleeves start along their axis, in sleeve radii, when they are joined one by one
/// (HubPlan::sleeve_start 0); the sphere's radius must exceed sqrt(1 + kSleeveStart²) sleeve
/// radii (plan_hubs: 1.25).
constexpr double kSleeveStart = 0.5;

/// Symmetric designs have joints whose beams mirror each other; mirror-image sleeves meet the
/// mirror-symmetric sphere and each other along edges shared by four faces (CGAL's output is
/// then a pinched, non-manifold STL). The sphere's longitudes are turned by an angle no mirror
/// plane through its axes maps onto itself, and socket k's polygons by frac(k · 0.382) of a side.
constexpr double kSphereTurn = 0.1234;  // [rad]
double socket_turn(std::size_t k, int segments) {
  const double golden = 0.3819660112501051;
  const double f = static_cast<double>(k + 1) * golden;
  return (f - std::floor(f)) * 2 * std::numbers::pi / segments;
}

/// Every corner of the primitives lies on a grid of 2^-kGridBits mm (about 1e-6 mm, below
/// float32's resolution in a part over 8 mm). The exact arithmetic of the booleans then works on
/// short rationals: on Botanic's joints a fifth of the CPU time of arbitrary doubles (the
/// degenerate predicates that corefinement evaluates exactly cost GMP's gcd of long numbers).
constexpr int kGridBits = 20;

Point point(const Vec3& p) {
  const auto snap = [](double x) {
    return std::ldexp(std::round(std::ldexp(x, kGridBits)), -kGridBits);
  };
  return Point(snap(p.x()), snap(p.y()), snap(p.z()));
}

/// A UV sphere of `radius` about the origin, `rings` latitude bands, `segments` longitudes,
/// oriented outward (each face's corners counter-clockwise seen from outside).
Mesh sphere(double radius, int rings, int segments) {
  Mesh m;
  const double pi = std::numbers::pi;
  const VertexIndex north = m.add_vertex(point(Vec3(0, 0, radius)));
  std::vector<std::vector<VertexIndex>> ring(rings - 1);
  for (int i = 1; i < rings; ++i) {
    const double phi = pi * i / rings;
    for (int k = 0; k < segments; ++k) {
      const double lambda = kSphereTurn + 2 * pi * k / segments;
      ring[i - 1].push_back(m.add_vertex(point(
          radius * Vec3(std::sin(phi) * std::cos(lambda), std::sin(phi) * std::sin(lambda),
                        std::cos(phi)))));
    }
  }
  const VertexIndex south = m.add_vertex(point(Vec3(0, 0, -radius)));
  for (int k = 0; k < segments; ++k) {
    const int k1 = (k + 1) % segments;
    m.add_face(north, ring.front()[k], ring.front()[k1]);
    for (int i = 0; i + 1 < rings - 1; ++i) {
      m.add_face(ring[i][k], ring[i + 1][k], ring[i + 1][k1]);
      m.add_face(ring[i][k], ring[i + 1][k1], ring[i][k1]);
    }
    m.add_face(south, ring.back()[k1], ring.back()[k]);
  }
  return m;
}

/// Closes a lathe's last ring (`ring`, counter-clockwise seen from +axis, its k-th vertex at
/// angle 2πk/n in the frame u, v = axis × u) by the convex polygon `cap` inside it (counter-
/// clockwise, in the same plane; a fan from its first corner) and the band between them: both
/// loops are star-shaped about the axis, so a merge of their corners by angle tiles the band.
void close_with_cap(Mesh& m, const std::vector<VertexIndex>& ring, const std::vector<Vec3>& cap,
                    const Vec3& axis, const Vec3& u) {
  const Vec3 v = axis.cross(u);
  const auto angle = [&](const Vec3& x) {
    const double a = std::atan2(x.dot(v), x.dot(u));
    return a < 0 ? a + 2 * std::numbers::pi : a;
  };
  const std::size_t n = ring.size(), c = cap.size();
  std::size_t j0 = 0;
  for (std::size_t j = 1; j < c; ++j) j0 = angle(cap[j]) < angle(cap[j0]) ? j : j0;
  std::vector<VertexIndex> inner;
  std::vector<double> inner_angle;
  for (std::size_t j = 0; j <= c; ++j) {
    const Vec3& x = cap[(j0 + j) % c];
    if (j < c) inner.push_back(m.add_vertex(point(x)));
    inner_angle.push_back(angle(x) + (j == c || (j > 0 && angle(x) < inner_angle[0])
                                          ? 2 * std::numbers::pi : 0));
  }
  inner.push_back(inner.front());
  for (std::size_t j = 1; j + 1 < c; ++j) m.add_face(inner[0], inner[j], inner[j + 1]);
  std::size_t i = 0, j = 0;
  while (i < n || j < c) {
    const double ring_next = 2 * std::numbers::pi * static_cast<double>(i + 1) / static_cast<double>(n);
    if (j == c || (i < n && ring_next < inner_angle[j + 1])) {
      m.add_face(ring[i], ring[(i + 1) % n], inner[j]);
      ++i;
    } else {
      m.add_face(ring[i % n], inner[j + 1], inner[j]);
      ++j;
    }
  }
}

/// The corners of a cap polygon about `axis` at `t` that holds a hole of radius `bore` well
/// inside and lies well inside a ring of `radius` with `segments` sides: the regular m-gon with
/// the fewest corners (4, 6 or 8) that fits between them; empty when none fits.
std::vector<Vec3> bore_cap(const Vec3& axis, const Vec3& u, double t, double radius, int segments,
                           double bore) {
  const Vec3 v = axis.cross(u);
  const double room = 0.98 * radius * std::cos(std::numbers::pi / segments);
  for (const int m : {4, 6, 8}) {
    const double need = 1.05 * bore / std::cos(std::numbers::pi / m);
    if (need >= room) continue;
    const double rho = 0.5 * (need + room);
    std::vector<Vec3> cap;
    for (int k = 0; k < m; ++k) {
      // Corners half a ring side off the ring's: no corner of the cap on a ring corner's ray.
      const double phi = std::numbers::pi * (2.0 * k + 0.5) / m + std::numbers::pi / segments;
      cap.push_back(t * axis + rho * (std::cos(phi) * u + std::sin(phi) * v));
    }
    return cap;
  }
  return {};
}

/// A closed cylinder about `axis` (unit) from t0 to t1 > t0 along it, its polygon's vertices on
/// `radius` (the first at angle `phase`), oriented outward, added to `m`. Its end caps are fans
/// from the axis; with `bore` > 0 (a hole of that radius will be cut through the far end) the
/// far cap is a polygon round the bore and a band (close_with_cap): the hole's wall then
/// crosses one or two of the cap's edges, not every edge of a fan.
void add_cylinder(Mesh& m, const Vec3& axis, double t0, double t1, double radius, int segments,
                  double phase = 0, double bore = 0) {
  const Vec3 helper = std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  // (u, v, axis) right-handed: the polygon runs counter-clockwise about the axis.
  const Vec3 u = axis.cross(helper).normalized(), v = axis.cross(u);
  std::vector<VertexIndex> bottom, top;
  for (int k = 0; k < segments; ++k) {
    const double phi = phase + 2 * std::numbers::pi * k / segments;
    const Vec3 radial = radius * (std::cos(phi) * u + std::sin(phi) * v);
    bottom.push_back(m.add_vertex(point(t0 * axis + radial)));
    top.push_back(m.add_vertex(point(t1 * axis + radial)));
  }
  const Vec3 u_phase = std::cos(phase) * u + std::sin(phase) * v;
  const std::vector<Vec3> cap =
      bore > 0 ? bore_cap(axis, u_phase, t1, radius, segments, bore) : std::vector<Vec3>{};
  const VertexIndex c0 = m.add_vertex(point(t0 * axis));
  const VertexIndex c1 = cap.empty() ? m.add_vertex(point(t1 * axis)) : c0;
  for (int k = 0; k < segments; ++k) {
    const int k1 = (k + 1) % segments;
    m.add_face(bottom[k], bottom[k1], top[k1]);
    m.add_face(bottom[k], top[k1], top[k]);
    if (cap.empty()) m.add_face(c1, top[k], top[k1]);
    m.add_face(c0, bottom[k1], bottom[k]);
  }
  if (!cap.empty()) close_with_cap(m, top, cap, axis, u_phase);
}

Mesh cylinder(const Vec3& axis, double t0, double t1, double radius, int segments,
              double phase = 0, double bore = 0) {
  Mesh m;
  add_cylinder(m, axis, t0, t1, radius, segments, phase, bore);
  return m;
}

/// A solid of revolution about `axis` (unit): the profile's (radius, t) points, the first and
/// last on the axis (radius 0), swept round with `segments` sides, the polygons' first vertex
/// along `u` (unit, ⟂ axis); oriented outward. With a `cap` (a convex polygon in the last
/// point's plane about the axis, counter-clockwise seen from +axis), the end face is that
/// polygon and the band round it instead of a fan from the axis.
Mesh lathe(const Vec3& axis, const Vec3& u, const std::vector<std::array<double, 2>>& profile,
           int segments, const std::vector<Vec3>& cap = {}) {
  const Vec3 v = axis.cross(u);
  Mesh m;
  const VertexIndex first = m.add_vertex(point(profile.front()[1] * axis));
  std::vector<std::vector<VertexIndex>> rings;
  for (std::size_t i = 1; i + 1 < profile.size(); ++i) {
    rings.emplace_back();
    for (int k = 0; k < segments; ++k) {
      const double phi = 2 * std::numbers::pi * k / segments;
      rings.back().push_back(m.add_vertex(point(
          profile[i][1] * axis + profile[i][0] * (std::cos(phi) * u + std::sin(phi) * v))));
    }
  }
  const VertexIndex last = cap.empty() ? m.add_vertex(point(profile.back()[1] * axis)) : first;
  for (int k = 0; k < segments; ++k) {
    const int k1 = (k + 1) % segments;
    m.add_face(first, rings.front()[k1], rings.front()[k]);
    for (std::size_t i = 0; i + 1 < rings.size(); ++i) {
      m.add_face(rings[i][k], rings[i][k1], rings[i + 1][k1]);
      m.add_face(rings[i][k], rings[i + 1][k1], rings[i + 1][k]);
    }
    if (cap.empty()) m.add_face(last, rings.back()[k], rings.back()[k1]);
  }
  if (!cap.empty()) close_with_cap(m, rings.back(), cap, axis, u);
  PMP::orient_to_bound_a_volume(m);
  return m;
}

/// A convex polygon (x, y in the frame ex, ey at `origin`) extruded along ez from z0 to z1;
/// oriented outward.
Mesh prism(const Vec3& origin, const Vec3& ex, const Vec3& ey, const Vec3& ez,
           const Polygon2& polygon, double z0, double z1) {
  Mesh m;
  std::vector<VertexIndex> bottom, top;
  for (const Eigen::Vector2d& p : polygon) {
    const Vec3 x = origin + p.x() * ex + p.y() * ey;
    bottom.push_back(m.add_vertex(point(x + z0 * ez)));
    top.push_back(m.add_vertex(point(x + z1 * ez)));
  }
  const std::size_t n = polygon.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t k1 = (k + 1) % n;
    m.add_face(bottom[k], bottom[k1], top[k1]);
    m.add_face(bottom[k], top[k1], top[k]);
  }
  for (std::size_t k = 1; k + 1 < n; ++k) {
    m.add_face(bottom[0], bottom[k + 1], bottom[k]);
    m.add_face(top[0], top[k], top[k + 1]);
  }
  PMP::orient_to_bound_a_volume(m);
  return m;
}

Error joint_error(const HubPlan& hub, const char* what) {
  return Error(fmt::format("joint {}", hub.joint), what);
}

/// The base as one solid of revolution about base_normal: a stem of the sleeves' radius from
/// inside the sphere (off-centre, like the sleeves, but not at their start) widening into a
/// plate a wall thick whose outer face is the flat base (a 2·segments-gon of base_radius).
void add_base(Mesh& solid, const HubPlan& hub, const KitOptions& o) {
  const Vec3& d = hub.base_normal;
  const Vec3 helper = std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 p = d.cross(helper).normalized(), q = d.cross(p);
  const double turn = 0.25 * kSphereTurn;
  const double stem = 0.3 * hub.sleeve_radius, plate = hub.base - o.wall;
  const std::vector<std::array<double, 2>> profile{
      {0, stem},     {hub.sleeve_radius, stem}, {hub.sleeve_radius, plate}, {hub.base_radius, plate},
      {hub.base_radius, hub.base}, {0, hub.base}};
  // The face's middle is the id's box (about a stroke wider) in two triangles: a fan from the
  // axis would cross every stroke with many of its edges, each crossing an exact construction.
  // The strokes' corners lie on a lattice of tenths of a stroke about the box's centre; the
  // box's height margin is off that lattice (0.309 strokes) so that its diagonal passes no
  // corner: a corner on it, moved by the 2^-20 mm grid, would leave an intersection point
  // closer to the corner than float32 resolves (a degenerate triangle in the STL).
  const Eigen::Vector2d half = label_half_size(hub.joint, o.label_stroke) +
                               o.label_stroke * Eigen::Vector2d(0.5, 0.309017);
  const Vec3 centre = hub.base * d, ex = half.x() * hub.label_x, ey = half.y() * hub.label_y;
  std::vector<Vec3> cap{centre - ex - ey, centre + ex - ey, centre + ex + ey, centre - ex + ey};
  if (ex.cross(ey).dot(d) < 0) std::reverse(cap.begin(), cap.end());
  // The box must lie inside the face's polygon (it does with base_radius ≥ the text's half
  // diagonal + a stroke unless the polygon is very coarse); else the plain fan.
  const int base_sides = 2 * polygon_sides(o);
  if (half.norm() >= 0.999 * hub.base_radius * std::cos(std::numbers::pi / base_sides)) cap.clear();
  Mesh base = lathe(d, std::cos(turn) * p + std::sin(turn) * q, profile, base_sides, cap);
  if (!PMP::corefine_and_compute_union(solid, base, solid)) {
    throw joint_error(hub, "the union of the hub and its base is not a closed manifold solid");
  }
}

/// The cutter of a bridge (kit.h "Bridges"): everything at or beyond the mid-plane, and in the
/// relief slab before it everything outside the glue disc. Its radius reaches the whole part,
/// or, when the base keeps its id uncut (HubPlan::plate_cut false), stops short of the plate.
Mesh bridge_cutter(const HubPlan& hub, const Socket& s, const KitOptions& o) {
  const double relief = kReliefWalls * o.wall, disc = s.disc;
  double far = hub.base + hub.base_radius + hub.hub_radius;
  for (const Socket& k : hub.sockets) {
    far = std::max(far, k.seat + k.depth + o.rod_diameter + k.mid + hub.sleeve_radius + o.wall);
  }
  double radius = 2 * far, end = s.mid + 2 * far;
  if (!hub.plate_cut) {
    // Up to the plate's inner face: t·c + R·√(1 − c²) < base − wall over t ≤ end.
    const double c = s.axis.dot(hub.base_normal), side = std::sqrt(std::max(1e-12, 1 - c * c));
    end = s.mid + far;
    const double room = hub.base - o.wall - 0.1 * o.wall - std::max(end * c, (s.mid - relief) * c);
    radius = std::max(disc + relief, room / side);
  }
  std::vector<std::array<double, 2>> profile{
      {0, s.mid},   {disc, s.mid}, {disc, s.mid - relief}, {radius, s.mid - relief},
      {radius, end}, {0, end}};
  if (disc == 0) profile = {{0, s.mid - relief}, {radius, s.mid - relief}, {radius, end}, {0, end}};
  return lathe(s.axis, s.disc_u, profile, polygon_sides(o));
}

/// Whether every bridge's cutter (within x·axis ≥ mid − relief) is clear of every socket hole
/// (run-out included) and of the engraving, so that they can be cut at once.
bool cutters_clear_of_holes(const HubPlan& hub, const KitOptions& o) {
  if (!hub.plate_cut) return false;  // the id's strokes may meet a cutter kept off the plate
  const double relief = kReliefWalls * o.wall;
  for (const Socket& b : hub.sockets) {
    if (!b.bridge) continue;
    for (const Socket& h : hub.sockets) {
      if (h.bridge) continue;
      const double c = h.axis.dot(b.axis), side = std::sqrt(std::max(0.0, 1 - c * c));
      const double reach = std::max(h.seat * c, (h.seat + h.depth + o.rod_diameter) * c);
      if (reach + h.radius * side > b.mid - relief - 0.05 * o.wall) return false;
    }
  }
  return true;
}

/// The hub as one closed mesh: sphere ∪ sleeves and stubs ∪ base, bridges cut, minus the holes
/// and the engraved id.
Mesh hub_mesh(const HubPlan& hub, const KitOptions& o) {
  const int sides = polygon_sides(o);
  // The sphere only rounds the core: a coarser polygon than the sockets' is enough.
  Mesh solid = sphere(hub.hub_radius, kSphereBands, kSphereSides);
  // A bridge's stub runs a wall past the mid-plane that cuts it.
  const auto end = [&](const Socket& s, double start) {
    return s.bridge ? std::max(s.mid, start) + o.wall : s.seat + s.depth;
  };
  if (hub.sleeve_start > 0) {
    // Disjoint sleeves whose start caps lie inside the sphere (plan_hubs): one mesh, one union.
    Mesh sleeves;
    for (std::size_t k = 0; k < hub.sockets.size(); ++k) {
      const Socket& s = hub.sockets[k];
      add_cylinder(sleeves, s.axis, hub.sleeve_start, end(s, hub.sleeve_start),
                   hub.sleeve_radius, sides, socket_turn(k, sides), s.bridge ? 0 : s.radius);
    }
    if (!PMP::corefine_and_compute_union(solid, sleeves, solid)) {
      throw joint_error(hub, "the union of the hub and its sleeves is not a closed manifold solid");
    }
  }
  for (std::size_t k = 0; k < hub.sockets.size() && hub.sleeve_start == 0; ++k) {
    const Socket& s = hub.sockets[k];
    // Sleeves that meet, one by one. Starting off-centre (its start cap still inside the
    // sphere), no two sleeves' caps share a point: nearly opposite beams would otherwise give
    // nearly coplanar caps.
    const double start = kSleeveStart * hub.sleeve_radius;
    Mesh sleeve = cylinder(s.axis, start, end(s, start), hub.sleeve_radius, sides,
                           socket_turn(k, sides), s.bridge ? 0 : s.radius);
    if (!PMP::corefine_and_compute_union(solid, sleeve, solid)) {
      throw joint_error(hub, "the union of the hub and a sleeve is not a closed manifold solid");
    }
  }
  if (hub.base > 0) add_base(solid, hub, o);
  // The bridges' cutters: one joins the holes' cut when no hole reaches it (cutters overlap each
  // other, so the others are cut one by one; uniting them first left pinched parts).
  std::vector<const Socket*> bridges;
  for (const Socket& s : hub.sockets)
    if (s.bridge) bridges.push_back(&s);
  const bool fold = !bridges.empty() && cutters_clear_of_holes(hub, o);
  for (std::size_t k = 0; k + (fold ? 1 : 0) < bridges.size(); ++k) {
    Mesh cutter = bridge_cutter(hub, *bridges[k], o);
    if (!PMP::corefine_and_compute_difference(solid, cutter, solid)) {
      throw joint_error(hub, "cutting a bridge's mid-plane left no closed manifold solid");
    }
  }
  // The holes are a wall apart (plan_hubs' seat): one mesh of disjoint cylinders, one cut. A
  // hole's polygon is turned half a side against its sleeve's: a hole edge lying in the plane
  // of a sleeve cap's fan edge (a degenerate edge-edge crossing) left the mouth's ring doubled.
  // The engraved id's strokes (disjoint prisms below every hole) join the same cut.
  const double half_side = std::numbers::pi / sides;
  Mesh holes;
  if (fold) CGAL::copy_face_graph(bridge_cutter(hub, *bridges.back(), o), holes);
  for (std::size_t k = 0; k < hub.sockets.size(); ++k) {
    const Socket& s = hub.sockets[k];
    if (s.bridge) continue;
    // The hole runs a rod's diameter past the sleeve's mouth: no coplanar faces to cut.
    add_cylinder(holes, s.axis, s.seat, s.seat + s.depth + o.rod_diameter, s.radius, sides,
                 socket_turn(k, sides) + half_side);
  }
  if (hub.base > 0) {
    for (const Polygon2& stroke : label_strokes(hub.joint, o.label_stroke)) {
      CGAL::copy_face_graph(prism(hub.base * hub.base_normal, hub.label_x, hub.label_y,
                                  hub.base_normal, stroke, -o.label_depth, o.label_depth),
                            holes);
    }
  }
  if (!PMP::corefine_and_compute_difference(solid, holes, solid)) {
    throw joint_error(hub, "cutting the sockets left no closed manifold solid");
  }
  return solid;
}

}  // namespace

PartMesh hub_part(const HubPlan& hub, const KitOptions& options) {
  const Mesh m = hub_mesh(hub, options);
  PartMesh part;
  part.points.reserve(m.number_of_vertices());
  part.triangles.reserve(m.number_of_faces());
  // Each corner rounded once; the mesh's indices may have gaps where corefinement removed one.
  std::vector<std::uint32_t> index(m.num_vertices());
  for (const auto v : m.vertices()) {
    const Point& q = m.point(v);
    index[v.idx()] = static_cast<std::uint32_t>(part.points.size());
    part.points.emplace_back(static_cast<float>(CGAL::to_double(q.x())),
                             static_cast<float>(CGAL::to_double(q.y())),
                             static_cast<float>(CGAL::to_double(q.z())));
  }
  for (const auto f : m.faces()) {
    std::array<std::uint32_t, 3> t{};
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(m.halfedge(f), m)) t[k++] = index[v.idx()];
    part.triangles.push_back(t);
  }
  return part;
}

std::string hub_stl(const HubPlan& hub, const KitOptions& options) {
  return stl_bytes(hub_part(hub, options));
}

}  // namespace gridshell::kit
