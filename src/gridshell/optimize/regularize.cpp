#include "gridshell/optimize/regularize.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/SparseCore>

#include "gridshell/core/sparse_cholesky.h"
#include "gridshell/core/error.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/metrics.h"
#include "gridshell/optimize/projector.h"

namespace gridshell {

std::vector<VertexConstraint> classify_vertices(const PolyMesh& mesh, double corner_angle_deg) {
  const Topology topo = build_topology(mesh);
  const std::vector<char> corner = boundary_corners(mesh.V, topo.boundary_loops, corner_angle_deg);
  std::vector<VertexConstraint> c(mesh.num_vertices(), VertexConstraint::free);
  for (const auto& loop : topo.boundary_loops)
    for (int v : loop)
      c[v] = corner[v] || topo.vertex_faces[v].size() <= 1 ? VertexConstraint::fixed
                                                           : VertexConstraint::boundary;
  return c;
}

std::vector<VertexConstraint> constraints_from_flags(const std::vector<char>& on_boundary,
                                                     const std::vector<char>& corner) {
  if (!corner.empty() && corner.size() != on_boundary.size())
    throw Error("constraints", "corner and boundary flags differ in length");
  std::vector<VertexConstraint> c(on_boundary.size(), VertexConstraint::free);
  for (std::size_t v = 0; v < c.size(); ++v) {
    if (!corner.empty() && corner[v])
      c[v] = VertexConstraint::fixed;
    else if (on_boundary[v])
      c[v] = VertexConstraint::boundary;
  }
  return c;
}

namespace {

/// Per-face step: (face index, its current vertices, out: target positions).
using TargetFn = std::function<void(int, const std::vector<Vec3>&, std::vector<Vec3>&)>;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void check_input(const PolyMesh& mesh, const std::vector<VertexConstraint>& constraints,
                 const RegularizeOptions& o) {
  const int nv = mesh.num_vertices();
  if (!constraints.empty() && static_cast<int>(constraints.size()) != nv)
    throw Error("constraints", "one constraint per vertex expected");
  for (const auto& f : mesh.faces) {
    if (f.size() < 3) throw Error("mesh", "face with fewer than 3 vertices");
    for (int v : f)
      if (v < 0 || v >= nv) throw Error("mesh", "face index out of range");
  }
  if (!mesh.V.allFinite()) throw Error("mesh", "non-finite vertex coordinates");
  if (o.max_iterations < 0) throw Error("max_iterations", "must be ≥ 0");
  if (!(o.tolerance >= 0)) throw Error("tolerance", "must be ≥ 0");
  if (!(o.closeness > 0) || !std::isfinite(o.closeness))
    throw Error("closeness", "must be a positive number");
  if (!(o.damping > 0 && o.damping <= 2)) throw Error("damping", "must be in (0, 2]");
  if (!(o.stretch_growth >= 1)) throw Error("stretch_growth", "must be ≥ 1");
  if (!(o.restretch >= 0 && o.restretch <= 1)) throw Error("restretch", "must lie in [0, 1]");
  if (!(o.size_anchor >= 0 && o.size_anchor <= 1)) throw Error("size_anchor", "must be in [0, 1]");
  if (!(o.size_evening >= 0 && o.size_evening <= 1))
    throw Error("size_evening", "must lie in [0, 1]");
}

/// Projects the movable vertices of X onto M or its boundary (parallel, disjoint writes).
/// `hints` (optional): positions already on M / its boundary near the answers.
/// `triangles` (optional): per vertex, the triangle of M its last closest point lay on; free
/// vertices then walk from there (SurfaceProjector::closest_point_walk) and it is updated.
void project(Points& X, const std::vector<VertexConstraint>& cons, const std::vector<char>& used,
             const SurfaceProjector& proj, const Points* hints = nullptr,
             std::vector<int>* triangles = nullptr) {
  tbb::parallel_for(0, static_cast<int>(X.rows()), [&](int v) {
    if (!used[v] || cons[v] == VertexConstraint::fixed) return;
    const Vec3 p = X.row(v).transpose();
    const bool b = cons[v] == VertexConstraint::boundary;
    Vec3 q;
    if (triangles && !b) {
      q = proj.closest_point_walk(p, (*triangles)[v]);
    } else if (hints) {
      const Vec3 h = hints->row(v).transpose();
      q = b ? proj.closest_boundary_point(p, h) : proj.closest_point(p, h);
    } else {
      q = b ? proj.closest_boundary_point(p) : proj.closest_point(p);
    }
    X.row(v) = q.transpose();
  });
}

/// A face of X: its plane (through the centroid, unit Newell normal; +z for a face of zero
/// vector area), half perimeter and planarity (mean |distance to the plane| / half perimeter).
struct FacePlane {
  Plane plane{Vec3::Zero(), Vec3::UnitZ()};
  double half_perimeter = 0, planarity = 0;
};

FacePlane face_plane(const Points& X, const std::vector<int>& face) {
  FacePlane fp;
  const std::size_t n = face.size();
  Vec3& centroid = fp.plane.point;
  for (int v : face) centroid += X.row(v).transpose();
  centroid /= static_cast<double>(n);
  Vec3 a = Vec3::Zero();
  double per = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 p = X.row(face[i]).transpose(), q = X.row(face[(i + 1) % n]).transpose();
    a += (p - centroid).cross(q - centroid);
    per += (q - p).norm();
  }
  if (a.norm() > 0) fp.plane.normal = a.normalized();
  fp.half_perimeter = 0.5 * per;
  double dev = 0;
  for (int v : face) dev += std::abs(fp.plane.signed_distance(X.row(v).transpose()));
  fp.planarity = per > 0 ? dev / static_cast<double>(n) / fp.half_perimeter : 0.0;
  return fp;
}

struct GuardBuffers {
  std::vector<FacePlane> planes;
  std::vector<double> excess;
  Points moved;
};

/// Planarity guard: a face that has become less planar than it was in the input (planarity q
/// above its input value q0) asks each of its free vertices to move in the surface's tangent
/// plane so that its height h over the face's plane shrinks by the excess fraction 1 − q0/q.
/// Moving a vertex by u in its tangent plane (normal = mean of its faces' normals) changes its
/// height over face f by a_f · u, a_f = the tangent components of f's normal, to first order;
/// each vertex takes half of argmin_u Σ_f (s_f h_f + a_f · u)² + |u|²/w. Faces that are as
/// planar as they were are left alone. The moves are tangential, so the following projection
/// onto M keeps them.
void guard_planarity(Points& X, const PolyMesh& mesh,
                     const std::vector<std::vector<int>>& vertex_faces,
                     const std::vector<double>& raw_planarity,
                     const std::vector<VertexConstraint>& cons, double weight, GuardBuffers& b) {
  const int nf = mesh.num_faces(), nv = static_cast<int>(X.rows());
  b.planes.resize(nf);
  b.excess.resize(nf);
  tbb::parallel_for(0, nf, [&](int f) {
    b.planes[f] = face_plane(X, mesh.faces[f]);
    const double q = b.planes[f].planarity;
    b.excess[f] = q > 0 ? std::max(0.0, 1 - raw_planarity[f] / q) : 0.0;
  });
  b.moved = X;
  tbb::parallel_for(0, nv, [&](int v) {
    if (cons[v] != VertexConstraint::free || vertex_faces[v].empty()) return;
    Vec3 n = Vec3::Zero();
    bool any = false;
    for (int f : vertex_faces[v]) {
      n += b.planes[f].plane.normal;
      any = any || b.excess[f] > 0;
    }
    if (!any || n.norm() == 0) return;
    n.normalize();
    const Vec3 e1 = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
    const Vec3 e2 = n.cross(e1);
    Eigen::Matrix2d A = Eigen::Matrix2d::Identity() / weight;
    Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
    const Vec3 x = X.row(v).transpose();
    for (int f : vertex_faces[v]) {
      const Plane& plane = b.planes[f].plane;
      const Eigen::Vector2d a(e1.dot(plane.normal), e2.dot(plane.normal));
      A += a * a.transpose();
      rhs += b.excess[f] * plane.signed_distance(x) * a;
    }
    const Eigen::Vector2d u = -A.ldlt().solve(rhs);
    b.moved.row(v) = (x + 0.5 * (u.x() * e1 + u.y() * e2)).transpose();
  });
  X.swap(b.moved);
}

/// The unknowns of the iteration: the vertices some face uses that are not fixed, numbered in
/// vertex order.
struct Unknowns {
  std::vector<char> used;  ///< per vertex: referenced by a face
  std::vector<int> idx;    ///< per vertex: its row, or -1 (unused or fixed)
  int count = 0;
};

Unknowns number_unknowns(const PolyMesh& mesh, const std::vector<VertexConstraint>& cons) {
  const int nv = mesh.num_vertices();
  Unknowns u;
  u.used.assign(nv, 0);
  for (const auto& f : mesh.faces)
    for (int v : f) u.used[v] = 1;
  u.idx.assign(nv, -1);
  for (int v = 0; v < nv; ++v)
    if (u.used[v] && cons[v] != VertexConstraint::fixed) u.idx[v] = u.count++;
  return u;
}

/// Simplicial LLᵀ (why: GlobalSystem).
SparseCholeskyOptions simplicial_options() {
  SparseCholeskyOptions o;
  o.mode = CholeskyMode::simplicial;
  return o;
}

/// The global step's system, factorised once. Σ_f |N_f x_f − N_f t_f|² is minimised in its
/// incidence form Σ_f Σ_{i∈f} |x_i − c_f − t̃_{f,i}|² with one extra unknown per face, its
/// centroid c_f (t̃ = targets minus their mean): eliminating c_f gives back the original energy
/// exactly, but the matrix couples a vertex only to its faces, not to every vertex of its faces,
/// and its Cholesky factor is 3× sparser (11 K polygons: 0.54 M against 1.62 M non-zeros), which
/// is what the memory-bound back-substitutions pay for every iteration. Unknowns: the free
/// vertices, then the faces (row count + f). Simplicial, not supernodal: the supernodes are tiny
/// and the BLAS per-call overhead made each back-substitution ~4× slower.
struct GlobalSystem {
  /// A fixed vertex's term of a row: value · x_v goes to the right-hand side.
  struct Coupling {
    int row, fixed_vertex;
    double value;
  };
  SparseCholesky llt{simplicial_options()};
  std::vector<Coupling> couplings;
};

/// Boundary fairing: w |x_b − (x_p + x_n)/2|² for each sliding boundary vertex b between its two
/// neighbours p, n along the mesh boundary — keeps the beams along the edge even while the faces
/// behind them move.
void add_boundary_fairing(const Topology& topo, const Unknowns& u,
                          const std::vector<VertexConstraint>& cons, double weight,
                          std::vector<Eigen::Triplet<double>>& trip,
                          std::vector<GlobalSystem::Coupling>& couplings) {
  const std::vector<int>& idx = u.idx;
  const int nv = static_cast<int>(idx.size());
  std::vector<std::vector<int>> along(nv);
  for (int e = 0; e < topo.num_edges(); ++e)
    if (topo.edge_faces[e].size() == 1) {
      along[topo.edges[e][0]].push_back(topo.edges[e][1]);
      along[topo.edges[e][1]].push_back(topo.edges[e][0]);
    }
  for (int b = 0; b < nv; ++b) {
    if (idx[b] < 0 || cons[b] != VertexConstraint::boundary || along[b].size() != 2) continue;
    const std::array<int, 3> v{b, along[b][0], along[b][1]};
    const std::array<double, 3> a{1.0, -0.5, -0.5};
    for (int i = 0; i < 3; ++i) {
      const int r = idx[v[i]];
      if (r < 0) continue;
      for (int j = 0; j < 3; ++j) {
        const double val = weight * a[i] * a[j];
        if (idx[v[j]] >= 0)
          trip.emplace_back(r, idx[v[j]], val);
        else
          couplings.push_back({r, v[j], val});
      }
    }
  }
}

void factorize_global(const PolyMesh& mesh, const Topology& topo, const Unknowns& u,
                      const std::vector<VertexConstraint>& cons, const RegularizeOptions& o,
                      GlobalSystem& sys) {
  const int nfree = u.count, nf = mesh.num_faces(), nrows = nfree + nf;
  std::vector<Eigen::Triplet<double>> trip;
  for (int fi = 0; fi < nf; ++fi) {
    const int cf = nfree + fi;
    for (const int v : mesh.faces[fi]) {
      trip.emplace_back(cf, cf, 1.0);
      const int r = u.idx[v];
      if (r < 0) {
        sys.couplings.push_back({cf, v, -1.0});  // fixed vertex: x_v goes to the right-hand side
        continue;
      }
      trip.emplace_back(r, r, 1.0);
      trip.emplace_back(r, cf, -1.0);
      trip.emplace_back(cf, r, -1.0);
    }
  }
  if (o.boundary_fairing > 0)
    add_boundary_fairing(topo, u, cons, o.boundary_fairing, trip, sys.couplings);
  for (int r = 0; r < nfree; ++r) trip.emplace_back(r, r, o.closeness);
  Eigen::SparseMatrix<double> A(nrows, nrows);
  A.setFromTriplets(trip.begin(), trip.end());
  if (!sys.llt.compute(A).ok)
    throw Error("regularize", "the per-vertex system could not be factorised");
}

/// Per-face targets at X into T, and the energy mean_f Σ_i |x_i − t_i|² / area_f (parallel over
/// the faces, disjoint writes; the sum is serial: deterministic).
double face_targets(const PolyMesh& mesh, const Points& X, const TargetFn& targets,
                    std::vector<std::vector<Vec3>>& T, std::vector<double>& face_energy) {
  const int nf = mesh.num_faces();
  tbb::parallel_for(tbb::blocked_range<int>(0, nf), [&](const tbb::blocked_range<int>& range) {
    std::vector<Vec3> p;  // reused across the chunk's faces
    for (int f = range.begin(); f != range.end(); ++f) {
      const auto& face = mesh.faces[f];
      p.resize(face.size());
      for (std::size_t i = 0; i < face.size(); ++i) p[i] = X.row(face[i]).transpose();
      targets(f, p, T[f]);  // T[f] keeps its capacity from one iteration to the next
      Vec3 a = Vec3::Zero();
      double s = 0, per = 0;
      for (std::size_t i = 0; i < p.size(); ++i) {
        a += p[i].cross(p[(i + 1) % p.size()]);
        per += (p[(i + 1) % p.size()] - p[i]).norm();
        s += (p[i] - T[f][i]).squaredNorm();
      }
      face_energy[f] = s / std::max(0.5 * a.norm(), 1e-12 * per * per);
    }
  });
  double e = 0;
  for (double x : face_energy) e += x;  // serial: deterministic
  return nf > 0 ? e / nf : 0.0;
}

/// The global step: Xnew = X + damping (argmin of the system at targets T − X) for the free
/// vertices. `anchor`: the positions the closeness term pulls towards. B, Y: reused buffers.
void global_step(const PolyMesh& mesh, const Unknowns& u, const GlobalSystem& sys,
                 const std::vector<std::vector<Vec3>>& T, const Points& X, const Points& anchor,
                 const RegularizeOptions& o, Eigen::MatrixX3d& B, Eigen::MatrixX3d& Y,
                 Points& Xnew) {
  const std::vector<int>& idx = u.idx;
  const int nv = mesh.num_vertices(), nf = mesh.num_faces(), nfree = u.count;
  for (int v = 0; v < nv; ++v)
    if (idx[v] >= 0) B.row(idx[v]) = o.closeness * anchor.row(v);
  for (int f = 0; f < nf; ++f) {
    const auto& face = mesh.faces[f];
    Vec3 m = Vec3::Zero();
    for (const Vec3& t : T[f]) m += t;
    m /= static_cast<double>(face.size());
    B.row(nfree + f).setZero();
    for (std::size_t i = 0; i < face.size(); ++i) {
      const Vec3 t = T[f][i] - m;
      B.row(nfree + f) -= t.transpose();  // Σ t̃ = 0 up to rounding
      if (idx[face[i]] >= 0) B.row(idx[face[i]]) += t.transpose();
    }
  }
  for (const GlobalSystem::Coupling& c : sys.couplings)
    B.row(c.row) -= c.value * X.row(c.fixed_vertex);
  Y = sys.llt.solve(B);
  for (int v = 0; v < nv; ++v)
    if (idx[v] >= 0) Xnew.row(v) = X.row(v) + o.damping * (Y.row(idx[v]) - X.row(v));
}

/// The local step (no global solve): each free vertex moves towards the mean of its targets.
/// B, count: reused buffers.
void local_step(const PolyMesh& mesh, const Unknowns& u, const std::vector<std::vector<Vec3>>& T,
                const Points& X, double damping, Eigen::MatrixX3d& B, std::vector<int>& count,
                Points& Xnew) {
  const std::vector<int>& idx = u.idx;
  B.setZero();
  count.assign(u.count, 0);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto& face = mesh.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i)
      if (idx[face[i]] >= 0) {
        B.row(idx[face[i]]) += T[f][i].transpose();
        ++count[idx[face[i]]];
      }
  }
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (idx[v] >= 0) Xnew.row(v) = X.row(v) + damping * (B.row(idx[v]) / count[idx[v]] - X.row(v));
}

/// Energy stall: less than energy_tolerance relative decrease over the last 3 iterations. Not
/// while the input is still the best iterate: the first over-relaxed steps can raise the energy
/// before it falls (the built-in funicular at 300 cells returned its input unchanged).
bool energy_stalled(const RegularizeStats& st, double best_energy, double energy_tolerance) {
  const auto& eh = st.energy_history;
  return eh.size() >= 4 && st.best_iteration > 0 &&
         eh[eh.size() - 4] - best_energy <= energy_tolerance * eh[eh.size() - 4];
}

/// The largest distance of a movable vertex of X to M, over the diagonal (one AABB query per
/// vertex, in parallel).
double max_surface_distance(const Points& X, const Unknowns& u,
                            const std::vector<VertexConstraint>& cons,
                            const SurfaceProjector& proj, double diag) {
  const int nv = static_cast<int>(X.rows());
  std::vector<double> dist(nv, 0.0);
  tbb::parallel_for(0, nv, [&](int v) {
    if (u.used[v] && cons[v] != VertexConstraint::fixed && diag > 0)
      dist[v] = proj.distance(X.row(v).transpose()) / diag;
  });
  double m = 0;
  for (double d : dist) m = std::max(m, d);
  return m;
}

PolyMesh run(const PolyMesh& mesh, const SurfaceProjector& proj, std::vector<VertexConstraint> cons,
             const RegularizeOptions& o, const TargetFn& targets, RegularizeStats* stats) {
  const auto t0 = Clock::now();
  check_input(mesh, cons, o);
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  if (cons.empty()) cons = classify_vertices(mesh);
  const Unknowns u = number_unknowns(mesh, cons);
  const int nfree = u.count;

  const Topology topo = build_topology(mesh);  // boundary edges, faces around each vertex
  PolyMesh out = mesh;
  Points& X = out.V;
  std::vector<int> triangles(nv, -1);  // where on M each vertex's closest point lies
  project(X, cons, u.used, proj, nullptr, &triangles);
  const Points X0 = X;
  const double diag = proj.diagonal();

  const bool global = o.solver == RegularizeOptions::Solver::global;
  GlobalSystem sys;
  const int nrows = nfree + nf;
  if (global && nfree > 0) factorize_global(mesh, topo, u, cons, o, sys);
  RegularizeStats st;
  // Planarity guard (hard projection): the input faces' planarity and the faces
  // around each vertex.
  std::vector<double> raw_planarity;
  const std::vector<std::vector<int>>& vertex_faces = topo.vertex_faces;
  GuardBuffers guard;
  if (o.projection == RegularizeOptions::Projection::hard && o.planarity_guard > 0) {
    raw_planarity.resize(nf);
    for (int f = 0; f < nf; ++f) raw_planarity[f] = face_plane(mesh.V, mesh.faces[f]).planarity;
  }
  st.setup_seconds = seconds_since(t0);

  std::vector<std::vector<Vec3>> T(nf);
  std::vector<double> face_energy(nf, 0.0);
  Eigen::MatrixX3d B(global ? nrows : nfree, 3), Y(global ? nrows : nfree, 3);
  std::vector<int> count;
  Points Xnew, P, best_X = X;
  const bool hard = o.projection == RegularizeOptions::Projection::hard;
  if (!hard && !global) throw Error("projection", "soft projection needs the global solver");
  double best_energy = INFINITY;
  for (int it = 0;; ++it) {
    auto tp = Clock::now();
    const double energy = face_targets(mesh, X, targets, T, face_energy);
    st.targets_seconds += seconds_since(tp);
    st.energy_history.push_back(energy);
    if (energy < best_energy) {
      best_energy = energy;
      best_X = X;
      st.best_iteration = it;
    }
    if (it >= o.max_iterations || st.converged) break;
    if (energy_stalled(st, best_energy, o.energy_tolerance)) {
      st.converged = true;
      break;
    }
    tp = Clock::now();
    Xnew = X;
    const Points* anchor = &X;
    if (!hard) {  // soft: pull towards the closest points of M (or its boundary)
      P = X;
      project(P, cons, u.used, proj);
      anchor = &P;
    }
    if (nfree > 0 && global)
      global_step(mesh, u, sys, T, X, o.anchor_to_input ? X0 : *anchor, o, B, Y, Xnew);
    else if (nfree > 0)
      local_step(mesh, u, T, X, o.damping, B, count, Xnew);
    if (hard && o.planarity_guard > 0)
      guard_planarity(Xnew, mesh, vertex_faces, raw_planarity, cons, o.planarity_guard, guard);
    st.solve_seconds += seconds_since(tp);
    tp = Clock::now();
    if (hard) project(Xnew, cons, u.used, proj, &X, &triangles);  // X is on M: a valid hint
    st.projection_seconds += seconds_since(tp);
    if (!Xnew.allFinite())
      throw Error("regularize", "the iteration diverged (non-finite position)");
    const double move = diag > 0 ? (Xnew - X).rowwise().norm().maxCoeff() / diag : 0.0;
    X.swap(Xnew);
    st.iterations = it + 1;
    st.max_move = move;
    st.move_history.push_back(move);
    if (move < o.tolerance) st.converged = true;  // evaluate this last iterate, then stop
  }
  X = best_X;
  st.energy = best_energy;
  st.max_surface_distance = max_surface_distance(X, u, cons, proj, diag);
  st.seconds = seconds_since(t0);
  if (stats) *stats = std::move(st);
  return out;
}

}  // namespace

namespace {

TargetFn regular_step(const PolyMesh& mesh, const RegularizeOptions& o) {
  std::vector<double> cap(mesh.num_faces(), INFINITY), size(mesh.num_faces(), 0.0);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const FaceFrame fr = face_frame(face_points(mesh, f));
    size[f] = std::sqrt(fr.sigma1 * fr.sigma2);
    if (std::isfinite(o.stretch_growth))
      cap[f] = std::pow(polygon_stretch(face_points(mesh, f)), o.restretch) * o.stretch_growth;
  }
  if (o.size_evening > 0 && mesh.num_faces() > 0) {  // sizes pulled towards their geometric mean
    double log_mean = 0;
    for (double g : size) log_mean += std::log(std::max(g, 1e-300)) / mesh.num_faces();
    for (double& g : size)
      g = std::pow(g, 1 - o.size_evening) * std::exp(o.size_evening * log_mean);
  }
  return [cap = std::move(cap), size = std::move(size), alpha = o.size_anchor](
             int f, const std::vector<Vec3>& p, std::vector<Vec3>& t) {
    const FaceFrame fr = face_frame(p);
    regular_targets(p, fr, cap[f], t);
    if (alpha > 0 && size[f] > 0) {
      const double g = std::sqrt(fr.sigma1 * fr.sigma2);
      if (g > 0) {
        const double k = std::pow(size[f] / g, alpha);
        for (Vec3& x : t) x = fr.centroid + k * (x - fr.centroid);
      }
    }
  };
}

}  // namespace

PolyMesh regularize(const PolyMesh& mesh, const SurfaceProjector& surface,
                    const std::vector<VertexConstraint>& constraints,
                    const RegularizeOptions& options, RegularizeStats* stats) {
  check_input(mesh, constraints, options);
  return run(mesh, surface, constraints, options, regular_step(mesh, options), stats);
}

PolyMesh regularize(const PolyMesh& mesh, const TriMesh& surface,
                    const std::vector<VertexConstraint>& constraints,
                    const RegularizeOptions& options, RegularizeStats* stats) {
  check_input(mesh, constraints, options);
  const auto t0 = Clock::now();
  const SurfaceProjector proj(surface);
  const double build = seconds_since(t0);
  PolyMesh out = run(mesh, proj, constraints, options, regular_step(mesh, options), stats);
  if (stats) {
    stats->seconds += build;
    stats->setup_seconds += build;
  }
  return out;
}

RegularizeOptions planarize_options() {
  RegularizeOptions o;
  o.boundary_fairing = 0.0;
  o.projection = RegularizeOptions::Projection::soft;
  o.closeness = 0.1;
  o.max_iterations = 300;
  o.energy_tolerance = 1e-4;
  return o;
}

PolyMesh planarize(const PolyMesh& mesh, const TriMesh& surface,
                   const std::vector<VertexConstraint>& constraints,
                   const RegularizeOptions& options, RegularizeStats* stats) {
  check_input(mesh, constraints, options);
  const SurfaceProjector proj(surface);
  return run(
      mesh, proj, constraints, options,
      [](int, const std::vector<Vec3>& p, std::vector<Vec3>& t) { t = plane_targets(p); }, stats);
}

}  // namespace gridshell
