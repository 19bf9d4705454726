#include "gridshell/optimize/flat_panels.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>

#include <Eigen/Sparse>
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include "gridshell/core/enum_words.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/metrics.h"
#include "gridshell/optimize/flat_panels_internal.h"
#include "gridshell/optimize/projector.h"

namespace gridshell {

namespace {
constexpr EnumWords<PanelMode, 2> kPanelModeWords{
    {{"free", PanelMode::free}, {"flat", PanelMode::flat}}};
}  // namespace

PanelMode parse_panel_mode(const std::string& word) {
  return parse_word(word, "--panels", kPanelModeWords);
}
const char* to_string(PanelMode mode) { return word_of(mode, kPanelModeWords); }

bool intersect_planes(const Vec3 n[3], const double d[3], Vec3& x, double& det, double min_det,
                      Eigen::Matrix<double, 3, 12>* jacobian) {
  const Vec3 c12 = n[1].cross(n[2]), c20 = n[2].cross(n[0]), c01 = n[0].cross(n[1]);
  det = n[0].dot(c12);
  if (!(std::abs(det) > min_det)) return false;
  // A⁻¹ = [n1×n2, n2×n0, n0×n1] / det (columns): Cramer's rule.
  Eigen::Matrix3d inv;
  inv.col(0) = c12 / det;
  inv.col(1) = c20 / det;
  inv.col(2) = c01 / det;
  x = inv * Vec3(d[0], d[1], d[2]);
  if (jacobian) {
    for (int i = 0; i < 3; ++i) {
      jacobian->block<3, 3>(0, 4 * i) = -inv.col(i) * x.transpose();
      jacobian->col(4 * i + 3) = inv.col(i);
    }
  }
  return true;
}

namespace flat_detail {

/// A panel polygon's 2-D corners in the frame of `normal`.
std::vector<Eigen::Vector2d> in_plane(const std::vector<Vec3>& p, const Vec3& normal) {
  const auto [r, s] = plane_axes(normal);
  std::vector<Eigen::Vector2d> q(p.size());
  for (std::size_t k = 0; k < p.size(); ++k) q[k] = {p[k].dot(r), p[k].dot(s)};
  return q;
}

static bool segments_cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                    const Eigen::Vector2d& d) {
  const double o1 = orient_2d(a, b, c), o2 = orient_2d(a, b, d);
  const double o3 = orient_2d(c, d, a), o4 = orient_2d(c, d, b);
  return ((o1 > 0) != (o2 > 0)) && ((o3 > 0) != (o4 > 0)) && o1 != 0 && o2 != 0 && o3 != 0 &&
         o4 != 0;
}

/// True when the polygon (2-D) is simple: non-zero area, no two non-adjacent sides crossing.
bool simple_2d(const std::vector<Eigen::Vector2d>& q) {
  const int n = static_cast<int>(q.size());
  if (n < 3 || std::abs(signed_area_2d(q)) <= 0) return false;
  for (int i = 0; i < n; ++i)
    for (int j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;
      if (segments_cross(q[i], q[(i + 1) % n], q[j], q[(j + 1) % n])) return false;
    }
  return true;
}

/// Smallest interior angle (degrees) and whether some corner is reflex, of a 2-D polygon.
std::pair<double, bool> corner_angles(const std::vector<Eigen::Vector2d>& q) {
  const int n = static_cast<int>(q.size());
  const double sign = signed_area_2d(q) >= 0 ? 1 : -1;
  double smallest = 360;
  bool reflex = false;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d a = q[(k + n - 1) % n] - q[k], b = q[(k + 1) % n] - q[k];
    double angle = std::atan2(std::abs(a.x() * b.y() - a.y() * b.x()), a.dot(b)) * 180 / M_PI;
    if (sign * orient_2d(q[(k + n - 1) % n], q[k], q[(k + 1) % n]) < 0) {
      angle = 360 - angle;
      reflex = true;
    }
    smallest = std::min(smallest, angle);
  }
  return {smallest, reflex};
}

}  // namespace flat_detail

using namespace flat_detail;

namespace flat_detail {

std::vector<std::array<Side, 3>> inside_sides(const Layout& L, const std::vector<Vec3>& x0) {
  const int nf = static_cast<int>(L.faces.size());
  std::vector<Vec3> centre(nf, Vec3::Zero());
  for (int f = 0; f < nf; ++f) {
    for (int j : L.faces[f]) centre[f] += x0[j];
    centre[f] /= static_cast<double>(std::max<std::size_t>(1, L.faces[f].size()));
  }
  std::vector<std::array<Side, 3>> out(L.joints.size());
  for (std::size_t j = 0; j < L.joints.size(); ++j) {
    const int* pl = L.joints[j].plane;
    if (pl[0] < 0 || pl[1] < 0 || pl[2] < 0) continue;
    const Vec3 c[3] = {centre[pl[0]], centre[pl[1]], centre[pl[2]]};
    const Vec3 N = (c[1] - c[0]).cross(c[2] - c[0]);
    if (!(N.norm() > 0)) continue;
    for (int k = 0; k < 3; ++k) {
      Vec3 m = N.cross(c[(k + 1) % 3] - c[k]);
      if (!(m.norm() > 0)) continue;
      m.normalize();
      if (m.dot(c[(k + 2) % 3] - c[k]) < 0) m = -m;
      const double sigma = m.dot(x0[j] - c[k]);
      out[j][k] = {m, m.dot(c[k]) + std::min(0.0, sigma)};
    }
  }
  return out;
}

std::vector<Beam> beams_of(const Layout& L, const std::vector<Vec3>& x0, double keep) {
  std::vector<std::pair<int, int>> sides;
  for (const auto& face : L.faces)
    for (std::size_t k = 0; k < face.size(); ++k) {
      const int a = face[k], b = face[(k + 1) % face.size()];
      sides.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(sides.begin(), sides.end());
  sides.erase(std::unique(sides.begin(), sides.end()), sides.end());
  std::vector<Beam> beams;
  for (const auto& [a, b] : sides) {
    const Vec3 e = x0[b] - x0[a];
    if (!(e.norm() > 0)) continue;
    beams.push_back({a, b, e.normalized(), keep * e.norm()});
  }
  return beams;
}

}  // namespace flat_detail

PanelShape panel_shape(const PolyMesh& mesh, const SurfaceProjector* surface) {
  PanelShape s;
  const int nf = mesh.num_faces();
  s.out_of_plane.assign(nf, 0);
  std::vector<double> angle(nf, 360);
  std::vector<char> reflex(nf, 0), simple(nf, 1);
  tbb::parallel_for(0, nf, [&](int f) {
    const std::vector<Vec3> p = face_points(mesh, f);
    const FaceFrame fr = face_frame(p);
    Vec3 mean = Vec3::Zero();  // the least-squares plane passes through the corners' mean
    for (const Vec3& x : p) mean += x;
    mean /= static_cast<double>(p.size());
    for (const Vec3& x : p)
      s.out_of_plane[f] = std::max(s.out_of_plane[f], std::abs((x - mean).dot(fr.normal)));
    const std::vector<Eigen::Vector2d> q = in_plane(p, fr.normal);
    simple[f] = simple_2d(q);
    const auto [a, r] = corner_angles(q);
    angle[f] = a;
    reflex[f] = r;
  });
  s.min_angle_deg = nf ? 360 : 0;
  for (int f = 0; f < nf; ++f) {
    s.out_of_plane_max = std::max(s.out_of_plane_max, s.out_of_plane[f]);
    s.nonconvex += reflex[f];
    s.self_intersecting += !simple[f];
    s.min_angle_deg = std::min(s.min_angle_deg, angle[f]);
  }
  if (nf) {
    std::vector<double> sorted = s.out_of_plane;
    std::nth_element(sorted.begin(), sorted.begin() + nf / 2, sorted.end());
    s.out_of_plane_median = sorted[nf / 2];
  }
  if (surface && mesh.num_vertices()) {
    std::vector<double> dist(mesh.num_vertices());
    tbb::parallel_for(0, mesh.num_vertices(),
                      [&](int v) { dist[v] = surface->distance(mesh.vertex(v)); });
    for (double d : dist) {
      s.surface_distance_max = std::max(s.surface_distance_max, d);
      s.surface_distance_mean += d;
    }
    s.surface_distance_mean /= mesh.num_vertices();
  }
  return s;
}

namespace {
/// Panels that are flat already (triangles; planar quads) are kept as they are: moving their
/// joints could only make the grid worse. Fills `out` and returns true when `design`'s panels
/// already pass the post-check's out-of-plane bound and none self-intersects.
bool keep_if_flat_already(const PolyMesh& design, const std::vector<int>& supports,
                          const FlatPanelOptions& options, FlatPanelResult& out) {
  const PanelShape given = panel_shape(design);
  if (given.out_of_plane_max > options.max_out_of_plane || given.self_intersecting != 0)
    return false;
  out.mesh = design;
  out.supports = supports;
  std::sort(out.supports.begin(), out.supports.end());
  out.source_vertex.resize(design.num_vertices());
  for (int v = 0; v < design.num_vertices(); ++v) out.source_vertex[v] = v;
  out.source_face.resize(design.num_faces());
  std::iota(out.source_face.begin(), out.source_face.end(), 0);
  for (int f = 0; f < design.num_faces(); ++f) {
    const Vec3 n = vector_area(design, f).normalized();
    out.normal.push_back(n);
    out.offset.push_back(n.dot(design.vertex(design.faces[f][0])));
  }
  out.stats.converged = true;
  out.stats.out_of_plane_max = given.out_of_plane_max;
  return true;
}
}  // namespace

namespace {

/// The design's shortest beam (m).
double shortest_beam(const PolyMesh& design, const Topology& topo) {
  double shortest = INFINITY;
  for (int e = 0; e < topo.num_edges(); ++e)
    shortest =
        std::min(shortest, (design.vertex(topo.edges[e][0]) - design.vertex(topo.edges[e][1])).norm());
  return shortest;
}

/// The post-check's measures of a flat result.
struct PostCheck {
  double own_plane = 0;   ///< largest corner distance to its panel's plane (m)
  double best_fit = 0;    ///< largest corner distance to its panel's best-fit plane (m)
  int self_intersecting = 0;
  double shortest = INFINITY;  ///< shortest beam (m)
  double farthest = 0;         ///< largest joint distance to the surface (m)
  double span = 0;             ///< larger plan side of the surface (m)
};

/// The surface's larger plan side (m): the post-check's span.
double plan_span(const TriMesh& surface) {
  const Eigen::RowVector3d extent = surface.V.colwise().maxCoeff() - surface.V.colwise().minCoeff();
  return std::max(extent.x(), extent.y());
}

PostCheck post_check(const FlatPanelResult& out, const std::vector<Vec3>& normal,
                     const std::vector<double>& offset, const TriMesh& surface,
                     const SurfaceProjector& projector) {
  PostCheck c;
  const PolyMesh& m = out.mesh;
  for (int f = 0; f < m.num_faces(); ++f) {
    const auto& face = m.faces[f];
    for (std::size_t k = 0; k < face.size(); ++k) {
      const Vec3 p = m.vertex(face[k]);
      c.own_plane = std::max(c.own_plane, std::abs(normal[f].dot(p) - offset[f]));
      c.shortest = std::min(c.shortest, (m.vertex(face[(k + 1) % face.size()]) - p).norm());
    }
  }
  const PanelShape shape = panel_shape(m);
  c.best_fit = shape.out_of_plane_max;
  c.self_intersecting = shape.self_intersecting;
  c.span = plan_span(surface);
  std::vector<double> dist(m.num_vertices());
  tbb::parallel_for(0, m.num_vertices(), [&](int v) { dist[v] = projector.distance(m.vertex(v)); });
  for (double d : dist) c.farthest = std::max(c.farthest, d);
  return c;
}

/// What fails the post-check (every failing part, one line), or "" when it passes: every corner
/// within `max_out_of_plane` of its panel's plane and of its best-fit plane, no self-intersecting
/// panel, no beam shorter than the allowed, no joint farther from the surface than the limit.
std::string post_check_failure(const PostCheck& c, const FlatPanelOptions& o,
                               double shortest_allowed) {
  std::vector<std::string> parts;
  const double off = std::max(c.own_plane, c.best_fit);
  if (!(off <= o.max_out_of_plane))
    parts.push_back(fmt::format("a panel is {:.3g} mm out of its plane (limit {:.3g} mm)", 1e3 * off,
                                1e3 * o.max_out_of_plane));
  if (c.self_intersecting > 0)
    parts.push_back(fmt::format("{} panels self-intersect", c.self_intersecting));
  if (!(c.shortest >= shortest_allowed))
    parts.push_back(fmt::format("a beam shrank to {:.3g} m (limit {:.3g} m)", c.shortest,
                                shortest_allowed));
  if (!(c.farthest <= o.max_surface_distance * c.span))
    parts.push_back(fmt::format("a joint is {:.3g} m from the surface (limit {:.3g} of the span, "
                                "{:.3g} m)",
                                c.farthest, o.max_surface_distance,
                                o.max_surface_distance * c.span));
  std::string all;
  for (const std::string& p : parts) all += (all.empty() ? "" : "; ") + p;
  return all;
}

}  // namespace

namespace {

/// For a restart after a failed post-check: multiplies by `factor` the stiffness of the joints of
/// every failing panel (not simple, a side shorter than the post-check allows, a corner farther
/// from the surface than `limit`) and of its neighbouring panels. Their design positions pass
/// every check (on the surface, simple cells, design-length beams), so the next attempt keeps
/// that region closer to them and lets the planes elsewhere take up the curvature.
void hold_failing_regions(const Layout& L, const Problem& P, const Planes& pl,
                          const std::vector<Vec3>& x, const SurfaceProjector& projector,
                          double limit, double factor, std::vector<double>& stiffness) {
  std::vector<char> mark(L.joints.size(), 0);
  for (std::size_t f = 0; f < L.faces.size(); ++f) {
    const auto& face = L.faces[f];
    std::vector<Vec3> p;
    bool bad = false;
    for (std::size_t k = 0; k < face.size(); ++k) {
      p.push_back(x[face[k]]);
      bad |= !((x[face[(k + 1) % face.size()]] - x[face[k]]).norm() >= P.shortest_allowed);
      bad |= !(projector.distance(x[face[k]]) <= limit);
    }
    if (!bad && simple_2d(in_plane(p, pl.n[f]))) continue;
    for (int j : face) mark[j] = 1;
    for (int g : P.face_neighbours[f])
      for (int j : L.faces[g]) mark[j] = 1;
  }
  for (std::size_t j = 0; j < mark.size(); ++j)
    if (mark[j]) stiffness[j] *= factor;
}

/// The last resort of a failed attempt (split_failing_panels): `out` (the attempt's supports,
/// source joints and stats) with its failing panels glazed as triangles, kept in `best` when it
/// passes the same post-check with fewer triangulated panels than the best so far.
void keep_if_split_passes(const Problem& P, const Planes& pl, const TriMesh& surface,
                          const SurfaceProjector& projector, FlatPanelResult out,
                          std::optional<FlatPanelResult>& best) {
  const double limit = P.o.max_surface_distance * plan_span(surface);
  const int max_panels =
      static_cast<int>(std::floor(P.o.max_triangulated * static_cast<double>(P.L->faces.size())));
  SplitPanels s;
  if (max_panels <= 0 || !split_failing_panels(P, pl, projector, limit, max_panels, s)) return;
  if (best && best->stats.triangulated_panels <= s.split) return;
  out.mesh.V = to_points(s.x);
  out.mesh.faces = std::move(s.faces);
  out.source_face = std::move(s.owner);
  out.normal = std::move(s.normal);
  out.offset = std::move(s.offset);
  const PostCheck c = post_check(out, out.normal, out.offset, surface, projector);
  const std::string failure = post_check_failure(c, P.o, P.shortest_allowed);
  spdlog::debug("[flat panels] {} panels triangulated: {}", s.split,
                failure.empty() ? "passes" : failure);
  if (!failure.empty()) return;
  out.stats.triangulated_panels = s.split;
  out.stats.surface_weight = P.o.surface_weight;
  out.stats.out_of_plane_max = c.own_plane;
  out.stats.surface_distance_max = c.farthest;
  out.stats.shortest_beam = c.shortest;
  best = std::move(out);
}

/// One run of the optimisation with `options` (its surface weight), checked; throws
/// FlatPanelsFailed when the result fails the post-check, after raising `stiffness` (per joint,
/// in and out) where it failed (hold_failing_regions) and keeping in `split` the result with the
/// failing panels triangulated when that passes with fewer of them (keep_if_split_passes).
FlatPanelResult flat_attempt(const PolyMesh& design, const std::vector<int>& supports,
                             const TriMesh& surface, const SurfaceProjector& projector,
                             const FlatPanelOptions& options, std::vector<double>& stiffness,
                             std::optional<FlatPanelResult>& split) {
  FlatPanelResult out;
  const int nv = design.num_vertices(), nf = design.num_faces();
  std::vector<char> is_support(nv, 0);
  for (int v : supports)
    if (v >= 0 && v < nv) is_support[v] = 1;
  std::vector<Vec3> x0(nv), vertex_normal(nv);
  for (int v = 0; v < nv; ++v) x0[v] = design.vertex(v);
  std::vector<Anchor> design_anchor;
  update_anchors(surface, projector, x0, design_anchor);
  for (int v = 0; v < nv; ++v) vertex_normal[v] = design_anchor[v].normal;
  Layout L = build_layout(design, vertex_normal, is_support);
  out.stats.split_joints = L.split;
  out.stats.added_joints = static_cast<int>(L.joints.size()) - nv;

  Problem P;
  P.L = &L;
  P.o = options;
  const Topology topo = build_topology(design);
  P.face_neighbours.resize(nf);
  double length = 0;
  for (int e = 0; e < topo.num_edges(); ++e) {
    length += (design.vertex(topo.edges[e][0]) - design.vertex(topo.edges[e][1])).norm();
    if (topo.edge_faces[e].size() == 2) {
      P.face_neighbours[topo.edge_faces[e][0]].push_back(topo.edge_faces[e][1]);
      P.face_neighbours[topo.edge_faces[e][1]].push_back(topo.edge_faces[e][0]);
    }
  }
  P.h = topo.num_edges() ? length / topo.num_edges() : 1;
  if (!(P.h > 0)) throw FlatPanelsFailed("the grid-shell has no length");
  const double shortest_design = shortest_beam(design, topo);
  for (const Joint& J : L.joints) {
    P.x0.push_back(x0[J.source] + J.along * options.split_spacing * shortest_design * J.tangent);
    P.anchor.push_back(design_anchor[J.source]);
  }
  P.shortest_allowed = options.min_beam_ratio * shortest_design;
  stiffness.resize(L.joints.size(), 1.0);
  P.stiffness = stiffness;
  P.beams = beams_of(L, P.x0, options.beam_keep);
  P.inside = inside_sides(L, P.x0);
  const std::vector<Anchor> anchors = P.anchor;
  Planes pl = start_planes(P, surface, projector, P.x0);
  std::vector<Vec3> x;
  std::vector<double> det;
  if (!joints_of(P, pl, x, det, options.min_det) && options.lift > 0) {
    // Parallel planes at a joint (a flat or cylindrical part): start again from lifted joints.
    P.anchor = anchors;
    pl = start_planes(P, surface, projector,
                      lifted_targets(P, options.lift, bbox_diagonal(design.V)));
    out.stats.lifted = true;
  }
  out.stats.iterations = optimise(P, pl, surface, projector, out.stats);
  for (int round = 0; round < options.flip_rounds; ++round) {
    // Beams the planes shrank below the post-check's shortest: turned over, then optimised again.
    if (!joints_of(P, pl, x, det, options.min_det) || short_beams(P, x) == 0) break;
    const int flips = flip_collapsed_beams(L, P, pl, x, std::max(1, nf / 10));
    if (flips == 0) break;
    out.stats.flipped_beams += flips;
    P.beams = beams_of(L, P.x0, options.beam_keep);
    P.inside = inside_sides(L, P.x0);
    out.stats.iterations += optimise(P, pl, surface, projector, out.stats);
  }

  for (std::size_t j = 0; j < L.joints.size(); ++j) {
    out.source_vertex.push_back(L.joints[j].source);
    if (L.joints[j].support) out.supports.push_back(static_cast<int>(j));
  }
  if (!joints_of(P, pl, x, det, options.min_det)) {
    keep_if_split_passes(P, pl, surface, projector, out, split);
    throw FlatPanelsFailed("the panels' planes are parallel at a joint");
  }
  if (spdlog::should_log(spdlog::level::debug))
    for (int f = 0; f < nf; ++f) {
      std::vector<Vec3> p;
      double far = 0, dmin = 1;
      bool boundary = false;
      for (int j : L.faces[f]) {
        p.push_back(x[j]);
        far = std::max(far, (x[j] - P.x0[j]).norm() / P.h);
        dmin = std::min(dmin, std::abs(det[j]));
        for (int s = 0; s < 3; ++s) boundary |= L.joints[j].plane[s] < 0;
      }
      if (!simple_2d(in_plane(p, pl.n[f])))
        spdlog::debug("[flat panels] panel {} ({} sides{}) self-intersects: joints up to {:.3g} "
                      "beams from the design, smallest det {:.3g}",
                      f, p.size(), boundary ? ", boundary" : "", far, dmin);
    }
  out.mesh.V = to_points(x);
  out.mesh.faces = L.faces;
  out.source_face.resize(nf);
  std::iota(out.source_face.begin(), out.source_face.end(), 0);
  out.normal = pl.n;
  out.offset = pl.d;
  out.stats.min_det = INFINITY;
  for (double d : det) out.stats.min_det = std::min(out.stats.min_det, std::abs(d));
  const PostCheck c = post_check(out, pl.n, pl.d, surface, projector);
  out.stats.out_of_plane_max = c.own_plane;
  out.stats.surface_distance_max = c.farthest;
  out.stats.shortest_beam = c.shortest;
  spdlog::debug("[flat panels] post-check: {:.3g} mm out of plane, {} self-intersecting, shortest "
                "beam {:.3g} m (limit {:.3g}), farthest joint {:.3g} m (limit {:.3g})",
                1e3 * std::max(c.own_plane, c.best_fit), c.self_intersecting, c.shortest,
                P.shortest_allowed, c.farthest, options.max_surface_distance * c.span);
  const std::string failure = post_check_failure(c, options, P.shortest_allowed);
  if (!failure.empty()) {
    hold_failing_regions(L, P, pl, x, projector, options.max_surface_distance * c.span,
                         options.restart_stiffness, stiffness);
    keep_if_split_passes(P, pl, surface, projector, std::move(out), split);
    throw FlatPanelsFailed(failure);
  }
  return out;
}

}  // namespace

FlatPanelResult flat_panels(const PolyMesh& design, const std::vector<int>& supports,
                            const TriMesh& surface, const SurfaceProjector& projector,
                            const FlatPanelOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  FlatPanelResult out;
  if (design.num_faces() == 0) throw FlatPanelsFailed("no panels");
  if (keep_if_flat_already(design, supports, options, out)) return out;
  std::vector<double> weights{options.surface_weight};
  weights.insert(weights.end(), options.retry_surface_weights.begin(),
                 options.retry_surface_weights.end());
  std::string first_failure;
  std::optional<FlatPanelResult> split;  // the last resort: failing panels triangulated
  int attempts = 0;
  for (std::size_t k = 0; k < weights.size(); ++k) {
    FlatPanelOptions o = options;
    o.surface_weight = weights[k];
    std::vector<double> stiffness;  // per joint, filled by the first attempt
    for (int restart = 0; restart <= options.restarts; ++restart) {
      const std::vector<double> before = stiffness;
      try {
        ++attempts;
        out = flat_attempt(design, supports, surface, projector, o, stiffness, split);
        out.stats.attempts = attempts;
        out.stats.surface_weight = weights[k];
        out.stats.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return out;
      } catch (const FlatPanelsFailed& e) {
        spdlog::debug("[flat panels] surface weight {}, restart {}: {}", weights[k], restart,
                      e.what());
        if (k == 0 && restart == 0) first_failure = e.what();
        const bool held = before.empty()
                              ? std::any_of(stiffness.begin(), stiffness.end(),
                                            [](double w) { return w != 1.0; })
                              : stiffness != before;
        if (!held) break;  // nothing failed where a restart could hold it: the same result again
      }
    }
  }
  if (split) {
    split->stats.attempts = attempts;
    split->stats.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return std::move(*split);
  }
  // What the first (default) attempt failed on; the retries and restarts are in docs/panels.md.
  throw FlatPanelsFailed(first_failure);
}

}  // namespace gridshell
