#pragma once
/// \file shell_solver.h
/// Linear static analysis of a thin continuous shell discretised by flat facet triangles
/// (shell_element.h: OPT membrane with drilling dof + DKT bending, 6 dof per node).
///
/// Units: SI (m, N, Pa, kg) unless the model is given in other consistent units.
/// Cost: assembly O(faces), parallel over elements; one sparse supernodal Cholesky (SuiteSparse
/// CHOLMOD, METIS order of the node graph). At 50 K triangles (155 K dofs): 15 GFlop, 0.4 GB;
/// ≈ 3.3 s of CPU with OpenBLAS, ≈ 11 s with the reference BLAS (docs/shell.md).

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gridshell/core/timings.h"
#include "gridshell/fem/principal_stress.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell::fem {

/// Degrees of freedom of a node, in this order everywhere (columns of displacements).
enum ShellDof { kUx = 0, kUy, kUz, kRx, kRy, kRz };

/// Material of the shell. The defaults are a design value for a reinforced-concrete-like shell
/// (the paper analyses a continuous shell only to get stress directions and relative
/// magnitudes, which do not depend on E for a single load case): E = 30 GPa, ν = 0.2,
/// 2400 kg/m³.
struct ShellMaterial {
  double E = 30e9;        ///< Young's modulus (Pa)
  double nu = 0.2;        ///< Poisson's ratio
  double density = 2400;  ///< kg/m³ (used by self-weight loads)
};

/// One load case entry. Forces in N, moments in N·m, distributed loads in N/m².
struct ShellLoad {
  enum class Kind {
    kNode,        ///< `force` and `moment` at `node`
    kSurface,     ///< `q` (global vector) per unit surface area
    kProjected,   ///< `q` (global vector) per unit plan area (the area projected on z = 0)
    kPressure,    ///< `p` per unit area against the face normal: force −p·n·area
    kSelfWeight,  ///< density · g · thickness per unit area, along −z
  };
  Kind kind = Kind::kNode;
  int node = -1;
  Vec3 force = Vec3::Zero();
  Vec3 moment = Vec3::Zero();
  Vec3 q = Vec3::Zero();
  double p = 0;
  double g = 9.81;
};

/// A shell model: facets, per-node fixities (6 per node: ux uy uz rx ry rz; empty = all free),
/// loads, material, thickness (m).
struct ShellModel {
  TriMesh mesh;
  std::vector<std::array<bool, 6>> fixed;
  std::vector<ShellLoad> loads;
  ShellMaterial material;
  double thickness = 0.1;
};

struct ShellOptions {
  /// Refuse models with unrestrained rigid-body motions before factorising (recommended; the
  /// factorisation would catch them too, but less legibly).
  bool check_mechanism = true;
  /// Models with at least this many dofs are factorised in two halves on two threads around a
  /// vertex separator (fem/split_cholesky.h); smaller ones, or graphs that do not split well,
  /// in one CHOLMOD factorisation. Either way the result does not depend on the machine.
  int split_min_dofs = 60000;
};

struct ShellResult {
  Eigen::MatrixXd displacement;  ///< n × 6: ux uy uz (m), rx ry rz (rad)
  Eigen::MatrixXd reaction;      ///< n × 6 support reactions (N, N·m); zero at free dofs
  Eigen::MatrixXd membrane;      ///< faces × 3: sxx, syy, sxy (Pa) in the facet frame
  StressField stress;            ///< per face: principal membrane stresses and directions
  double max_displacement = 0;   ///< max over vertices of |(ux, uy, uz)| (m)
  int max_displacement_vertex = -1;
  Vec3 applied_force = Vec3::Zero();   ///< sum of all applied forces (N)
  Vec3 reaction_force = Vec3::Zero();  ///< sum of the support reaction forces (N)
  int dofs = 0;                        ///< 6 × vertices
  int free_dofs = 0;
  double factor_nnz = 0;    ///< non-zeros of the Cholesky factor
  double factor_flops = 0;  ///< floating-point operations of the factorisation
  /// Seconds per phase: "assemble", "order", "factorize", "solve", "stress". The ordering and
  /// symbolic analysis run on their own thread during the assembly, so the wall time is about
  /// max(assemble, order) + factorize + solve + stress.
  Timings timings;
  /// Process CPU seconds during the factorisation (the benchmark's figure on a loaded machine;
  /// includes other threads of the process if any run meanwhile).
  double cpu_factor = 0;
  /// Fill-reducing ordering used: "metis-nodes" (METIS nested dissection of the node graph,
  /// 6 dofs per node kept together), "split-metis-nodes" (the same within the two halves of a
  /// split factorisation) or "cholmod-default" (fallback if METIS failed).
  std::string ordering;
};

/// Solves K u = f. Throws Error("model", ...) for: bad indices, degenerate facets, a
/// non-positive thickness or modulus, and a mechanism (message names the free motion, e.g.
/// "translation along z" or "rotation about an axis along (0, 1, 0) through (5, 0, 0)", or the
/// vertex/dof at which the factorisation found a zero pivot). Deterministic.
ShellResult solve_shell(const ShellModel& model, const ShellOptions& options = {});

/// Principal membrane stresses of a facet from its local stress (sxx, syy, sxy) and frame
/// (rows: local x, y, normal): s1 ≥ s2, unit directions in 3-D.
PrincipalStress principal_membrane_stress(const Eigen::Vector3d& local_stress,
                                          const Eigen::Matrix3d& frame);

/// Defaults of the design pipeline's shell analysis (`gridshell stress SURFACE`).
struct ShellDefaults {
  ShellMaterial material;
  double thickness = 0.1;       ///< m
  double projected_load = 1e3;  ///< N per m² of plan area, downward (−z): 1 kN/m²
  bool self_weight = false;     ///< add the shell's own weight (density · g · t)
  bool clamped = false;         ///< supports clamp rotations too (default: pinned)
};

/// The shell model of a surface for the design pipeline: uniform projected load, the surface's
/// supports pinned (or clamped), default material and thickness.
ShellModel surface_shell_model(const Surface& surface, const ShellDefaults& defaults = {});

/// surface_shell_model + solve_shell.
ShellResult analyze_surface_stress(const Surface& surface, const ShellDefaults& defaults = {},
                                   const ShellOptions& options = {});

}  // namespace gridshell::fem
