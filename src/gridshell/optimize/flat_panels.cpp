#include "gridshell/optimize/flat_panels.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include "gridshell/core/cholmod_support.h"
#include "gridshell/core/enum_words.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/metrics.h"
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

namespace {

/// A panel polygon's 2-D corners in the frame of `normal`.
std::vector<Eigen::Vector2d> in_plane(const std::vector<Vec3>& p, const Vec3& normal) {
  const auto [r, s] = plane_axes(normal);
  std::vector<Eigen::Vector2d> q(p.size());
  for (std::size_t k = 0; k < p.size(); ++k) q[k] = {p[k].dot(r), p[k].dot(s)};
  return q;
}

bool segments_cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
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

}  // namespace

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

/// A joint of the flat grid-shell: the design joint it comes from and its three planes (≥ 0: a
/// panel; < 0: fixed plane −1 − k).
struct Joint {
  int source = 0;
  int plane[3] = {0, 0, 0};
  bool support = false;
  bool pinned = false;  ///< an interior support: held at its design position
};

/// The flat grid-shell's topology: joints, their planes, the faces over the new joints.
struct Layout {
  std::vector<Joint> joints;
  std::vector<Vec3> fixed_normal;
  std::vector<double> fixed_offset;
  std::vector<std::vector<int>> faces;
  int split = 0;
};

/// One use of vertex v by face f: its neighbours in f.
struct Corner {
  int face, slot, prev, next;
};

/// The corners around v in fan order (each one's `next` is the following one's `prev`); for a
/// boundary joint the fan starts at the face after the boundary. Throws for a non-manifold joint.
std::vector<Corner> fan(const std::vector<Corner>& around, bool boundary, int v) {
  const int k = static_cast<int>(around.size());
  int start = 0;
  if (boundary) {  // the corner whose prev is no other corner's next
    start = -1;
    for (int i = 0; i < k && start < 0; ++i) {
      bool follows = false;
      for (int j = 0; j < k; ++j) follows |= j != i && around[j].next == around[i].prev;
      if (!follows) start = i;
    }
    if (start < 0) throw FlatPanelsFailed(fmt::format("joint {} is not manifold", v));
  }
  std::vector<Corner> out{around[start]};
  std::vector<char> used(k, 0);
  used[start] = 1;
  while (static_cast<int>(out.size()) < k) {
    int found = -1;
    for (int j = 0; j < k; ++j)
      if (!used[j] && around[j].prev == out.back().next) found = j;
    if (found < 0) throw FlatPanelsFailed(fmt::format("joint {} is not manifold", v));
    used[found] = 1;
    out.push_back(around[found]);
  }
  return out;
}

/// Adds a fixed plane through x with normal n; returns its plane reference.
int add_fixed(Layout& L, const Vec3& n, const Vec3& x) {
  L.fixed_normal.push_back(n);
  L.fixed_offset.push_back(n.dot(x));
  return -static_cast<int>(L.fixed_normal.size());
}

/// The boundary plane(s) of boundary joint v: normal n_s × t (and t for a corner).
std::pair<Vec3, Vec3> boundary_frame(const PolyMesh& design, int v, int before, int after,
                                     const Vec3& surface_normal) {
  Vec3 t = design.vertex(after) - design.vertex(before);
  if (t.norm() <= 0) t = design.vertex(after) - design.vertex(v);
  t.normalize();
  Vec3 m = surface_normal.cross(t);
  if (m.norm() < 1e-6) m = t.unitOrthogonal();
  return {m.normalized(), t};
}

/// The layout: which planes meet at each joint; joints of more than three planes split into fans.
Layout build_layout(const PolyMesh& design, const std::vector<Vec3>& vertex_normal,
                    const std::vector<char>& is_support) {
  const Topology topo = build_topology(design);
  const int nv = design.num_vertices();
  std::vector<std::vector<Corner>> around(nv);
  for (int f = 0; f < design.num_faces(); ++f) {
    const auto& face = design.faces[f];
    const int n = static_cast<int>(face.size());
    for (int k = 0; k < n; ++k)
      around[face[k]].push_back({f, k, face[(k + n - 1) % n], face[(k + 1) % n]});
  }
  Layout L;
  L.faces = design.faces;
  std::vector<std::vector<std::vector<int>>> replace(design.num_faces());
  for (int f = 0; f < design.num_faces(); ++f) replace[f].resize(design.faces[f].size());
  L.joints.resize(nv);  // joint v keeps id v; split parts are appended
  for (int v = 0; v < nv; ++v) {
    L.joints[v].source = v;
    L.joints[v].support = is_support[v];
    L.joints[v].pinned = is_support[v] && !topo.on_boundary[v];
    if (around[v].empty()) throw FlatPanelsFailed(fmt::format("joint {} is in no panel", v));
    const bool boundary = topo.on_boundary[v];
    const std::vector<Corner> c = fan(around[v], boundary, v);
    const int k = static_cast<int>(c.size());
    std::vector<std::array<int, 3>> parts;  // planes of each part, in order
    std::vector<std::vector<int>> part_of(k);  // per corner: the parts in face order
    if (!boundary) {
      if (k < 3) throw FlatPanelsFailed(fmt::format("interior joint {} has {} panels", v, k));
      // u_i = f1 ∩ f(i+1) ∩ f(i+2), i = 0 … k − 3 (0-based corners).
      for (int i = 0; i + 2 < k; ++i) parts.push_back({c[0].face, c[i + 1].face, c[i + 2].face});
      for (int i = static_cast<int>(parts.size()) - 1; i >= 0; --i) part_of[0].push_back(i);
      part_of[1] = {0};
      for (int j = 2; j + 1 < k; ++j) part_of[j] = {j - 2, j - 1};
      part_of[k - 1].push_back(k - 3);
    } else {
      const auto [m, t] = boundary_frame(design, v, c.front().prev, c.back().next, vertex_normal[v]);
      const int B = add_fixed(L, m, design.vertex(v));
      if (k == 1) {
        parts.push_back({c[0].face, B, add_fixed(L, t, design.vertex(v))});
        part_of[0] = {0};
      } else {
        // u_i = B ∩ f_i ∩ f(i+1), i = 0 … k − 2.
        for (int i = 0; i + 1 < k; ++i) parts.push_back({B, c[i].face, c[i + 1].face});
        part_of[0] = {0};
        for (int j = 1; j + 1 < k; ++j) part_of[j] = {j - 1, j};
        part_of[k - 1] = {k - 2};
      }
    }
    std::vector<int> ids(parts.size());
    for (std::size_t i = 0; i < parts.size(); ++i) {
      ids[i] = i == 0 ? v : static_cast<int>(L.joints.size());
      if (i > 0) L.joints.push_back({v, {0, 0, 0}, false, false});
      for (int s = 0; s < 3; ++s) L.joints[ids[i]].plane[s] = parts[i][s];
    }
    if (parts.size() > 1) ++L.split;
    for (int j = 0; j < k; ++j) {
      std::vector<int>& r = replace[c[j].face][c[j].slot];
      for (int p : part_of[j]) r.push_back(ids[p]);
    }
  }
  for (int f = 0; f < design.num_faces(); ++f) {
    L.faces[f].clear();
    for (const auto& r : replace[f]) L.faces[f].insert(L.faces[f].end(), r.begin(), r.end());
  }
  return L;
}

/// The planes being optimised and the fixed ones.
struct Planes {
  std::vector<Vec3> n;
  std::vector<double> d;
};

/// Per joint the closest point on M and M's normal there (the surface term's anchor).
struct Anchor {
  Vec3 point = Vec3::Zero(), normal = Vec3::UnitZ();
  int triangle = -1;
};

struct Problem {
  const Layout* L = nullptr;
  std::vector<Vec3> x0;         ///< design position per joint
  std::vector<Anchor> anchor;   ///< per joint
  std::vector<std::vector<int>> face_neighbours;
  double h = 1;                 ///< mean beam length
  FlatPanelOptions o;
};

void plane_of(const Problem& P, const Planes& pl, int ref, Vec3& n, double& d) {
  if (ref >= 0) {
    n = pl.n[ref];
    d = pl.d[ref];
  } else {
    n = P.L->fixed_normal[-1 - ref];
    d = P.L->fixed_offset[-1 - ref];
  }
}

/// All joints of `pl`; false when a joint's planes are nearly parallel.
bool joints_of(const Problem& P, const Planes& pl, std::vector<Vec3>& x, std::vector<double>& det,
               double min_det) {
  const int nj = static_cast<int>(P.L->joints.size());
  x.resize(nj);
  det.resize(nj);
  std::vector<char> ok(nj, 1);
  tbb::parallel_for(0, nj, [&](int j) {
    Vec3 n[3];
    double d[3];
    for (int s = 0; s < 3; ++s) plane_of(P, pl, P.L->joints[j].plane[s], n[s], d[s]);
    ok[j] = intersect_planes(n, d, x[j], det[j], min_det) && x[j].allFinite();
  });
  return std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
}

/// The energy's residuals of joint j (up to 5): surface, design (3), barrier.
int joint_residuals(const Problem& P, int j, const Vec3& x, double det, double r[5]) {
  const Joint& J = P.L->joints[j];
  const double ws = std::sqrt(P.o.surface_weight) / P.h;
  const double w0 = std::sqrt(J.pinned ? P.o.support_weight : P.o.design_weight) / P.h;
  r[0] = ws * P.anchor[j].normal.dot(x - P.anchor[j].point);
  for (int k = 0; k < 3; ++k) r[1 + k] = w0 * (x[k] - P.x0[j][k]);
  const double a = std::abs(det);
  r[4] = a < P.o.barrier_det ? std::sqrt(P.o.barrier_weight) * std::log(P.o.barrier_det / a) : 0;
  return 5;
}

/// The fairness residual of face f: n_f − mean of its neighbours' normals.
Vec3 fairness_residual(const Problem& P, const Planes& pl, int f) {
  const auto& nb = P.face_neighbours[f];
  Vec3 m = Vec3::Zero();
  for (int g : nb) m += pl.n[g];
  if (nb.empty()) return Vec3::Zero();
  return std::sqrt(P.o.fairness_weight) * (pl.n[f] - m / static_cast<double>(nb.size()));
}

double energy(const Problem& P, const Planes& pl, const std::vector<Vec3>& x,
              const std::vector<double>& det) {
  double e = 0;
  for (std::size_t j = 0; j < x.size(); ++j) {
    double r[5];
    joint_residuals(P, static_cast<int>(j), x[j], det[j], r);
    for (double v : r) e += v * v;
  }
  for (std::size_t f = 0; f < pl.n.size(); ++f)
    e += fairness_residual(P, pl, static_cast<int>(f)).squaredNorm();
  return e;
}

/// Number of panels that are not simple polygons (in their own planes).
int self_intersections(const Layout& L, const Planes& pl, const std::vector<Vec3>& x) {
  int count = 0;
  for (std::size_t f = 0; f < L.faces.size(); ++f) {
    std::vector<Vec3> p;
    for (int j : L.faces[f]) p.push_back(x[j]);
    count += !simple_2d(in_plane(p, pl.n[f]));
  }
  return count;
}


/// The closest points on M of the joints `x` and M's normals there (walks from the last ones).
void update_anchors(const TriMesh& surface, const SurfaceProjector& projector,
                    const std::vector<Vec3>& x, std::vector<Anchor>& anchor) {
  anchor.resize(x.size());
  tbb::parallel_for(0, static_cast<int>(x.size()), [&](int j) {
    Anchor& a = anchor[j];
    a.point = projector.closest_point_walk(x[j], a.triangle);
    if (a.triangle >= 0 && a.triangle < surface.num_faces()) {
      const auto& t = surface.F.row(a.triangle);
      const Vec3 p0 = surface.V.row(t[0]).transpose(), p1 = surface.V.row(t[1]).transpose(),
                 p2 = surface.V.row(t[2]).transpose();
      const Vec3 n = (p1 - p0).cross(p2 - p0);
      if (n.norm() > 0) a.normal = n.normalized();
    }
  });
}

/// Adds the local Gauss–Newton block G (rows × cols, residuals r) at the unknowns `col` (−1 =
/// none) to JᵀJ (triplets) and Jᵀr.
void add_block(const Eigen::MatrixXd& G, const Eigen::VectorXd& r, const std::vector<int>& col,
               std::vector<Eigen::Triplet<double>>& H, Eigen::VectorXd& g) {
  const Eigen::MatrixXd GtG = G.transpose() * G;
  const Eigen::VectorXd Gtr = G.transpose() * r;
  const int m = static_cast<int>(col.size());
  for (int a = 0; a < m; ++a) {
    if (col[a] < 0) continue;
    g[col[a]] += Gtr[a];
    for (int b = 0; b < m; ++b)
      if (col[b] >= 0 && col[b] <= col[a]) H.emplace_back(col[a], col[b], GtG(a, b));
  }
}

/// The joint terms' Gauss–Newton blocks (9 unknowns: the three planes' (α1, α2, β)).
void joint_blocks(const Problem& P, const Planes& pl, const std::vector<Vec3>& x,
                  const std::vector<double>& det, std::vector<Eigen::Triplet<double>>& H,
                  Eigen::VectorXd& g) {
  for (std::size_t j = 0; j < x.size(); ++j) {
    const Joint& J = P.L->joints[j];
    Vec3 n[3];
    double d[3];
    for (int s = 0; s < 3; ++s) plane_of(P, pl, J.plane[s], n[s], d[s]);
    Vec3 xj;
    double dj;
    Eigen::Matrix<double, 3, 12> Jx;
    intersect_planes(n, d, xj, dj, 0, &Jx);
    Eigen::Matrix<double, 3, 9> Dx = Eigen::Matrix<double, 3, 9>::Zero();
    Eigen::Matrix<double, 1, 9> Ddet = Eigen::Matrix<double, 1, 9>::Zero();
    const Vec3 cof[3] = {n[1].cross(n[2]), n[2].cross(n[0]), n[0].cross(n[1])};
    std::vector<int> col(9, -1);
    for (int s = 0; s < 3; ++s) {
      const int f = J.plane[s];
      if (f < 0) continue;
      const auto [b1, b2] = plane_axes(pl.n[f]);
      Dx.col(3 * s) = Jx.block<3, 3>(0, 4 * s) * b1;
      Dx.col(3 * s + 1) = Jx.block<3, 3>(0, 4 * s) * b2;
      Dx.col(3 * s + 2) = Jx.col(4 * s + 3);
      Ddet(3 * s) = cof[s].dot(b1);
      Ddet(3 * s + 1) = cof[s].dot(b2);
      for (int k = 0; k < 3; ++k) col[3 * s + k] = 3 * f + k;
    }
    double res[5];
    joint_residuals(P, static_cast<int>(j), x[j], det[j], res);
    const double ws = std::sqrt(P.o.surface_weight) / P.h;
    const double w0 = std::sqrt(J.pinned ? P.o.support_weight : P.o.design_weight) / P.h;
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(5, 9);
    G.row(0) = ws * P.anchor[j].normal.transpose() * Dx;
    G.middleRows(1, 3) = w0 * Dx;
    if (res[4] > 0) G.row(4) = -std::sqrt(P.o.barrier_weight) / det[j] * Ddet;
    add_block(G, Eigen::Map<Eigen::VectorXd>(res, 5), col, H, g);
  }
}

/// The fairness terms' blocks: face f and its neighbours' (α1, α2).
void fairness_blocks(const Problem& P, const Planes& pl, std::vector<Eigen::Triplet<double>>& H,
                     Eigen::VectorXd& g) {
  const double w = std::sqrt(P.o.fairness_weight);
  for (std::size_t f = 0; f < pl.n.size(); ++f) {
    const auto& nb = P.face_neighbours[f];
    if (nb.empty()) continue;
    const int m = 2 + 2 * static_cast<int>(nb.size());
    Eigen::MatrixXd G(3, m);
    std::vector<int> col(m);
    const auto [b1, b2] = plane_axes(pl.n[f]);
    G.col(0) = w * b1;
    G.col(1) = w * b2;
    col[0] = 3 * static_cast<int>(f);
    col[1] = 3 * static_cast<int>(f) + 1;
    for (std::size_t k = 0; k < nb.size(); ++k) {
      const auto [c1, c2] = plane_axes(pl.n[nb[k]]);
      G.col(2 + 2 * k) = -w / nb.size() * c1;
      G.col(3 + 2 * k) = -w / nb.size() * c2;
      col[2 + 2 * k] = 3 * nb[k];
      col[3 + 2 * k] = 3 * nb[k] + 1;
    }
    const Vec3 r = fairness_residual(P, pl, static_cast<int>(f));
    add_block(G, r, col, H, g);
  }
}

/// The planes after the step δ: n ← normalize(n + α1 b1 + α2 b2), d ← d + β.
Planes step(const Planes& pl, const Eigen::VectorXd& delta) {
  Planes out = pl;
  for (std::size_t f = 0; f < pl.n.size(); ++f) {
    const auto [b1, b2] = plane_axes(pl.n[f]);
    out.n[f] = (pl.n[f] + delta[3 * f] * b1 + delta[3 * f + 1] * b2).normalized();
    out.d[f] = pl.d[f] + delta[3 * f + 2];
  }
  return out;
}

/// The design's joints lifted by the paraboloid −σ κ/2 |P_t(x − o)|² along M's normal (o the
/// centre of the grid-shell, κ = lift / bbox diagonal, σ the side the panels' normals point to):
/// on flat and cylindrical parts the tangent planes of a paraboloid meet over the circumcentres
/// of neighbouring cells (a power diagram), so joint positions become well defined.
std::vector<Vec3> lifted_targets(const Problem& P, double lift, double diagonal) {
  std::vector<Vec3> t = P.x0;
  if (lift <= 0) return t;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& x : P.x0) centre += x;
  centre /= std::max<std::size_t>(1, P.x0.size());
  double side = 0;
  for (std::size_t j = 0; j < t.size(); ++j) side += P.anchor[j].normal.dot(P.x0[j] - centre);
  const double sigma = side >= 0 ? 1 : -1, kappa = lift / std::max(1e-300, diagonal);
  for (std::size_t j = 0; j < t.size(); ++j) {
    const Vec3& n = P.anchor[j].normal;
    const Vec3 y = (P.x0[j] - centre) - (P.x0[j] - centre).dot(n) * n;
    t[j] -= 0.5 * sigma * kappa * y.squaredNorm() * n;
  }
  return t;
}

/// Best-fit plane of each panel's joints `x` (normal kept on the side of the previous one).
void fit_planes(const Layout& L, const std::vector<Vec3>& x, Planes& pl) {
  tbb::parallel_for(0, static_cast<int>(L.faces.size()), [&](int f) {
    std::vector<Vec3> p;
    for (int j : L.faces[f]) p.push_back(x[j]);
    const FaceFrame fr = face_frame(p);
    Vec3 n = fr.normal;
    if (pl.n[f].dot(n) < 0) n = -n;
    pl.n[f] = n;
    pl.d[f] = n.dot(fr.centroid);
  });
}

/// The starting planes: nearly planar panels by alternation (ShapeUp-like, Bouaziz et al. 2012)
/// with a rising planarity weight w_p = 1 … 1e6: each panel's best-fit plane, then each joint at
/// argmin w_p Σ (n·x − d)² over its three planes + the joint terms of the energy (towards the
/// lifted design joint). Where the planes then meet well, their intersections are next to these
/// joints and the Levenberg–Marquardt steps start close to a minimum.
Planes start_planes(Problem& P, const TriMesh& surface, const SurfaceProjector& projector,
                    const std::vector<Vec3>& target) {
  const Layout& L = *P.L;
  const int nj = static_cast<int>(L.joints.size()), nf = static_cast<int>(L.faces.size());
  Planes pl;
  pl.n.assign(nf, Vec3::Zero());
  pl.d.assign(nf, 0);
  std::vector<Vec3> x = target;
  for (int stage = 0; stage <= 6; ++stage) {
    const double wp = std::pow(10.0, stage);
    for (int it = 0; it < 8; ++it) {
      fit_planes(L, x, pl);
      update_anchors(surface, projector, x, P.anchor);
      tbb::parallel_for(0, nj, [&](int j) {
        const Joint& J = L.joints[j];
        const double w0 = J.pinned ? P.o.support_weight : P.o.design_weight;  // phase 1
        const Anchor& a = P.anchor[j];
        Eigen::Matrix3d A = w0 * Eigen::Matrix3d::Identity() +
                            P.o.surface_weight * a.normal * a.normal.transpose();
        Vec3 b = w0 * target[j] + P.o.surface_weight * a.normal * a.normal.dot(a.point);
        for (int s = 0; s < 3; ++s) {
          Vec3 n;
          double d;
          plane_of(P, pl, J.plane[s], n, d);
          A += wp * n * n.transpose();
          b += wp * d * n;
        }
        x[j] = A.ldlt().solve(b);
      });
    }
  }
  fit_planes(L, x, pl);
  return pl;
}

/// Levenberg–Marquardt on the planes; returns the iterations run, `converged` when it stopped on
/// its tolerance.
int optimise(Problem& P, Planes& pl, const TriMesh& surface, const SurfaceProjector& projector,
             FlatPanelStats& stats) {
  const int nu = 3 * static_cast<int>(pl.n.size());
  std::vector<Vec3> x;
  std::vector<double> det;
  if (!joints_of(P, pl, x, det, P.o.min_det))
    throw FlatPanelsFailed("the panels' first planes are parallel at a joint");
  int crossings = self_intersections(*P.L, pl, x);
  if (spdlog::should_log(spdlog::level::debug)) {
    int far_interior = 0, far_boundary = 0, boundary = 0;
    for (std::size_t j = 0; j < x.size(); ++j) {
      const bool b = P.L->joints[j].plane[0] < 0 || P.L->joints[j].plane[1] < 0 ||
                     P.L->joints[j].plane[2] < 0;
      boundary += b;
      if ((x[j] - P.x0[j]).norm() > P.h) (b ? far_boundary : far_interior)++;
    }
    spdlog::debug("[flat panels] start: {} joints ({} boundary); farther than a beam from the "
                  "design: {} interior, {} boundary",
                  x.size(), boundary, far_interior, far_boundary);
  }
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
  bool analysed = false;
  double mu = 1e-3;
  int it = 0;
  for (; it < P.o.max_iterations; ++it) {
    update_anchors(surface, projector, x, P.anchor);
    const double E = energy(P, pl, x, det);
    if (it == 0) stats.energy_start = E;
    stats.energy = E;
    std::vector<Eigen::Triplet<double>> T;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(nu);
    joint_blocks(P, pl, x, det, T, g);
    fairness_blocks(P, pl, T, g);
    for (int i = 0; i < nu; ++i) T.emplace_back(i, i, 0.0);
    Eigen::SparseMatrix<double> H(nu, nu);
    H.setFromTriplets(T.begin(), T.end());
    const Eigen::VectorXd diag = H.diagonal();
    bool accepted = false;
    for (int attempt = 0; attempt < 12 && !accepted; ++attempt) {
      Eigen::SparseMatrix<double> A = H;
      for (int i = 0; i < nu; ++i) A.coeffRef(i, i) += mu * (diag[i] + 1e-9);
      if (!analysed) {
        analyze_pattern(solver, A);
        analysed = true;
      }
      solver.factorize(A);
      if (solver.info() != Eigen::Success) {
        mu *= 10;
        continue;
      }
      const Eigen::VectorXd delta = solver.solve(-g);
      const Planes trial = step(pl, delta);
      std::vector<Vec3> xt;
      std::vector<double> dt;
      if (delta.allFinite() && joints_of(P, trial, xt, dt, P.o.min_det)) {
        const int ct = self_intersections(*P.L, trial, xt);
        const double Et = energy(P, trial, xt, dt);
        if ((ct <= crossings || !P.o.guard) && Et < E) {
          pl = trial, x = std::move(xt), det = std::move(dt), crossings = ct;
          stats.energy = Et;
          accepted = true;
          mu = std::max(mu / 3, 1e-9);
          if (E - Et < P.o.tolerance * E) {
            stats.converged = true;
            return it + 1;
          }
        }
      }
      if (!accepted) mu *= 5;
    }
    spdlog::debug("[flat panels] iteration {}: energy {:.6g}, {} self-intersecting, mu {:.3g}{}",
                  it, stats.energy, crossings, mu, accepted ? "" : " (no step)");
    if (!accepted) {  // no step lowers the energy: a minimum to the solver's accuracy
      stats.converged = true;
      return it;
    }
  }
  return it;
}

}  // namespace

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

FlatPanelResult flat_panels(const PolyMesh& design, const std::vector<int>& supports,
                            const TriMesh& surface, const SurfaceProjector& projector,
                            const FlatPanelOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  FlatPanelResult out;
  const int nv = design.num_vertices(), nf = design.num_faces();
  if (nf == 0) throw FlatPanelsFailed("no panels");
  if (keep_if_flat_already(design, supports, options, out)) return out;
  std::vector<char> is_support(nv, 0);
  for (int v : supports)
    if (v >= 0 && v < nv) is_support[v] = 1;
  std::vector<Vec3> x0(nv), vertex_normal(nv);
  for (int v = 0; v < nv; ++v) x0[v] = design.vertex(v);
  std::vector<Anchor> design_anchor;
  update_anchors(surface, projector, x0, design_anchor);
  for (int v = 0; v < nv; ++v) vertex_normal[v] = design_anchor[v].normal;
  const Layout L = build_layout(design, vertex_normal, is_support);
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
  for (const Joint& J : L.joints) {
    P.x0.push_back(x0[J.source]);
    P.anchor.push_back(design_anchor[J.source]);
  }
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

  if (!joints_of(P, pl, x, det, options.min_det))
    throw FlatPanelsFailed("the panels' planes are parallel at a joint");
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
  out.mesh.V.resize(static_cast<int>(x.size()), 3);
  for (std::size_t j = 0; j < x.size(); ++j) out.mesh.V.row(static_cast<int>(j)) = x[j].transpose();
  out.mesh.faces = L.faces;
  out.normal = pl.n;
  out.offset = pl.d;
  out.stats.min_det = INFINITY;
  for (double d : det) out.stats.min_det = std::min(out.stats.min_det, std::abs(d));
  for (std::size_t j = 0; j < L.joints.size(); ++j) {
    out.source_vertex.push_back(L.joints[j].source);
    if (L.joints[j].support) out.supports.push_back(static_cast<int>(j));
  }
  // The post-check: every corner on its panel's plane, every panel simple.
  for (int f = 0; f < nf; ++f)
    for (int j : L.faces[f])
      out.stats.out_of_plane_max =
          std::max(out.stats.out_of_plane_max, std::abs(pl.n[f].dot(x[j]) - pl.d[f]));
  const PanelShape shape = panel_shape(out.mesh);
  out.stats.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!(out.stats.out_of_plane_max <= options.max_out_of_plane) ||
      !(shape.out_of_plane_max <= options.max_out_of_plane))
    throw FlatPanelsFailed(fmt::format("a panel is {:.3g} mm out of its plane (limit {:.3g} mm)",
                                       1e3 * std::max(out.stats.out_of_plane_max,
                                                      shape.out_of_plane_max),
                                       1e3 * options.max_out_of_plane));
  if (shape.self_intersecting > 0)
    throw FlatPanelsFailed(fmt::format("{} panels self-intersect", shape.self_intersecting));
  // A beam the planes have collapsed (two joints at one point) is no frame member.
  double shortest_design = INFINITY, shortest = INFINITY;
  for (int e = 0; e < topo.num_edges(); ++e)
    shortest_design = std::min(
        shortest_design, (design.vertex(topo.edges[e][0]) - design.vertex(topo.edges[e][1])).norm());
  for (int f = 0; f < nf; ++f)
    for (std::size_t k = 0; k < L.faces[f].size(); ++k)
      shortest = std::min(shortest, (x[L.faces[f][k]] - x[L.faces[f][(k + 1) % L.faces[f].size()]])
                                        .norm());
  if (!(shortest >= options.min_beam_ratio * shortest_design))
    throw FlatPanelsFailed(fmt::format("a beam shrank to {:.3g} m (the design's shortest: {:.3g} m)",
                                       shortest, shortest_design));
  const Eigen::RowVector3d extent = surface.V.colwise().maxCoeff() - surface.V.colwise().minCoeff();
  const double span = std::max(extent.x(), extent.y());
  double farthest = 0;
  for (const Vec3& p : x) farthest = std::max(farthest, projector.distance(p));
  if (!(farthest <= options.max_surface_distance * span))
    throw FlatPanelsFailed(fmt::format("a joint is {:.3g} m from the surface (limit {:.3g} of the "
                                       "span, {:.3g} m)",
                                       farthest, options.max_surface_distance,
                                       options.max_surface_distance * span));
  return out;
}

}  // namespace gridshell
