#pragma once
/// \file frame_solver.h
/// Discretisation and the basic solves of a 3D frame: members subdivided into elements, dof
/// numbering (supports and the rotations of truss-only nodes removed), sparse assembly of the
/// linear, geometric and corotational tangent stiffness, linear static analysis, linearised
/// buckling (K + λ K_G) and geometrically non-linear equilibrium at a load factor.
///
/// Sparse SPD solves use CHOLMOD (supernodal LLᵀ, ordering the better of AMD and METIS);
/// indefinite tangents are factorised with CHOLMOD's simplicial LDLᵀ, whose D gives the number
/// of negative pivots (only done when asked: a solve or a pivot count). The sparsity pattern is
/// built once; assembly is parallel per element into disjoint slots, then summed in a fixed
/// order, so results do not depend on the thread count.

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/SparseCore>

#include "gridshell/fem/frame_element.h"
#include "gridshell/fem/frame_model.h"

namespace gridshell::fem {

using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

/// The discretised frame.
struct FrameMesh {
  Points X;  ///< reference coordinates: model nodes first, then interior nodes
  int num_model_nodes = 0;
  struct Element {
    int i = -1, j = -1;  ///< node ids in X
    int member = -1;
    bool truss = false;
    CorotBeam beam;  ///< stiffness, reference length and frame
  };
  std::vector<Element> elements;
  std::vector<std::array<int, 6>> dof;      ///< per node: equation number or −1 (restrained)
  std::vector<std::array<bool, 6>> active;  ///< per node: dof exists (not a truss-only rotation)
  int num_dofs = 0;
  Eigen::VectorXd load_full;  ///< 6 per node, the reference load (factor 1)
  Eigen::VectorXd load;       ///< reduced to the free dofs
  /// Per member: its element ids in order from node i to node j.
  std::vector<std::vector<int>> member_elements;
};

/// Subdivides members and numbers dofs. Throws Error (subject) for invalid models.
FrameMesh discretize(const FrameModel& model, const std::string& subject = "model");

/// A deformed configuration: node positions and nodal rotation matrices.
struct FrameState {
  Points x;
  std::vector<Mat3> R;
};
FrameState reference_state(const FrameMesh& mesh);
/// Applies an increment of the free dofs: translations added, rotations as left spins.
void apply_increment(const FrameMesh& mesh, const Eigen::VectorXd& du, FrameState& state);
/// Displacements (x − X) per node, n×3.
Points displacements(const FrameMesh& mesh, const FrameState& state);
/// Rotation vectors per node, n×3.
Points rotations(const FrameState& state);

/// One element's tangent stiffness (12×12, global components, [ui θi uj θj]) at `state`, with
/// its internal force and axial force (tension positive): the corotational beam, or the truss
/// (its rotation rows zero). `symmetric` as for corot_tangent.
Mat12 element_tangent(const FrameMesh::Element& e, const FrameState& state, Vec12& force,
                      double& axial, bool symmetric = true);
/// One element's internal force (and axial force) at `state`.
Vec12 element_force(const FrameMesh::Element& e, const FrameState& state, double& axial);

/// The full (6 per node) internal force from every element's force, added in element order (as
/// FrameAssembler::internal_force adds them, so the same forces give the same bits).
Eigen::VectorXd sum_element_forces(const FrameMesh& mesh, const std::vector<Vec12>& forces);

/// Sparse assembly on a fixed pattern (free dofs only, full symmetric storage).
class FrameAssembler {
 public:
  explicit FrameAssembler(const FrameMesh& mesh);
  const SpMat& pattern() const { return K_; }
  /// Linear stiffness; optional element-wise internal forces not needed here.
  SpMat linear_stiffness() const;
  /// Geometric stiffness for per-element axial forces (tension positive).
  SpMat geometric_stiffness(const std::vector<double>& axial) const;
  /// Corotational tangent and the internal force vector (full 6 per node, including restrained
  /// dofs, so reactions can be read off). `axial` optional out (per element N).
  SpMat tangent(const FrameState& state, Eigen::VectorXd* f_int_full,
                std::vector<double>* axial = nullptr, bool symmetric = true) const;
  /// Internal force only (cheaper). `element_forces` optional out: each element's force, whose
  /// sum_element_forces is the result.
  Eigen::VectorXd internal_force(const FrameState& state, std::vector<double>* axial = nullptr,
                                 std::vector<Vec12>* element_forces = nullptr) const;
  /// Reduces a full (6 per node) vector to the free dofs.
  Eigen::VectorXd reduce(const Eigen::VectorXd& full) const;
  /// Expands free dofs to a full (6 per node) vector (zeros at restrained dofs).
  Eigen::VectorXd expand(const Eigen::VectorXd& free) const;

 private:
  /// K on the pattern from element matrices: `element(k)` (called in parallel) gives element
  /// k's 12×12 matrix. Elements go through one small reused buffer a chunk at a time, each chunk
  /// added serially (elements share entries), so no per-element copy of all the matrices is
  /// kept (Aquadom: 27 MB fewer to touch per assembly).
  SpMat assemble(const std::function<Mat12(int)>& element) const;
  const FrameMesh& mesh_;
  SpMat K_;                // pattern
  std::vector<int> slot_;  // per element entry (144 per element): value index or −1
};

/// How often a TangentSolver is factorised on its pattern: `repeated` (a path's tangents) keeps
/// the analysed triangle in the factor's order and refills it (SparseCholeskyOptions::
/// factor_order_copy: faster refactorisations, 8 bytes per stored entry of the triangle);
/// `once` (a linear or buckling analysis) does not.
enum class Refactorisation { once, repeated };

/// Factorisation of a symmetric (possibly indefinite) tangent.
class TangentSolver {
 public:
  explicit TangentSolver(Refactorisation refactorisation = Refactorisation::once);
  ~TangentSolver();
  TangentSolver(const TangentSolver&) = delete;
  TangentSolver& operator=(const TangentSolver&) = delete;
  /// Factorises K (pattern must not change between calls) by LLᵀ. When K is not positive
  /// definite the LDLᵀ factorisation is deferred until a solve or the pivot count asks for it.
  /// Returns false if K is found singular.
  bool factorize(const SpMat& K);
  /// The symbolic analysis (fill-reducing ordering) of K's pattern, which factorize() otherwise
  /// does on its first call: it needs no values, so it can run while K is assembled.
  void analyze(const SpMat& pattern);
  /// The LLᵀ's symbolic analysis copied from `analysed` (of the same pattern; nothing when null):
  /// the solvers of a frame's paths, whose tangents share one pattern, order it once.
  void analyze_like(const TangentSolver* analysed, const SpMat& pattern);
  /// True when the last factorisation was positive definite.
  bool positive_definite() const { return pd_; }
  /// Number of negative pivots of LDLᵀ (0 when positive definite); −1 if LDLᵀ broke down.
  int negative_pivots() const;
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  /// When not positive definite: the equation at which LLᵀ broke down (for mechanism messages).
  int failed_equation() const { return failed_; }
  /// Smallest pivot ratio D_kk / K_kk seen (LLᵀ: L_kk² / K_kk) and its equation.
  double min_pivot_ratio() const { return min_ratio_; }
  int min_pivot_equation() const { return min_eq_; }

  struct Impl;
  /// The factorisations (for the solver's own translation unit: the buckling operator).
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
  bool ldlt() const;
  bool pd_ = false;
  mutable int negative_ = 0;
  mutable bool ldlt_done_ = false;
  SpMat K_;
  int failed_ = -1;
  double min_ratio_ = 0;
  int min_eq_ = -1;
};

/// Names the node and direction of an equation ("node 12 (uz)").
std::string describe_dof(const FrameMesh& mesh, int equation);

/// Throws Error(subject, "mechanism: ...") when K is singular or not positive definite.
void factorize_or_explain(TangentSolver& solver, const SpMat& K, const FrameMesh& mesh,
                          const std::string& subject);

/// Linear static analysis.
struct LinearResult {
  /// The factorised linear stiffness K (positive definite): linear_buckling reuses it instead of
  /// analysing and factorising K again.
  std::shared_ptr<const TangentSolver> stiffness;
  Eigen::VectorXd u;          ///< free dofs
  Points displacement;        ///< per node, n×3
  std::vector<double> axial;  ///< per element, tension positive
  Eigen::VectorXd reactions;  ///< full (6 per node): forces the supports exert
};
LinearResult linear_static(const FrameMesh& mesh, const FrameAssembler& assembler,
                           const std::string& subject = "model");

/// Strain energy ½ u_eᵀ K_e u_e of every element (linear stiffness) for a free-dof vector u:
/// a displacement field, or a buckling mode (whose energies then say where the mode bends).
std::vector<double> element_strain_energy(const FrameMesh& mesh, const FrameAssembler& assembler,
                                          const Eigen::VectorXd& u);

/// Section forces of one element in its local frame (x from node i to node j, y and z the
/// section axes of frame_model.h): the axial force N (tension positive; constant along the
/// element, loads act only at nodes) and, at end i and end j, the torsion T and the bending
/// moments My, Mz (signs follow the end-force convention; checks use magnitudes). Trusses: N only.
struct ElementSectionForces {
  double N = 0;
  std::array<double, 2> T{}, My{}, Mz{};
};

/// Of a linear solution (free-dof vector u): the local end forces K_e u_e.
std::vector<ElementSectionForces> element_section_forces(const FrameMesh& mesh,
                                                         const FrameAssembler& assembler,
                                                         const Eigen::VectorXd& u);
/// Of a corotational state: the local forces of the corotational element (f = ∂U/∂d).
std::vector<ElementSectionForces> element_section_forces(const FrameMesh& mesh,
                                                         const FrameState& state);

/// The envelope of a model member's section forces over its elements' ends.
struct MemberForces {
  double N_max = 0;       ///< largest axial force (tension positive) [N]
  double N_min = 0;       ///< smallest axial force (compression negative) [N]
  double My = 0, Mz = 0;  ///< largest |My|, |Mz| [N·m]
  double M = 0;           ///< largest resultant bending moment √(My² + Mz²) at one end [N·m]
  double T = 0;           ///< largest |T| [N·m]
  /// Largest |shear force| along local y and z [N]: per element |Mz_i + Mz_j| / l and
  /// |My_i + My_j| / l (no loads between an element's nodes).
  double Vy = 0, Vz = 0;
  /// Bending moments at the member's ends i and j [N·m], signed so that equal values bend the
  /// member in single curvature (uniform moment): −(end-force moment) at i, +(end-force moment)
  /// at j. Their ratio ψ gives the equivalent uniform moment factor Cm (EN 1993-1-1 Table B.3).
  std::array<double, 2> My_end{}, Mz_end{};
};
std::vector<MemberForces> member_forces(const FrameMesh& mesh,
                                        const std::vector<ElementSectionForces>& elements);

/// Linearised buckling: K φ = λ (−K_G(N_linear)) φ; the smallest positive λ first. Uses the
/// factorised K of `linear` (Lanczos on L⁻¹(−K_G)L⁻ᵀ: each step one forward and one back
/// substitution by CHOLMOD, and one K_G product; Aquadom triangulation,
/// 93 762 dofs: ~60 steps, memory-bound).
struct BucklingResult {
  std::vector<double> lambdas;         ///< ascending, positive only
  std::vector<Eigen::VectorXd> modes;  ///< free-dof vectors, max |translation| = 1
};
struct BucklingOptions {
  int modes = 5;
};
BucklingResult linear_buckling(const FrameMesh& mesh, const FrameAssembler& assembler,
                               const LinearResult& linear, const BucklingOptions& options = {});

}  // namespace gridshell::fem
