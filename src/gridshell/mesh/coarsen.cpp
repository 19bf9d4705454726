#include "gridshell/mesh/coarsen.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Edge_collapse_visitor_base.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_normal_change_filter.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Edge_length_cost.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Edge_length_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <optional>

#include "gridshell/core/error.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/mesh/nearest_triangles.h"
#include "gridshell/mesh/topology.h"

namespace gridshell {

namespace {

namespace SMS = CGAL::Surface_mesh_simplification;
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using VertexIndex = SurfaceMesh::Vertex_index;

/// What a vertex is to the simplification: free inside, on the boundary (may be removed, not
/// moved), or kept (a support, a boundary corner, the end of a supported stretch).
enum Role : std::uint8_t { kInterior = 0, kBoundary = 1, kKept = 2 };

struct Maps {
  SurfaceMesh::Property_map<VertexIndex, std::uint8_t> role;
  SurfaceMesh::Property_map<VertexIndex, int> source;  ///< input vertex, −1 once moved
  SurfaceMesh::Property_map<VertexIndex, std::uint8_t> support;
};

/// The placement of a collapsed edge: the midpoint between two interior vertices, else the
/// vertex of higher role (a kept or boundary vertex never moves); none (not collapsible) for two
/// kept vertices, and for an edge between two boundary vertices that is not itself a boundary
/// edge (it would pinch the surface). Along the boundary, of two boundary vertices the one kept
/// is the one whose removal makes the shorter boundary edge (always keeping the same end would
/// let the survivor slide along the boundary, swallowing one vertex after the other).
class KeepingPlacement {
 public:
  explicit KeepingPlacement(const Maps& maps) : maps_(maps) {}
  template <typename Profile>
  boost::optional<typename Profile::Point> operator()(const Profile& p) const {
    const int r0 = maps_.role[p.v0()], r1 = maps_.role[p.v1()];
    if (r0 == kInterior && r1 == kInterior) return CGAL::midpoint(p.p0(), p.p1());
    if (r0 == kKept && r1 == kKept) return boost::none;
    const bool border_edge = p.is_v0_v1_a_border() || p.is_v1_v0_a_border();
    if (r0 != kInterior && r1 != kInterior && !border_edge) return boost::none;
    if (r0 != r1 || !border_edge) return r1 > r0 ? p.p1() : p.p0();
    return keep_v0(p) ? p.p0() : p.p1();
  }

 private:
  /// For a boundary edge v0–v1 between the boundary vertices w0 and w1 (w0 – v0 – v1 – w1):
  /// whether keeping v0 (new edge v0–w1) makes a shorter edge than keeping v1 (new edge w0–v1).
  template <typename Profile>
  static bool keep_v0(const Profile& p) {
    const auto& tm = p.surface_mesh();
    VertexIndex w0, w1;
    if (p.is_v0_v1_a_border()) {  // the border cycle runs w0 → v0 → v1 → w1
      w0 = CGAL::source(CGAL::prev(p.v0_v1(), tm), tm);
      w1 = CGAL::target(CGAL::next(p.v0_v1(), tm), tm);
    } else {  // it runs w1 → v1 → v0 → w0
      w0 = CGAL::target(CGAL::next(p.v1_v0(), tm), tm);
      w1 = CGAL::source(CGAL::prev(p.v1_v0(), tm), tm);
    }
    return CGAL::squared_distance(p.p0(), tm.point(w1)) <=
           CGAL::squared_distance(tm.point(w0), p.p1());
  }

  Maps maps_;
};

/// Carries the roles over a collapse: the surviving vertex takes the flags of the endpoint whose
/// position it took (interior midpoints: moved, no source).
struct KeepingVisitor : SMS::Edge_collapse_visitor_base<SurfaceMesh> {
  explicit KeepingVisitor(const Maps& maps) : maps(maps) {}
  template <typename Profile>
  void OnCollapsing(const Profile& p, const boost::optional<Point>& placement) {
    from = VertexIndex();  // null: a midpoint
    if (placement && *placement == p.p0())
      from = p.v0();
    else if (placement && *placement == p.p1())
      from = p.v1();
    if (from != VertexIndex() && maps.role[p.v0()] == kInterior && maps.role[p.v1()] == kInterior)
      from = VertexIndex();  // two interior vertices always meet at their midpoint
  }
  template <typename Profile>
  void OnCollapsed(const Profile& /*p*/, VertexIndex v) {
    if (from == VertexIndex()) {
      maps.role[v] = kInterior, maps.source[v] = -1, maps.support[v] = 0;
      return;
    }
    const std::uint8_t role = maps.role[from], support = maps.support[from];
    const int source = maps.source[from];
    maps.role[v] = role, maps.source[v] = source, maps.support[v] = support;
  }
  Maps maps;
  VertexIndex from;  ///< the endpoint whose position the collapse keeps (null: a midpoint)
};

/// Per input vertex: its role (see Role).
std::vector<std::uint8_t> vertex_roles(const Surface& s, double corner_angle_deg) {
  const int nv = s.mesh.num_vertices();
  // The boundary loops: from the triangle adjacency (linear time, no per-vertex lists; the same
  // loops as Topology's), or from the general topology where the adjacency refuses the mesh.
  std::vector<std::vector<int>> loops;
  std::vector<char> on_boundary(nv, 0);
  try {
    loops = build_triangle_adjacency(s.mesh.F, nv).boundary_loops;
    for (const auto& loop : loops)
      for (int v : loop) on_boundary[v] = 1;
  } catch (const Error&) {
    Topology topo = build_topology(s.mesh);
    loops = std::move(topo.boundary_loops);
    on_boundary = std::move(topo.on_boundary);
  }
  std::vector<char> support(nv, 0);
  for (int v : s.supports) support[v] = 1;
  const std::vector<char> corner = boundary_corners(s.mesh.V, loops, corner_angle_deg);
  std::vector<std::uint8_t> role(nv, kInterior);
  for (int v = 0; v < nv; ++v) {
    if (on_boundary[v]) role[v] = kBoundary;
    if (corner[v] || (support[v] && !on_boundary[v])) role[v] = kKept;
  }
  for (const auto& loop : loops) {  // where the supported stretches end
    const std::size_t n = loop.size();
    for (std::size_t k = 0; k < n; ++k) {
      const int v = loop[k], prev = loop[(k + n - 1) % n], next = loop[(k + 1) % n];
      if (support[v] && (!support[prev] || !support[next])) role[v] = kKept;
    }
  }
  return role;
}

/// Moves each interior vertex of `mesh` onto the closest point of the input (`closest`); the
/// queries run in parallel, each writing its own row.
void project_interior(TriMesh& mesh, const std::vector<int>& source,
                      const NearestTriangles& closest) {
  if (closest.empty()) return;
  tbb::parallel_for(tbb::blocked_range<int>(0, mesh.num_vertices(), 256),
                    [&](const tbb::blocked_range<int>& range) {
                      for (int v = range.begin(); v < range.end(); ++v)
                        if (source[v] < 0)
                          mesh.V.row(v) = closest.closest_point(mesh.vertex(v)).transpose();
                    });
}

CoarseSurface unchanged(const Surface& surface) {
  CoarseSurface out{surface, std::vector<int>(surface.mesh.num_vertices()), {}};
  std::iota(out.source_vertex.begin(), out.source_vertex.end(), 0);
  return out;
}

}  // namespace

CoarseSurface coarsen_surface(const Surface& surface, const CoarsenOptions& options) {
  if (!(options.edge_length > 0)) return unchanged(surface);
  const TriMesh& in = surface.mesh;
  SurfaceMesh sm;
  // Room for every element up front (edges: at most 3 per face, fewer when shared).
  sm.reserve(in.num_vertices(), 3 * in.num_faces() / 2 + in.num_vertices(), in.num_faces());
  std::vector<VertexIndex> vertex(in.num_vertices());
  for (int v = 0; v < in.num_vertices(); ++v)
    vertex[v] = sm.add_vertex(Point(in.V(v, 0), in.V(v, 1), in.V(v, 2)));
  for (int f = 0; f < in.num_faces(); ++f)
    if (sm.add_face(vertex[in.F(f, 0)], vertex[in.F(f, 1)], vertex[in.F(f, 2)]) ==
        SurfaceMesh::null_face())
      return unchanged(surface);  // not an oriented manifold: leave it to the full resolution
  Maps maps{sm.add_property_map<VertexIndex, std::uint8_t>("v:role", kInterior).first,
            sm.add_property_map<VertexIndex, int>("v:source", -1).first,
            sm.add_property_map<VertexIndex, std::uint8_t>("v:support", 0).first};
  // The input's closest-point tree (for the copy's interior vertices at the end) is built beside
  // the collapse when the pool has a free worker. In an objective search the other worker is
  // blocked waiting for this very coarsening (the design cache warmed beside it) and the tree is
  // built after the collapse (1.4 s at 2 M triangles). A thread of its own avoided that but kept
  // the tree's freed memory in that thread's allocator arena: +0.4 GB peak at 2 M triangles
  // (docs/performance.md, "The coarsening's own serial steps").
  std::optional<NearestTriangles> closest;
  tbb::task_group tree;
  tree.run([&] { closest.emplace(in); });
  const std::vector<std::uint8_t> role = vertex_roles(surface, options.corner_angle_deg);
  for (int v = 0; v < in.num_vertices(); ++v)
    maps.role[vertex[v]] = role[v], maps.source[vertex[v]] = v;
  for (int v : surface.supports) maps.support[vertex[v]] = 1;

  SMS::Edge_length_stop_predicate<double> stop(options.edge_length);
  SMS::edge_collapse(sm, stop,
                     CGAL::parameters::get_cost(SMS::Edge_length_cost<SurfaceMesh>())
                         .get_placement(KeepingPlacement(maps))
                         .filter(SMS::Bounded_normal_change_filter<>())
                         .visitor(KeepingVisitor(maps)));
  sm.collect_garbage();

  CoarseSurface out;
  TriMesh& mesh = out.surface.mesh;
  mesh.V.resize(sm.number_of_vertices(), 3);
  out.source_vertex.assign(sm.number_of_vertices(), -1);
  for (VertexIndex v : sm.vertices()) {
    const int i = static_cast<int>(v);
    const Point& p = sm.point(v);
    mesh.V.row(i) << p.x(), p.y(), p.z();
    out.source_vertex[i] = maps.source[v];
    if (maps.support[v]) out.surface.supports.push_back(i);
  }
  mesh.F.resize(sm.number_of_faces(), 3);
  for (SurfaceMesh::Face_index f : sm.faces()) {
    int k = 0;
    for (VertexIndex v : CGAL::vertices_around_face(sm.halfedge(f), sm))
      mesh.F(static_cast<int>(f), k++) = static_cast<int>(v);
  }
  std::sort(out.surface.supports.begin(), out.surface.supports.end());
  tree.wait();
  project_interior(mesh, out.source_vertex, *closest);
  if (!closest->empty()) out.nearest_input_face = closest->nearest_faces(mesh);
  return out;
}

}  // namespace gridshell
