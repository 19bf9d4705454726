#pragma once
/// \file metrics.h
/// Shape of the faces of a polygon mesh: the paper's planarity and regularity measures, the
/// stretched-regular-polygon target of a face (the per-face step of the regularization), and
/// beam-length statistics.
///
/// Definitions (per face f with n vertices p_0 … p_{n-1}, centroid c):
/// - **best-fit plane**: through c, normal = the eigenvector of the smallest eigenvalue of the
///   covariance Σ (p_i − c)(p_i − c)ᵀ, oriented like the face's vector area (Newell normal).
/// - **planarity(f)** = mean_i |(p_i − c)·n| / (perimeter(f) / 2). Dimensionless; 0 = planar.
/// - **target(f)**: PCA in the best-fit plane gives axes a1 (largest spread), a2 = n × a1 and
///   standard deviations σ1 ≥ σ2. The face is un-stretched, q_i ↦ (x_i σ̄/σ1, y_i σ̄/σ2) with
///   σ̄ = √(σ1σ2) (area kept); a regular n-gon of the same perimeter as the un-stretched face
///   and the face's orientation is aligned to it by the least-squares rotation (2-D Kabsch;
///   for a regular polygon every cyclic correspondence is a rotation by 2πk/n of the same
///   template, so this optimum is the best over all cyclic correspondences); it is re-stretched
///   by (σ1/σ̄, σ2/σ̄) and placed back at c in the plane (a1, a2). Any affine image of a regular
///   polygon is its own target. σ2 is clamped to ≥ 1e-6 σ1 (a degenerate, collinear face).
/// - **regularity(f)** = Σ_i |p_i − target_i|² / area(f), area = |vector area| (clamped below
///   at 1e-12 · perimeter² so that a degenerate face never divides by zero). Dimensionless.
/// - **edge_length_cv** = population standard deviation / mean of the unique edge lengths.
///
/// Cost: O(Σ face sizes); faces are processed in parallel (TBB), results independent of the
/// thread count.

#include <cmath>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

/// Best-fit plane and principal axes of a set of points (a face).
struct FaceFrame {
  Vec3 centroid = Vec3::Zero();
  Vec3 axis1 = Vec3::UnitX();   ///< in-plane direction of largest spread
  Vec3 axis2 = Vec3::UnitY();   ///< normal × axis1
  Vec3 normal = Vec3::UnitZ();  ///< best-fit plane normal, oriented like the vector area
  double sigma1 = 0;            ///< rms spread along axis1 (m)
  double sigma2 = 0;            ///< rms spread along axis2 (m)
};

/// PCA frame of a polygon given by its vertices in order.
FaceFrame face_frame(const std::vector<Vec3>& polygon);

/// Target positions of the polygon's vertices: the aligned stretched regular polygon above.
/// `max_stretch` (≥ 1) caps the stretch σ1/σ2 given back to the target: a face more stretched
/// than that gets a less stretched target (σ̄ kept). Infinity = the paper's uncapped target.
std::vector<Vec3> regular_targets(const std::vector<Vec3>& polygon, double max_stretch = INFINITY);
/// Same with the polygon's `face_frame` already computed.
std::vector<Vec3> regular_targets(const std::vector<Vec3>& polygon, const FaceFrame& frame,
                                  double max_stretch);
/// Same, written into `out` (resized; no allocation once its capacity suffices).
void regular_targets(const std::vector<Vec3>& polygon, const FaceFrame& frame, double max_stretch,
                     std::vector<Vec3>& out);

/// The stretch σ1/σ2 of a polygon (≥ 1; large for a degenerate face, capped at 1e6).
double polygon_stretch(const std::vector<Vec3>& polygon);

/// Orthogonal projection of the vertices onto the polygon's best-fit plane.
std::vector<Vec3> plane_targets(const std::vector<Vec3>& polygon);

/// Planarity of one polygon (definition above).
double polygon_planarity(const std::vector<Vec3>& polygon);
/// Regularity of one polygon (definition above).
double polygon_regularity(const std::vector<Vec3>& polygon);

struct MeshMetrics {
  double planarity_mean = 0;  ///< mean over faces of planarity(f)
  double planarity_max = 0;
  double regularity_mean = 0;  ///< mean over faces of regularity(f)
  double regularity_max = 0;
  double edge_length_mean = 0;     ///< m
  double edge_length_cv = 0;       ///< std / mean of edge lengths
  double total_length = 0;         ///< m, sum of unique edge lengths (beams)
  std::vector<double> planarity;   ///< per face
  std::vector<double> regularity;  ///< per face
};

/// All metrics of a polygon mesh. Throws Error for a face index out of range or a face with
/// fewer than 3 vertices.
MeshMetrics mesh_metrics(const PolyMesh& mesh);

/// The vertices of face f as points.
std::vector<Vec3> face_points(const PolyMesh& mesh, int f);

}  // namespace gridshell
