#pragma once
/// \file frame_relax.h
/// Local relaxation of a concentrated out-of-balance force (non-linear elimination; Lanzkron,
/// Rose & Wilkes 1996, Cai & Keyes 2002).
///
/// On a large grid-shell close to its critical load the non-linearity is often local: a few
/// hundred of the frame's nodes, where the shell is flat or weak, carry nearly all of a corrector
/// iterate's residual (Aquadom at λ ≈ 2.5: 90 % of |r|² on 100–200 of 13 908 nodes), and a
/// global Newton step taken with a tangent from elsewhere on the path overshoots there and
/// nowhere else. `relax_locally` finds those nodes, adds a ring of neighbours, and runs Newton on
/// that region alone — every other node held where it is, λ fixed — with the region's own
/// tangent (a sparse LLᵀ of a few thousand dofs by the library's SparseCholesky: milliseconds). The
/// global corrector then continues from a state whose residual is spread thin, where its stale
/// tangent contracts well. It only changes the iterates, not the equilibrium the corrector
/// converges to.
///
/// Cost: per local iteration the region's elements' forces and, where another iteration follows,
/// their tangents and a factorisation of the region's stiffness (its ordering once per call).

#include <vector>

#include <Eigen/Core>

#include "gridshell/fem/frame_solver.h"

namespace gridshell::fem {

/// Defaults measured on the Aquadom design's stability block (docs/performance.md, "Local
/// relaxation"): with share 0.9 and 2 rings a relaxation cut the global residual only 3–5×
/// (the 10 % of |r|² outside the core stays), with 0.99 and 4 rings 12–26×.
struct LocalRelaxOptions {
  double share = 0.99;  ///< the core: the fewest nodes carrying this share of |r|²
  /// Relax only when the core is at most this fraction of the nodes (else the residual is not
  /// local and a global iteration is the cheaper cure).
  double max_core_fraction = 0.1;
  int rings = 4;            ///< rings of neighbouring nodes (through elements) around the core
  int max_iterations = 4;   ///< local Newton iterations
  double reduction = 1e-3;  ///< stop when the region's residual has fallen by this factor
};

struct LocalRelaxResult {
  bool relaxed = false;  ///< the state was changed
  int core = 0, nodes = 0, iterations = 0;
  double before = 0, after = 0;  ///< the region's residual norm before and after
};

/// Per node the elements that touch it (built once per mesh).
std::vector<std::vector<int>> node_elements(const FrameMesh& mesh);

/// Relaxes the region of `state` where the free-dof residual `r` (= λ f − f_int) is concentrated,
/// at load factor `lambda`; adds the region's displacement increment (free dofs; rotations as
/// left spins, as apply_increment takes them) to `du`. Leaves `state` and `du` unchanged when the
/// residual is not concentrated, the region's tangent is not positive definite (it could carry
/// the region onto another branch) or no local step reduces the residual. `element_forces`
/// (optional, in and out): every element's force at `state` (FrameAssembler::internal_force's);
/// when relaxed, the forces of the elements the region touches become those of the relaxed
/// state, bit for bit as internal_force would give them — the others have not changed.
LocalRelaxResult relax_locally(const FrameMesh& mesh,
                               const std::vector<std::vector<int>>& node_elements, double lambda,
                               const Eigen::VectorXd& r, FrameState& state, Eigen::VectorXd& du,
                               const LocalRelaxOptions& options = {},
                               std::vector<Vec12>* element_forces = nullptr);

}  // namespace gridshell::fem
