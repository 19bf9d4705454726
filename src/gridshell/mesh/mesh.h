#pragma once
/// \file mesh.h
/// The mesh values that flow between the stages. Plain Eigen arrays: vertices as an n×3 matrix
/// of doubles (metres), faces as index lists (0-based).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace gridshell {

using Vec3 = Eigen::Vector3d;
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// A triangle mesh: the input surface M, the support mesh, the deformed surface M'.
struct TriMesh {
  Points V;     ///< vertex positions
  Triangles F;  ///< triangles, counter-clockwise seen from the outside (the normal side)

  int num_vertices() const { return static_cast<int>(V.rows()); }
  int num_faces() const { return static_cast<int>(F.rows()); }
  Vec3 vertex(int v) const { return V.row(v).transpose(); }
};

/// A polygon mesh: the grid-shell. Faces are panels, edges are beams, vertices are joints.
struct PolyMesh {
  Points V;
  std::vector<std::vector<int>> faces;

  int num_vertices() const { return static_cast<int>(V.rows()); }
  int num_faces() const { return static_cast<int>(faces.size()); }
  Vec3 vertex(int v) const { return V.row(v).transpose(); }
};

/// A surface to build on: the triangle mesh and the vertices that are supported (sorted ids).
struct Surface {
  TriMesh mesh;
  std::vector<int> supports;
};

/// Triangulates every polygon: a convex one (every corner turning the same way about its Newell
/// normal, by a degree or more) as a fan from its first vertex; a concave one by CGAL's hole
/// filling of its outline (the constrained Delaunay triangulation in its plane when nearly planar,
/// else a minimum-weight search), whose triangles stay inside it where a fan would fold one over
/// the others. Triangles stay as they are.
TriMesh triangulate(const PolyMesh& poly);

/// The polygon mesh whose faces are the triangles of `tri`.
PolyMesh to_poly(const TriMesh& tri);

/// The rows of a vertex array: x[i] is row i.
Points to_points(const std::vector<Vec3>& x);

}  // namespace gridshell
