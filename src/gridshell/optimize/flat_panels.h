#pragma once
/// \file flat_panels.h
/// Flat glass: every panel of a grid-shell exactly planar, by construction (`--panels flat`).
///
/// Method (planar hexagonal meshes by plane intersection: Wang, Liu et al. 2008; Li, Liu, Wang,
/// "Planar hexagonal meshing for architecture", IEEE TVCG 2015). The unknowns are one plane per
/// panel, n_f·x = d_f with |n_f| = 1; every joint is the intersection of exactly three planes, so
/// every panel is flat to round-off whatever the planes are. Which three planes:
/// - interior joint of valence 3: its three panels' planes;
/// - interior joint of valence k ≥ 4 (faces f1 … fk around it): split into k − 2 joints
///   u_i = f1 ∩ f(i+1) ∩ f(i+2), joined by short beams along f1 (a fan from f1);
/// - boundary joint with two panels: the two planes and its boundary plane — the plane through
///   the design joint that holds the boundary curve's tangent t and the surface normal n_s
///   (normal n_s × t; it cuts the panels' common edge at right angles); with one panel (a
///   corner): the panel's plane, the boundary plane and the plane through the joint normal to t,
///   so the joint stays on the surface normal through its design position; with k ≥ 3 panels:
///   split into k − 1 joints u_i = boundary plane ∩ f_i ∩ f(i+1), joined along the boundary, their
///   targets in order along it (`split_spacing`).
/// - supports: on the boundary, as boundary joints (on their boundary plane, near their design
///   position like any joint); interior supports (columns) held at their design position by a
///   strong spring (`support_weight`); a split support stays a support at its first part.
/// The planes minimise, by Levenberg–Marquardt (Gauss–Newton steps, exact Jacobians of the
/// 3-plane intersection, sparse Cholesky by CHOLMOD; tangent-space updates of each normal):
///   Σ_j w_s (n_c·(x_j − c_j))²/h² + w_0 |x_j − x0_j|²/h² + w_fair Σ_f |n_f − mean_g n_g|²
///   + w_b Σ_j max(0, log(τ/|det_j|))²
///   + w_beam Σ_beams max(0, ℓ_min − u·(x_b − x_a))²/h² + w_in Σ_j Σ_sides max(0, −σ_k(x_j))²/h²
/// (x_j the joints, c_j their closest points on the input surface M and n_c its normal there,
/// x0_j the design's joints, h the mean beam length, det_j = det(n_1, n_2, n_3) of a joint's
/// planes, u a beam's design direction and ℓ_min half its design length, σ_k the signed distance
/// to side k of the triangle of the joint's three panels' centres): closeness to M, closeness to
/// the design (the cells' shape and size), fair planes (a Laplacian of the normals: constant
/// curvature costs nothing), a barrier against nearly parallel planes (joints running away),
/// beams that neither collapse nor turn over, joints inside their cells' triangle (never stricter
/// than the design joint's own place). A step is refused when a joint's planes become nearly
/// parallel (|det| < min_det), a panel that was simple self-intersects or a beam falls below the
/// post-check's shortest.
/// Beam flips: a beam the planes still shrink below the post-check's shortest is turned over (T1:
/// a = A∩B∩C, b = A∩B∩D become A∩C∩D, B∩C∩D; at the boundary b = Bnd∩A∩C, i = A∩C∩D become
/// Bnd∩A∩D, Bnd∩C∩D, `boundary_flips`) and the steps run again (`flip_rounds`).
/// Restarts: a result that fails the post-check is optimised again from the start with the joints
/// of the failing panels (self-intersecting, a beam too short, a joint too far off) and of their
/// neighbours held closer to their design positions, which pass every check (`restarts`,
/// `restart_stiffness`). Retry: then the same with each of `retry_surface_weights`; the first
/// result that passes the same post-check is kept.
/// Last resort: when every attempt fails, the failing panels of the attempt that needs the fewest
/// give up their planes and are glazed as flat triangles (`max_triangulated`); the rest stay
/// flat cells (flat_panels_internal.h, split_failing_panels).
/// Start: nearly planar panels by a ShapeUp-like alternation with a rising planarity weight
/// (best-fit plane per panel, then each joint nearest to its three planes, the surface and its
/// design position); their planes start the Levenberg–Marquardt steps. When two of a joint's
/// start planes are parallel (a flat part), the alternation starts again from the design joints
/// lifted by a shallow paraboloid (`lift`): the tangent planes of a paraboloid meet over the
/// circumcentres of neighbouring cells (a power diagram), so joint positions are well defined.
/// After the last step the joints are computed once more and checked: every corner within
/// `max_out_of_plane` of its panel's plane and of its best-fit plane, every joint finite, no
/// panel self-intersecting, no joint farther from the surface than `max_surface_distance` × its
/// span, no beam collapsed (`min_beam_ratio`); otherwise FlatPanelsFailed (never a silent pass).
///
/// Cost: O(joints) per iteration plus one sparse Cholesky of 3 × panels unknowns (analysed once
/// per round); up to 1 + flip_rounds rounds of max_iterations steps per attempt, (1 + restarts) ×
/// (1 + retries) attempts (bench/flat_panels_bench.cpp: Botanic at about 1200 panels).

#include <array>
#include <string>
#include <vector>

#include "gridshell/core/error.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell {

class SurfaceProjector;

/// How the panels of a design are made.
enum class PanelMode {
  free,  ///< joints on the surface, panels as they come (today's grid-shells; the paper)
  flat,  ///< every panel exactly planar (flat_panels below)
};
PanelMode parse_panel_mode(const std::string& word);
const char* to_string(PanelMode mode);

/// The intersection x of the planes n_i·x = d_i (i = 0, 1, 2) and det(n_0, n_1, n_2). Returns
/// false (x untouched) when |det| ≤ min_det (nearly parallel planes).
/// `jacobian` (optional, 3 × 12): ∂x/∂(n_0, d_0, n_1, d_1, n_2, d_2). From A x = d with the rows
/// of A the normals: ∂x/∂d_i = A⁻¹ e_i = c_i, ∂x/∂n_i = −c_i xᵀ.
bool intersect_planes(const Vec3 n[3], const double d[3], Vec3& x, double& det,
                      double min_det = 1e-14, Eigen::Matrix<double, 3, 12>* jacobian = nullptr);

/// A triangulation of the polygon `p` (3-D corners, in order) whose diagonals run inside it
/// (seen along its best-fit plane's normal, as panel_shape sees it) and are at least `min_side`
/// long, with the largest smallest corner angle (Klincsek's O(n³) dynamic programme); corner
/// indices, in the polygon's orientation. A polygon folded over itself as seen is triangulated
/// in space, every triangle turning the way its best-fit normal does. Empty when there is none
/// (every triangulation needs a shorter diagonal or a triangle turned over).
std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<Vec3>& p, double min_side);

struct FlatPanelOptions {
  /// w_s: joint to the input surface (normal distance). Measured on the 11 surfaces of
  /// docs/panels.md: 10 passes the post-check on 6 at the first attempt, 5 and 40 on 4.
  double surface_weight = 10;
  /// When the result fails the post-check, the optimisation runs again from the start with each
  /// of these surface weights in turn and the first result that passes is kept (the check is the
  /// same). Measured: 20 adds Neumünster (docs/panels.md); each retry costs one more stage.
  std::vector<double> retry_surface_weights = {20};
  /// Restarts per surface weight of an attempt that fails the post-check: the joints of the
  /// failing panels (self-intersecting, with a beam shorter than allowed or a joint too far from
  /// the surface) and of their neighbouring panels get `restart_stiffness` times their design
  /// weight (cumulative), and the optimisation runs again from the start. Measured
  /// (docs/panels.md): 10 of the 11 surfaces pass instead of 7; holding only the failing panels'
  /// own joints, 9; factor 5 passes as many as 10.
  int restarts = 5;
  double restart_stiffness = 10;
  /// w_0: joint to the design's joint. Measured (docs/panels.md): 0.1 lets boundary cells slide
  /// their inner joints past the boundary (self-intersecting panels on all six shared surfaces);
  /// 1 keeps the cells' shape.
  double design_weight = 1.0;
  double support_weight = 100;   ///< interior supports (columns) to their design position
  double fairness_weight = 0.01; ///< w_fair: Laplacian of the normals
  double barrier_weight = 1e-4;  ///< w_b
  double barrier_det = 1e-5;     ///< τ: the barrier acts below this |det|
  double min_det = 1e-10;        ///< hard: no step makes a joint's |det| smaller
  double lift = 0.05;            ///< κ × bbox diagonal: the start's lift (lifted_targets)
  /// w_beam: hinge on each beam's signed length (along its design direction) below `beam_keep` ×
  /// its design length; keeps beams from collapsing or turning over (a T1 flip).
  double beam_weight = 10;
  double beam_keep = 0.5;
  /// A boundary joint of k ≥ 3 panels is split into k − 1 joints along the boundary; their
  /// targets start this many × the design's shortest beam apart, in order along the boundary
  /// (from one point they would leave a beam the post-check counts as collapsed, or cross).
  double split_spacing = 1.0;
  /// w_in: hinge keeping each joint of three panels inside the triangle of its panels' centres
  /// (never stricter than the design joint's own place).
  double inside_weight = 10;
  int max_iterations = 60;
  /// Rounds of beam flips (T1) where the planes shrank a beam below the post-check's shortest,
  /// each followed by the Levenberg–Marquardt steps again (0: none).
  int flip_rounds = 3;
  /// Also flip short beams from a boundary joint of two panels to an interior joint: the panel
  /// behind reaches the boundary (docs/panels.md).
  bool boundary_flips = true;
  double tolerance = 1e-7;        ///< stop when the energy falls by less than this fraction
  double max_out_of_plane = 5e-4; ///< m: the post-check (0.5 mm)
  /// The post-check: no joint farther from the surface than this × its span (larger plan side).
  double max_surface_distance = 0.01;
  /// The post-check: no beam shorter than this × the design's shortest beam (a collapsed beam
  /// would be a mechanism in the frame analysis; the beams of split joints are held to it too).
  double min_beam_ratio = 0.25;
  /// The last resort when every attempt fails the post-check: in the attempt that needs the
  /// fewest, the failing panels give up their planes and are glazed as flat triangles (new beams
  /// along their diagonals), at most this fraction of the panels (0: never; the design then keeps
  /// its free panels). Every other panel stays a flat cell of the design.
  double max_triangulated = 0.1;
  /// A step may not add self-intersecting panels (off: only the energy decides; measured: on
  /// gives fewer failures).
  bool guard = true;
};

/// Shape of panels and joints, for any grid-shell (free or flat).
struct PanelShape {
  std::vector<double> out_of_plane;  ///< per panel: largest corner distance to its best-fit plane (m)
  double out_of_plane_max = 0, out_of_plane_median = 0;  ///< m
  int nonconvex = 0;           ///< panels with a reflex corner (in the best-fit plane)
  int self_intersecting = 0;   ///< panels that are not simple polygons
  double min_angle_deg = 0;    ///< smallest interior corner angle of any panel
  double surface_distance_max = 0, surface_distance_mean = 0;  ///< joints to M (m; 0 without M)
};
/// Measures `mesh`; `surface` (optional) for the joints' distance to it.
PanelShape panel_shape(const PolyMesh& mesh, const SurfaceProjector* surface = nullptr);

struct FlatPanelStats {
  int iterations = 0;
  bool converged = false;
  int split_joints = 0;      ///< joints of valence ≥ 4 (or boundary joints of ≥ 3 panels) split
  int added_joints = 0;      ///< joints the splits added
  int flipped_beams = 0;     ///< beams turned over (T1 flips): panels that changed corners
  bool lifted = false;       ///< the start needed the lift (planes parallel at a joint)
  double energy_start = 0, energy = 0;
  double min_det = 0;        ///< smallest |det| of a joint's three planes
  double out_of_plane_max = 0;  ///< m, corner to its panel's own plane (the post-check)
  double surface_distance_max = 0;  ///< m, the farthest joint from the input surface
  double shortest_beam = 0;      ///< m
  int attempts = 1;              ///< optimisations run (1 + the retries and restarts needed)
  double surface_weight = 0;     ///< w_s of the attempt that passed
  int triangulated_panels = 0;   ///< panels glazed as triangles (max_triangulated)
  double seconds = 0;
};

struct FlatPanelResult {
  /// The design's faces (ids), joints at plane intersections; a triangulated panel's first
  /// triangle keeps its id, its others follow all panels.
  PolyMesh mesh;
  std::vector<int> supports;  ///< support joints of `mesh` (sorted)
  std::vector<int> source_vertex;  ///< per joint of `mesh`: the design joint it comes from
  std::vector<int> source_face;    ///< per panel of `mesh`: the design panel it glazes
  std::vector<Vec3> normal;   ///< per panel: unit normal of its plane
  std::vector<double> offset; ///< per panel: n·x = offset
  FlatPanelStats stats;
};

/// What flat_panels throws when the result fails its post-check or the mesh cannot be made flat
/// this way (a non-manifold joint); the pipeline then keeps the free panels and says so.
class FlatPanelsFailed : public Error {
 public:
  explicit FlatPanelsFailed(const std::string& what) : Error("--panels flat", what) {}
};

/// Planar panels for `design` (joints on or near the surface `projector` projects on; faces
/// consistently oriented; `projector` built on `surface`). `supports`: joints of `design` that are
/// supported.
FlatPanelResult flat_panels(const PolyMesh& design, const std::vector<int>& supports,
                            const TriMesh& surface, const SurfaceProjector& projector,
                            const FlatPanelOptions& options = {});

}  // namespace gridshell
