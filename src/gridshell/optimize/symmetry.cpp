#include "gridshell/optimize/symmetry.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include <fmt/format.h>

#include "gridshell/core/enum_words.h"
#include "gridshell/core/error.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/optimize/projector.h"

namespace gridshell {

SymmetryReport detect_symmetry(const TriMesh& surface, double tolerance) {
  if (surface.num_vertices() == 0) throw Error("surface", "empty mesh");
  if (!(tolerance >= 0)) throw Error("symmetry tolerance", "must be ≥ 0");
  SymmetryReport r;
  const Vec3 lo = surface.V.colwise().minCoeff().transpose();
  const Vec3 hi = surface.V.colwise().maxCoeff().transpose();
  r.center = 0.5 * (lo + hi);
  r.diagonal = (hi - lo).norm();
  r.x_plane = Plane{r.center, Vec3::UnitX()};
  r.y_plane = Plane{r.center, Vec3::UnitY()};
  const SurfaceProjector proj(surface);
  double dx = 0, dy = 0;
  for (int v = 0; v < surface.num_vertices(); ++v) {
    const Vec3 p = surface.vertex(v);
    dx = std::max(dx, proj.distance(r.x_plane.reflect(p)));
    dy = std::max(dy, proj.distance(r.y_plane.reflect(p)));
  }
  const double d = r.diagonal > 0 ? r.diagonal : 1.0;
  r.x_deviation = dx / d;
  r.y_deviation = dy / d;
  r.x_symmetric = r.x_deviation <= tolerance;
  r.y_symmetric = r.y_deviation <= tolerance;
  return r;
}

namespace {
constexpr EnumWords<Symmetry, 4> kSymmetryWords{{{"none", Symmetry::none},
                                                 {"x", Symmetry::x},
                                                 {"y", Symmetry::y},
                                                 {"xy", Symmetry::xy}}};
}  // namespace

Symmetry parse_symmetry(const std::string& word) {
  if (word.empty()) return Symmetry::none;
  if (const auto s = find_word(word, kSymmetryWords)) return *s;
  throw Error("--symmetry", "expected x, y, xy or none, got '" + word + "'");
}

const char* to_string(Symmetry s) { return word_of(s, kSymmetryWords); }

std::vector<Plane> symmetry_planes(const SymmetryReport& r, Symmetry which) {
  std::vector<Plane> planes;
  auto add = [&](bool symmetric, double deviation, const Plane& plane, const char* name) {
    if (!symmetric)
      throw Error("--symmetry", fmt::format("the surface is not symmetric about the {} plane "
                                            "(deviation {:.3g} of the diagonal)",
                                            name, deviation));
    planes.push_back(plane);
  };
  if (which == Symmetry::x || which == Symmetry::xy)
    add(r.x_symmetric, r.x_deviation, r.x_plane, "x");
  if (which == Symmetry::y || which == Symmetry::xy)
    add(r.y_symmetric, r.y_deviation, r.y_plane, "y");
  return planes;
}

std::vector<Plane> symmetry_planes(const SymmetryReport& r, const std::string& which) {
  return symmetry_planes(r, parse_symmetry(which));
}

namespace {

/// Removes spikes (… x, y, x …) from a cyclic polygon until none is left.
void remove_spikes(std::vector<int>& p) {
  bool changed = true;
  while (changed && p.size() >= 3) {
    changed = false;
    const std::size_t n = p.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (p[i] == p[(i + 2) % n]) {
        // drop y = p[i+1] and the second x = p[i+2]
        const std::size_t a = (i + 1) % n, b = (i + 2) % n;
        std::vector<int> q;
        for (std::size_t j = 0; j < n; ++j)
          if (j != a && j != b) q.push_back(p[j]);
        p.swap(q);
        changed = true;
        break;
      }
    }
  }
}

/// Merges P (walking a→b) and Q (walking b→a) across edge a–b.
std::vector<int> merge_across(const std::vector<int>& P, const std::vector<int>& Q, int a, int b) {
  auto rotate_to = [](const std::vector<int>& f, int first) {
    std::vector<int> r(f);
    auto it = std::find(r.begin(), r.end(), first);
    std::rotate(r.begin(), it, r.end());
    return r;
  };
  std::vector<int> p = rotate_to(P, b);  // b … a
  std::vector<int> q = rotate_to(Q, a);  // a … b
  std::vector<int> out(p);
  for (std::size_t i = 1; i + 1 < q.size(); ++i) out.push_back(q[i]);
  remove_spikes(out);
  return out;
}

struct Stage {
  PolyMesh mesh;
  std::vector<int> src_v, src_f;
  std::vector<std::vector<int>> mirror;  // per plane done so far: per vertex its mirror image
};

/// The sector's vertices against a plane: which faces use them, which lie on the plane (within
/// tol_abs; snapped onto it in V). Throws when the sector lies on both sides.
struct PlaneSides {
  std::vector<char> used, on;
  Points V;
};

PlaneSides split_by_plane(const PolyMesh& S, const Plane& plane, double tol_abs) {
  const int nv = S.num_vertices();
  PlaneSides ps;
  ps.used.assign(nv, 0);
  for (const auto& f : S.faces)
    for (int v : f) ps.used[v] = 1;
  ps.on.assign(nv, 0);
  bool pos = false, neg = false;
  ps.V = S.V;
  for (int v = 0; v < nv; ++v) {
    if (!ps.used[v]) continue;
    const double d = plane.signed_distance(S.vertex(v));
    if (std::abs(d) <= tol_abs) {
      ps.on[v] = 1;
      ps.V.row(v) = plane.project(S.vertex(v)).transpose();
    } else if (d > 0) {
      pos = true;
    } else {
      neg = true;
    }
  }
  if (pos && neg) throw Error("symmetry", "the sector lies on both sides of a symmetry plane");
  return ps;
}

/// Mirror maps of the doubled vertex set: earlier planes carry over to the copy (perpendicular
/// planes commute), and the new plane pairs each vertex with its copy `mir`.
std::vector<std::vector<int>> doubled_mirror_maps(const std::vector<std::vector<int>>& earlier,
                                                  const PlaneSides& ps, const std::vector<int>& mir,
                                                  int next) {
  const int nv = static_cast<int>(ps.used.size());
  std::vector<std::vector<int>> mirror;
  for (const auto& m : earlier) {
    std::vector<int> mm(next, -1);
    for (int v = 0; v < nv; ++v)
      if (ps.used[v]) {
        mm[v] = m[v];
        if (!ps.on[v]) mm[mir[v]] = mir[m[v]];
      }
    mirror.push_back(std::move(mm));
  }
  std::vector<int> mm(next, -1);
  for (int v = 0; v < nv; ++v)
    if (ps.used[v]) {
      mm[v] = mir[v];
      mm[mir[v]] = v;
    }
  mirror.push_back(std::move(mm));
  return mirror;
}

/// Sector edges on the plane must be on the sector's boundary.
void check_plane_edges_on_boundary(const PolyMesh& S, const std::vector<char>& on) {
  std::map<std::pair<int, int>, int> dir;
  for (int f = 0; f < S.num_faces(); ++f) {
    const auto& face = S.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i], b = face[(i + 1) % face.size()];
      if (on[a] && on[b]) dir[{a, b}] = f;
    }
  }
  for (const auto& [e, f] : dir)
    if (dir.count({e.second, e.first}))
      throw Error("symmetry", "a sector edge on the symmetry plane is interior to the sector");
}

/// Merges each sector face touching the plane along an edge with its mirror (faces[nf + f]),
/// which `keep` then drops.
void merge_faces_on_plane(const PolyMesh& S, const std::vector<char>& on,
                          std::vector<std::vector<int>>& faces, std::vector<char>& keep) {
  const int nf = S.num_faces();
  for (int f = 0; f < nf; ++f) {
    std::vector<int> merged = faces[f];
    const std::vector<int>& mirror_face = faces[nf + f];
    bool any = false;
    const auto& face = S.faces[f];
    for (std::size_t i = 0; i < face.size() && !any; ++i) {
      const int a = face[i], b = face[(i + 1) % face.size()];
      if (on[a] && on[b]) {
        merged = merge_across(merged, mirror_face, a, b);
        any = true;
      }
    }
    if (!any) continue;
    // Any on-plane edge still walked both ways means the face touched the plane twice.
    std::map<std::pair<int, int>, int> seen;
    for (std::size_t i = 0; i < merged.size(); ++i)
      seen[{merged[i], merged[(i + 1) % merged.size()]}]++;
    for (const auto& [e, c] : seen)
      if (seen.count({e.second, e.first}) || c > 1)
        throw Error("symmetry", "a cell touches the symmetry plane in two separate places");
    faces[f] = std::move(merged);
    keep[nf + f] = 0;
  }
}

/// Dissolves interior on-plane vertices left with two neighbours (a beam crossing the plane).
void dissolve_plane_crossings(const PlaneSides& ps, PolyMesh& mesh) {
  const Topology topo = build_topology(mesh);
  std::vector<char> drop(mesh.num_vertices(), 0);
  for (int v = 0; v < static_cast<int>(ps.used.size()); ++v)
    if (ps.used[v] && ps.on[v] && !topo.on_boundary[v] && topo.vertex_neighbors[v].size() == 2)
      drop[v] = 1;
  for (auto& f : mesh.faces) {
    std::vector<int> g;
    for (int v : f)
      if (!drop[v]) g.push_back(v);
    f.swap(g);
  }
}

/// Drops the vertices no face references from out.mesh (of `next` vertices), renumbering the
/// faces, the source vertices and the mirror maps.
void compact_vertices(const std::vector<int>& src_v, const std::vector<std::vector<int>>& mirror,
                      int next, Stage& out) {
  std::vector<int> remap(next, -1);
  int k = 0;
  for (const auto& f : out.mesh.faces)
    for (int v : f)
      if (remap[v] < 0) remap[v] = 0;
  for (int v = 0; v < next; ++v)
    if (remap[v] == 0) remap[v] = k++;
  Points X(k, 3);
  out.src_v.assign(k, -1);
  for (int v = 0; v < next; ++v)
    if (remap[v] >= 0) {
      X.row(remap[v]) = out.mesh.V.row(v);
      out.src_v[remap[v]] = src_v[v];
    }
  out.mesh.V = std::move(X);
  for (auto& f : out.mesh.faces)
    for (int& v : f) v = remap[v];
  for (const auto& m : mirror) {
    std::vector<int> mm(k, -1);
    for (int v = 0; v < next; ++v)
      if (remap[v] >= 0) {
        if (m[v] < 0 || remap[m[v]] < 0)
          throw Error("symmetry", "welding was not symmetric (planes must be perpendicular)");
        mm[remap[v]] = remap[m[v]];
      }
    out.mirror.push_back(std::move(mm));
  }
}

Stage reflect_once(const Stage& in, const Plane& plane, double tol_abs) {
  const PolyMesh& S = in.mesh;
  const int nv = S.num_vertices();
  const PlaneSides ps = split_by_plane(S, plane, tol_abs);
  // Vertices: originals, then mirror images of the off-plane ones.
  std::vector<int> mir(nv, -1);
  int next = nv;
  for (int v = 0; v < nv; ++v)
    if (ps.used[v]) mir[v] = ps.on[v] ? v : next++;
  Points W(next, 3);
  W.topRows(nv) = ps.V;
  std::vector<int> src_v(next);
  for (int v = 0; v < nv; ++v) {
    src_v[v] = in.src_v[v];
    if (ps.used[v] && !ps.on[v]) {
      W.row(mir[v]) = plane.reflect(ps.V.row(v).transpose()).transpose();
      src_v[mir[v]] = in.src_v[v];
    }
  }
  const std::vector<std::vector<int>> mirror = doubled_mirror_maps(in.mirror, ps, mir, next);
  // Faces: originals, then their mirror images (reversed, to keep the orientation).
  const int nf = S.num_faces();
  std::vector<std::vector<int>> faces(S.faces);
  std::vector<int> src_f(in.src_f);
  for (int f = 0; f < nf; ++f) {
    std::vector<int> g;
    for (auto it = S.faces[f].rbegin(); it != S.faces[f].rend(); ++it) g.push_back(mir[*it]);
    faces.push_back(std::move(g));
    src_f.push_back(in.src_f[f]);
  }
  check_plane_edges_on_boundary(S, ps.on);
  std::vector<char> keep(faces.size(), 1);
  merge_faces_on_plane(S, ps.on, faces, keep);
  Stage out;
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (keep[f]) {
      out.mesh.faces.push_back(std::move(faces[f]));
      out.src_f.push_back(src_f[f]);
    }
  out.mesh.V = std::move(W);
  dissolve_plane_crossings(ps, out.mesh);
  compact_vertices(src_v, mirror, next, out);
  for (const auto& f : out.mesh.faces)
    if (f.size() < 3) throw Error("symmetry", "welding produced a degenerate face");
  return out;
}

}  // namespace

ReflectedMesh reflect_and_weld(const PolyMesh& sector, const std::vector<Plane>& planes,
                               double weld_tolerance) {
  const int nv = sector.num_vertices();
  for (const auto& f : sector.faces) {
    if (f.size() < 3) throw Error("symmetry", "sector face with fewer than 3 vertices");
    for (int v : f)
      if (v < 0 || v >= nv) throw Error("symmetry", "sector face index out of range");
  }
  if (!sector.V.allFinite()) throw Error("symmetry", "non-finite sector coordinates");
  if (!(weld_tolerance >= 0)) throw Error("weld tolerance", "must be ≥ 0");
  Stage s;
  s.mesh = sector;
  s.src_v.resize(nv);
  for (int v = 0; v < nv; ++v) s.src_v[v] = v;
  s.src_f.resize(sector.num_faces());
  for (int f = 0; f < sector.num_faces(); ++f) s.src_f[f] = f;
  const double tol_abs = weld_tolerance * (nv > 0 ? bbox_diagonal(sector.V) : 0.0);
  for (const Plane& p : planes) {
    const double n = p.normal.norm();
    if (!(n > 0) || !std::isfinite(n)) throw Error("symmetry", "plane with a zero normal");
    Plane q = p;
    q.normal = p.normal / n;
    if (q.axis() < 0) {
      for (int k = 0; k < 3; ++k)  // snap near-axis normals to the axis: exact reflections
        if (std::abs(std::abs(q.normal[k]) - 1.0) < 1e-15)
          q.normal = Vec3::Unit(k) * (q.normal[k] > 0 ? 1 : -1);
    }
    s = reflect_once(s, q, tol_abs);
  }
  ReflectedMesh r;
  r.mesh = std::move(s.mesh);
  r.source_vertex = std::move(s.src_v);
  r.source_face = std::move(s.src_f);
  r.mirror = std::move(s.mirror);
  return r;
}

void enforce_symmetry(PolyMesh& mesh, const std::vector<Plane>& planes,
                      const std::vector<std::vector<int>>& mirror) {
  const int nv = mesh.num_vertices();
  if (mirror.size() != planes.size()) throw Error("symmetry", "one mirror map per plane expected");
  for (std::size_t k = 0; k < planes.size(); ++k) {
    if (static_cast<int>(mirror[k].size()) != nv)
      throw Error("symmetry", "mirror map size differs from the vertex count");
    const Plane& p = planes[k];
    for (int v = 0; v < nv; ++v) {
      const int m = mirror[k][v];
      if (m < 0 || m >= nv) throw Error("symmetry", "mirror map index out of range");
      if (m == v) {
        mesh.V.row(v) = p.project(mesh.vertex(v)).transpose();
      } else if (v < m) {
        const Vec3 a = 0.5 * (mesh.vertex(v) + p.reflect(mesh.vertex(m)));
        mesh.V.row(v) = a.transpose();
        mesh.V.row(m) = p.reflect(a).transpose();
      }
    }
  }
}

}  // namespace gridshell
