#include "gridshell/grids/quad_aniso_internal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "gridshell/core/error.h"
#include "gridshell/optimize/projector.h"

namespace gridshell::quad_aniso_internal {

namespace {

/// Step 3a: edges within one lattice point are collapsed, edges across one lattice step kept;
/// then joints closer than 0.3 h are merged once more (one lattice point split in two where the
/// lattices of a seam disagree slightly).
LatticeJoints collapse_to_joints(const std::vector<Vec3>& pos, const Topology& topo,
                                 const CrossField& cf, const std::vector<Vec3>& org,
                                 const std::vector<double>& scale, double h) {
  const int nv = static_cast<int>(pos.size());
  const std::vector<Vec3>&n = cf.n, &q = cf.q, &t = cf.t;
  DisjointSets sets(nv);
  LatticeJoints J;
  for (const auto& e : topo.edges) {
    const int i = e[0], j = e[1];
    const Vec3 qj = match_cross(q[j], n[j], q[i]), tj = n[j].cross(qj);
    const double hi = h * scale[i], hj = h * scale[j];
    const auto [a, b] = compat_position(pos[i], q[i], t[i], org[i], hi, pos[j], qj, tj, org[j], hj);
    if ((a - b).norm() > 0.25 * (hi + hj)) continue;  // the two lattices disagree here
    const int di0 = static_cast<int>(std::lround((a - org[i]).dot(q[i]) / hi));
    const int di1 = static_cast<int>(std::lround((a - org[i]).dot(t[i]) / hi));
    const int dj0 = static_cast<int>(std::lround((b - org[j]).dot(qj) / hj));
    const int dj1 = static_cast<int>(std::lround((b - org[j]).dot(tj) / hj));
    const int d0 = di0 - dj0, d1 = di1 - dj1;
    if (d0 == 0 && d1 == 0)
      sets.unite(i, j);
    else if (std::abs(d0) + std::abs(d1) == 1)
      J.steps.push_back({i, j});
  }
  J.cluster.assign(nv, -1);
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1)
      for (const auto& s : J.steps)
        if ((J.pos[J.cluster[s[0]]] - J.pos[J.cluster[s[1]]]).norm() < 0.3 * h)
          sets.unite(s[0], s[1]);
    std::fill(J.cluster.begin(), J.cluster.end(), -1);
    int& nc = J.count;
    nc = 0;
    for (int v = 0; v < nv; ++v) {
      const int r = sets.find(v);
      if (J.cluster[r] < 0) J.cluster[r] = nc++;
      J.cluster[v] = J.cluster[r];
    }
    J.pos.assign(nc, Vec3::Zero());
    J.normal.assign(nc, Vec3::Zero());
    J.vertices.assign(nc, 0);
    for (int v = 0; v < nv; ++v) {
      J.pos[J.cluster[v]] += org[v];
      J.normal[J.cluster[v]] += n[v];
      ++J.vertices[J.cluster[v]];
    }
    for (int c = 0; c < nc; ++c) {
      J.pos[c] /= J.vertices[c];
      J.normal[c] = J.normal[c].norm() > 0 ? Vec3(J.normal[c].normalized()) : Vec3(Vec3::UnitZ());
    }
  }
  return J;
}

/// Step 3b: each joint's beams (dangling ones pruned), ordered counter-clockwise about its
/// normal, starting from the cross's axis q at the joint's first vertex.
std::vector<std::vector<int>> joint_rings(const LatticeJoints& J, const CrossField& cf) {
  const int nc = J.count;
  std::vector<int> first(nc, -1);
  for (int v = 0; v < static_cast<int>(J.cluster.size()); ++v)
    if (first[J.cluster[v]] < 0) first[J.cluster[v]] = v;
  std::vector<std::set<int>> adj(nc);
  for (const auto& s : J.steps) {
    const int a = J.cluster[s[0]], b = J.cluster[s[1]];
    if (a != b) adj[a].insert(b), adj[b].insert(a);
  }
  std::deque<int> prune;
  for (int c = 0; c < nc; ++c)
    if (adj[c].size() == 1) prune.push_back(c);
  while (!prune.empty()) {
    const int c = prune.front();
    prune.pop_front();
    if (adj[c].size() != 1) continue;
    const int other = *adj[c].begin();
    adj[c].clear();
    adj[other].erase(c);
    if (adj[other].size() == 1) prune.push_back(other);
  }
  std::vector<std::vector<int>> ring(nc);
  for (int c = 0; c < nc; ++c) {
    const Vec3 n = J.normal[c], q = cf.q[first[c]];
    const Vec3 along = q - q.dot(n) * n;
    const Vec3 r = along.norm() > 1e-12 ? Vec3(along.normalized()) : any_perpendicular(n);
    const Vec3 s = n.cross(r);
    std::vector<std::pair<double, int>> by_angle;
    for (int b : adj[c]) {
      const Vec3 d = J.pos[b] - J.pos[c];
      by_angle.emplace_back(std::atan2(d.dot(s), d.dot(r)), b);
    }
    std::sort(by_angle.begin(), by_angle.end());
    for (const auto& [angle, b] : by_angle) ring[c].push_back(b);
  }
  return ring;
}

/// Step 3c: faces traced by turning at each joint to the previous beam of its ring; kept when
/// closed, not too many sides, no joint twice and facing along the joints' normals.
std::vector<std::vector<int>> trace_faces(const std::vector<std::vector<int>>& ring,
                                          const LatticeJoints& J, int max_face_sides) {
  std::map<std::pair<int, int>, char> used;
  std::vector<std::vector<int>> faces;
  for (int a0 = 0; a0 < J.count; ++a0) {
    for (int b0 : ring[a0]) {
      if (used.count({a0, b0})) continue;
      std::vector<int> face{a0};
      int a = a0, b = b0;
      bool closed = false;
      for (int step = 0; step < 4 * max_face_sides; ++step) {
        used[{a, b}] = 1;
        if (b == a0) {
          closed = true;
          break;
        }
        face.push_back(b);
        const auto& rb = ring[b];
        const int k = static_cast<int>(std::find(rb.begin(), rb.end(), a) - rb.begin());
        const int deg = static_cast<int>(rb.size());
        const int next = rb[(k - 1 + deg) % deg];
        a = b, b = next;
      }
      if (!closed || static_cast<int>(face.size()) > max_face_sides || face.size() < 3) continue;
      std::vector<int> sorted = face;
      std::sort(sorted.begin(), sorted.end());
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) continue;
      Vec3 area = Vec3::Zero(), normal = Vec3::Zero();
      for (size_t k = 0; k < face.size(); ++k) {
        area += J.pos[face[k]].cross(J.pos[face[(k + 1) % face.size()]]);
        normal += J.normal[face[k]];
      }
      if (area.dot(normal) <= 0) continue;  // the outer boundary, or a folded face
      faces.push_back(std::move(face));
    }
  }
  return faces;
}

/// The joints `J` of M′ carried to M (not yet projected on it): each joint's position is its
/// vertices' lattice points through the affine map of the incident triangle that contains each
/// best, averaged; its normal is the mean of its vertices' normals on M (`rest_normal`).
LatticeJoints joints_on_rest(const TriMesh& rest, const TriMesh& def, const Topology& topo,
                             const std::vector<Vec3>& org, const LatticeJoints& J,
                             const std::vector<Vec3>& rest_normal) {
  const int nv = def.num_vertices(), nc = J.count;
  LatticeJoints on_m = J;
  std::vector<Vec3>&cm = on_m.pos, &normal = on_m.normal;
  std::fill(cm.begin(), cm.end(), Vec3::Zero());
  std::fill(normal.begin(), normal.end(), Vec3::Zero());
  for (int v = 0; v < nv; ++v) {
    double best = -std::numeric_limits<double>::infinity();
    Vec3 mapped = rest.vertex(v);
    for (int f : topo.vertex_faces[v]) {
      const Vec3 a = def.vertex(def.F(f, 0)), b = def.vertex(def.F(f, 1)),
                 c = def.vertex(def.F(f, 2));
      const Vec3 e1 = b - a, e2 = c - a, d = org[v] - a;
      Eigen::Matrix2d G;
      G << e1.dot(e1), e1.dot(e2), e1.dot(e2), e2.dot(e2);
      const Eigen::Vector2d st = G.ldlt().solve(Eigen::Vector2d(e1.dot(d), e2.dot(d)));
      const double score = std::min({1 - st(0) - st(1), st(0), st(1)});
      if (!std::isfinite(score) || score <= best) continue;
      best = score;
      const Vec3 ra = rest.vertex(rest.F(f, 0));
      mapped =
          ra + st(0) * (rest.vertex(rest.F(f, 1)) - ra) + st(1) * (rest.vertex(rest.F(f, 2)) - ra);
    }
    cm[J.cluster[v]] += mapped;
    normal[J.cluster[v]] += rest_normal[v];
  }
  for (int c = 0; c < nc; ++c) {
    cm[c] /= J.vertices[c];
    normal[c] = normal[c].norm() > 0 ? Vec3(normal[c].normalized()) : J.normal[c];
  }
  return on_m;
}

/// The total area of polygons `faces` with corners `pos`.
double faces_area(const std::vector<std::vector<int>>& faces, const std::vector<Vec3>& pos) {
  double total = 0;
  for (const auto& f : faces) total += polygon_area(pos, f);
  return total;
}

/// Step 4: the joints carried to M (`joints_on_rest`) projected on it; joints renumbered in the
/// order the faces use them.
PolyMesh joints_on_surface(const TriMesh& rest, const std::vector<Vec3>& cm,
                           std::vector<std::vector<int>> faces) {
  const int nc = static_cast<int>(cm.size());
  std::vector<int> index(nc, -1);
  PolyMesh out;
  int count = 0;
  for (auto& f : faces)
    for (int& c : f) {
      if (index[c] < 0) index[c] = count++;
      c = index[c];
    }
  out.V.resize(count, 3);
  const SurfaceProjector proj(rest);
  for (int c = 0; c < nc; ++c)
    if (index[c] >= 0) out.V.row(index[c]) = proj.closest_point(cm[c]).transpose();
  out.faces = std::move(faces);
  return out;
}

}  // namespace

PolyMesh quad_mesh_from_frames(const MetricFrames& m, const TriMesh& rest, const TriMesh& def,
                               double h, const QuadAnisoOptions& o) {
  if (!(h > 0) || !std::isfinite(h)) throw Error("quad-aniso", "spacing must be positive");
  const CrossField& cf = m.cfs[0];
  const std::vector<Vec3> org = position_field(m.levels, m.cfs, m.matched, m.scale, h, o);
  const LatticeJoints joints = collapse_to_joints(m.pos, m.topo, cf, org, m.scale[0], h);
  // Faces are traced twice: with the beams ordered about each joint on M′, and on M, and the
  // tracing whose faces cover more of M is kept (M′'s on a tie). M′ is where the lattice is
  // square, but it can be crushed where the metric changes fast (the rim of a lobe of large cells
  // next to small ones): there neighbours' angles about a joint on M′ are not their order on the
  // surface, faces are walked across cells, and a whole lobe was left without faces. On M, the
  // roof, the order is right there; near M′'s boundary a joint's point on M is extrapolated and
  // its order can be the worse one.
  const LatticeJoints on_m = joints_on_rest(rest, def, m.topo, org, joints, m.rest_normal);
  std::vector<std::vector<int>> faces =
      trace_faces(joint_rings(joints, cf), joints, o.max_face_sides);
  std::vector<std::vector<int>> faces_m =
      trace_faces(joint_rings(on_m, cf), on_m, o.max_face_sides);
  if (faces_area(faces_m, on_m.pos) > faces_area(faces, on_m.pos) * (1 + 1e-9))
    faces = std::move(faces_m);
  if (faces.empty()) throw Error("quad-aniso", "extraction found no faces (spacing too large?)");
  pair_odd_faces(faces, joints.pos, joints.normal, h);
  merge_triangle_pairs(faces, joints.pos);
  absorb_lone_triangles(faces, joints.pos);
  return joints_on_surface(rest, on_m.pos, std::move(faces));
}

}  // namespace gridshell::quad_aniso_internal

namespace gridshell {

PolyMesh quad_mesh_on_metric(const TriMesh& rest, const TriMesh& def, const Field& field, double h,
                             const QuadAnisoOptions& o) {
  if (!(h > 0) || !std::isfinite(h)) throw Error("quad-aniso", "spacing must be positive");
  return quad_aniso_internal::quad_mesh_from_frames(
      quad_aniso_internal::metric_frames(rest, def, field, h, o), rest, def, h, o);
}

}  // namespace gridshell
