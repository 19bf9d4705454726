#include "gridshell/fem/frame_solver.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>

#include <Spectra/SymEigsSolver.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>
#include <Eigen/Eigenvalues>

#include "gridshell/core/sparse_cholesky.h"
#include "gridshell/core/error.h"
#include "gridshell/fem/frame_pattern.h"
#include "gridshell/fem/linear_cases.h"

namespace gridshell::fem {

namespace {
const char* kDofNames[6] = {"ux", "uy", "uz", "rx", "ry", "rz"};
}

FrameMesh discretize(const FrameModel& model, const std::string& subject) {
  validate(model, subject);
  FrameMesh mesh;
  const int n0 = model.num_nodes();
  mesh.num_model_nodes = n0;
  int extra = 0;
  for (const FrameMember& m : model.members)
    if (m.type == MemberType::beam) extra += m.elements - 1;
  mesh.X.resize(n0 + extra, 3);
  mesh.X.topRows(n0) = model.nodes;
  int next = n0;
  mesh.member_elements.resize(model.members.size());
  std::vector<char> has_element(n0 + extra, 0), has_beam(n0 + extra, 0);
  for (int k = 0; k < static_cast<int>(model.members.size()); ++k) {
    const FrameMember& m = model.members[k];
    const FrameSection& s = model.sections[m.section];
    const FrameMaterial& mat = model.materials[m.material];
    const Vec3 a = model.nodes.row(m.i).transpose(), b = model.nodes.row(m.j).transpose();
    const Mat3 R0 = element_frame(a, b, m.up.squaredNorm() > 0 ? m.up : s.up);
    const int ne = m.type == MemberType::beam ? m.elements : 1;
    const double G = mat.E / (2 * (1 + mat.nu));
    int prev = m.i;
    for (int e = 0; e < ne; ++e) {
      int node;
      if (e == ne - 1) {
        node = m.j;
      } else {
        node = next++;
        mesh.X.row(node) = (a + (b - a) * (double(e + 1) / ne)).transpose();
      }
      FrameMesh::Element el;
      el.i = prev;
      el.j = node;
      el.member = k;
      el.truss = m.type == MemberType::truss;
      el.beam.s = {mat.E * s.A, mat.E * s.Iy, mat.E * s.Iz, G * s.J};
      el.beam.l0 = (b - a).norm() / ne;
      el.beam.R0 = R0;
      mesh.member_elements[k].push_back(static_cast<int>(mesh.elements.size()));
      mesh.elements.push_back(el);
      has_element[prev] = has_element[node] = 1;
      if (!el.truss) has_beam[prev] = has_beam[node] = 1;
      prev = node;
    }
  }
  const int n = static_cast<int>(mesh.X.rows());
  mesh.active.assign(n, {});
  mesh.dof.assign(n, {-1, -1, -1, -1, -1, -1});
  std::vector<std::array<bool, 6>> fixed(n, std::array<bool, 6>{});
  for (const FrameSupport& s : model.supports)
    for (int c = 0; c < 6; ++c) fixed[s.node][c] = fixed[s.node][c] || s.fix[c];
  int eq = 0;
  for (int v = 0; v < n; ++v)
    for (int c = 0; c < 6; ++c) {
      mesh.active[v][c] = has_element[v] && (c < 3 || has_beam[v]);
      if (mesh.active[v][c] && !fixed[v][c]) mesh.dof[v][c] = eq++;
    }
  mesh.num_dofs = eq;
  if (eq == 0) throw Error(subject, "every degree of freedom is restrained: nothing to analyse");
  mesh.load_full = load_vector(mesh, model.loads, subject);
  mesh.load = Eigen::VectorXd::Zero(eq);
  for (int v = 0; v < n; ++v)
    for (int c = 0; c < 6; ++c)
      if (mesh.dof[v][c] >= 0) mesh.load(mesh.dof[v][c]) = mesh.load_full(6 * v + c);
  return mesh;
}

FrameState reference_state(const FrameMesh& mesh) {
  FrameState s;
  s.x = mesh.X;
  s.R.assign(mesh.X.rows(), Mat3::Identity());
  return s;
}

void apply_increment(const FrameMesh& mesh, const Eigen::VectorXd& du, FrameState& state) {
  const int n = static_cast<int>(mesh.X.rows());
  for (int v = 0; v < n; ++v) {
    Vec3 w = Vec3::Zero();
    bool rot = false;
    for (int c = 0; c < 6; ++c) {
      const int d = mesh.dof[v][c];
      if (d < 0) continue;
      if (c < 3) {
        state.x(v, c) += du(d);
      } else {
        w(c - 3) = du(d);
        rot = true;
      }
    }
    if (rot) state.R[v] = rotation_exp(w) * state.R[v];
  }
}

Points displacements(const FrameMesh& mesh, const FrameState& state) {
  return state.x - mesh.X;
}

Points rotations(const FrameState& state) {
  Points r(state.R.size(), 3);
  for (size_t v = 0; v < state.R.size(); ++v) r.row(v) = rotation_log(state.R[v]).transpose();
  return r;
}

// ---------------------------------------------------------------------------------------------
// Assembly

namespace {
// Global dof (6 per node) of element-local entry a (0..11).
inline int elem_dof(const FrameMesh& mesh, const FrameMesh::Element& e, int a) {
  const int node = a < 6 ? e.i : e.j;
  const int c = a % 6;
  if (e.truss && c >= 3) return -1;
  return mesh.dof[node][c];
}
}  // namespace

FrameAssembler::FrameAssembler(const FrameMesh& mesh) : mesh_(mesh), K_(frame_pattern(mesh)) {
  const int ne = static_cast<int>(mesh.elements.size());
  slot_.assign(static_cast<size_t>(ne) * 144, -1);
  tbb::parallel_for(0, ne, [&](int k) {
    const auto& e = mesh.elements[k];
    for (int b = 0; b < 12; ++b) {
      const int c = elem_dof(mesh, e, b);
      if (c < 0) continue;
      const int* begin = K_.innerIndexPtr() + K_.outerIndexPtr()[c];
      const int* end = K_.innerIndexPtr() + K_.outerIndexPtr()[c + 1];
      for (int a = 0; a < 12; ++a) {
        const int r = elem_dof(mesh, e, a);
        if (r < 0) continue;
        const int* it = std::lower_bound(begin, end, r);
        slot_[static_cast<size_t>(k) * 144 + b * 12 + a] =
            static_cast<int>(it - K_.innerIndexPtr());
      }
    }
  });
}

SpMat FrameAssembler::assemble(const std::function<Mat12(int)>& element) const {
  constexpr int kChunk = 2048;  // elements per chunk: 2.4 MB of matrices
  const int ne = static_cast<int>(mesh_.elements.size());
  std::vector<Mat12> chunk(static_cast<size_t>(std::min(ne, kChunk)));
  SpMat K = K_;
  double* v = K.valuePtr();
  std::fill(v, v + K.nonZeros(), 0.0);
  for (int k0 = 0; k0 < ne; k0 += kChunk) {
    const int k1 = std::min(ne, k0 + kChunk);
    tbb::parallel_for(k0, k1, [&](int k) { chunk[k - k0] = element(k); });
    for (int k = k0; k < k1; ++k) {
      const int* slot = slot_.data() + static_cast<size_t>(k) * 144;
      const double* m = chunk[k - k0].data();  // column-major, as the slots
      for (int q = 0; q < 144; ++q)
        if (slot[q] >= 0) v[slot[q]] += m[q];
    }
  }
  return K;
}

namespace {
inline Mat12 truss_to12(const Mat6& k6) {
  Mat12 K = Mat12::Zero();
  K.block<3, 3>(0, 0) = k6.block<3, 3>(0, 0);
  K.block<3, 3>(0, 6) = k6.block<3, 3>(0, 3);
  K.block<3, 3>(6, 0) = k6.block<3, 3>(3, 0);
  K.block<3, 3>(6, 6) = k6.block<3, 3>(3, 3);
  return K;
}
inline Vec12 truss_f12(const Vec6& f6) {
  Vec12 f = Vec12::Zero();
  f.segment<3>(0) = f6.head<3>();
  f.segment<3>(6) = f6.tail<3>();
  return f;
}
inline Mat3 truss_block(double EA_l0, const Vec3& e, double N, double l) {
  return EA_l0 * e * e.transpose() + N / l * (Mat3::Identity() - e * e.transpose());
}
/// Linear stiffness of one element (beam or truss), global coordinates.
Mat12 element_linear_stiffness(const FrameMesh::Element& e) {
  if (!e.truss) return beam_linear_stiffness(e.beam.s, e.beam.l0, e.beam.R0);
  const Mat3 Kb = truss_block(e.beam.s.EA / e.beam.l0, e.beam.R0.col(0), 0, e.beam.l0);
  Mat6 k6;
  k6 << Kb, -Kb, -Kb, Kb;
  return truss_to12(k6);
}
}  // namespace

SpMat FrameAssembler::linear_stiffness() const {
  return assemble([&](int k) { return element_linear_stiffness(mesh_.elements[k]); });
}

SpMat FrameAssembler::geometric_stiffness(const std::vector<double>& axial) const {
  return assemble([&](int k) -> Mat12 {
    const auto& e = mesh_.elements[k];
    if (!e.truss) return beam_geometric_stiffness(axial[k], e.beam.l0, e.beam.R0);
    const Mat3 Kb = truss_block(0, e.beam.R0.col(0), axial[k], e.beam.l0);
    Mat6 k6;
    k6 << Kb, -Kb, -Kb, Kb;
    return truss_to12(k6);
  });
}

namespace {
CorotState element_state(const FrameMesh::Element& e, const FrameState& st) {
  CorotState s;
  s.xi = st.x.row(e.i).transpose();
  s.xj = st.x.row(e.j).transpose();
  s.Ri = st.R[e.i];
  s.Rj = st.R[e.j];
  return s;
}
void add_force(const FrameMesh::Element& e, const Vec12& f, Eigen::VectorXd& full) {
  full.segment<6>(6 * e.i) += f.head<6>();
  full.segment<6>(6 * e.j) += f.tail<6>();
}
}  // namespace

Mat12 element_tangent(const FrameMesh::Element& e, const FrameState& state, Vec12& force,
                      double& axial, bool symmetric) {
  const CorotState s = element_state(e, state);
  if (e.truss) {
    force = truss_f12(truss_force(e.beam.s.EA, e.beam.l0, s.xi, s.xj, &axial));
    return truss_to12(truss_tangent(e.beam.s.EA, e.beam.l0, s.xi, s.xj));
  }
  Vec7 f;
  const Mat12 Ke = corot_tangent(e.beam, s, &force, symmetric, &f);
  axial = f(0);
  return Ke;
}

Vec12 element_force(const FrameMesh::Element& e, const FrameState& state, double& axial) {
  const CorotState s = element_state(e, state);
  if (e.truss) return truss_f12(truss_force(e.beam.s.EA, e.beam.l0, s.xi, s.xj, &axial));
  Vec7 f;
  const Vec12 force = corot_force(e.beam, s, &f);
  axial = f(0);
  return force;
}

SpMat FrameAssembler::tangent(const FrameState& state, Eigen::VectorXd* f_int_full,
                              std::vector<double>* axial, bool symmetric) const {
  const int ne = static_cast<int>(mesh_.elements.size());
  std::vector<Vec12> forces(ne);
  std::vector<double> N(ne);
  SpMat K = assemble([&](int k) -> Mat12 {
    return element_tangent(mesh_.elements[k], state, forces[k], N[k], symmetric);
  });
  if (f_int_full) {
    f_int_full->setZero(6 * mesh_.X.rows());
    for (int k = 0; k < ne; ++k) add_force(mesh_.elements[k], forces[k], *f_int_full);
  }
  if (axial) *axial = std::move(N);
  return K;
}

Eigen::VectorXd FrameAssembler::internal_force(const FrameState& state, std::vector<double>* axial,
                                               std::vector<Vec12>* element_forces) const {
  const int ne = static_cast<int>(mesh_.elements.size());
  std::vector<Vec12> own;
  std::vector<Vec12>& forces = element_forces ? *element_forces : own;
  forces.resize(ne);
  std::vector<double> N(ne);
  tbb::parallel_for(0, ne,
                    [&](int k) { forces[k] = element_force(mesh_.elements[k], state, N[k]); });
  if (axial) *axial = std::move(N);
  return sum_element_forces(mesh_, forces);
}

Eigen::VectorXd sum_element_forces(const FrameMesh& mesh, const std::vector<Vec12>& forces) {
  Eigen::VectorXd full = Eigen::VectorXd::Zero(6 * mesh.X.rows());
  for (size_t k = 0; k < mesh.elements.size(); ++k) add_force(mesh.elements[k], forces[k], full);
  return full;
}

Eigen::VectorXd FrameAssembler::reduce(const Eigen::VectorXd& full) const {
  Eigen::VectorXd r(mesh_.num_dofs);
  for (int v = 0; v < static_cast<int>(mesh_.X.rows()); ++v)
    for (int c = 0; c < 6; ++c)
      if (mesh_.dof[v][c] >= 0) r(mesh_.dof[v][c]) = full(6 * v + c);
  return r;
}

Eigen::VectorXd FrameAssembler::expand(const Eigen::VectorXd& free) const {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(6 * mesh_.X.rows());
  for (int v = 0; v < static_cast<int>(mesh_.X.rows()); ++v)
    for (int c = 0; c < 6; ++c)
      if (mesh_.dof[v][c] >= 0) f(6 * v + c) = free(mesh_.dof[v][c]);
  return f;
}

// ---------------------------------------------------------------------------------------------
// Factorisation

namespace {
// Fill-reducing ordering for all the frame's factorisations: the better (fewer flops) of AMD and
// METIS nested dissection. For grid-shell frames METIS saves about a quarter of the flops; the
// extra analysis is done once per pattern.
//
// Supernodal: a frame's supernodes are tiny (Aquadom: 11 281 of 12 732 have ≤ 6 columns), but
// with the executables' small dense kernels (src/interpose/) the supernodal factorisation is
// still faster than the simplicial one, which has no BLAS calls (docs/performance.md, "The
// sparse solver": simplicial ×1.2–1.3 on the Aquadom and Lilium frames).
//
// K is stored whole (frame_pattern.h); the LLᵀ reads its upper triangle. For a path's tangents
// the permuted lower triangle CHOLMOD factorises is kept (`factor_order_copy`) and refilled from
// K at every factorisation: CHOLMOD's own permuted transpose was a third of a tangent's
// factorisation in the stability block (docs/performance.md). Only the failing column of an
// indefinite K is wanted: the factorisation stops there.
SparseCholeskyOptions llt_options(Refactorisation refactorisation) {
  SparseCholeskyOptions o;
  o.ordering = CholeskyOrdering::best_of_amd_metis;
  o.triangle = StoredTriangle::upper;
  o.stop_at_failure = true;
  o.factor_order_copy = refactorisation == Refactorisation::repeated;
  return with_environment(o);
}

// Simplicial LDLᵀ (no pivoting) for indefinite tangents; D gives the inertia. The lower
// triangle is the one CHOLMOD's simplicial factorisation permutes with one transpose.
SparseCholeskyOptions ldlt_options() {
  SparseCholeskyOptions o;
  o.ordering = CholeskyOrdering::best_of_amd_metis;
  o.mode = CholeskyMode::simplicial;
  o.kind = CholeskyKind::ldlt;
  o.triangle = StoredTriangle::lower;
  return o;
}

}  // namespace

struct TangentSolver::Impl {
  SparseCholesky llt;
  SparseCholesky ldlt{ldlt_options()};
  explicit Impl(Refactorisation r) : llt(llt_options(r)) {}
};

TangentSolver::TangentSolver(Refactorisation refactorisation)
    : impl_(std::make_unique<Impl>(refactorisation)) {}
TangentSolver::~TangentSolver() = default;

void TangentSolver::analyze(const SpMat& pattern) {
  Impl& m = *impl_;
  if (!m.llt.analyzed()) m.llt.analyze(pattern);
}

void TangentSolver::analyze_like(const TangentSolver* analysed, const SpMat& pattern) {
  if (analysed && analysed->impl_->llt.analyzed())
    impl_->llt.adopt_analysis(analysed->impl_->llt, pattern);
}

bool TangentSolver::factorize(const SpMat& K) {
  Impl& m = *impl_;
  analyze(K);
  const CholeskyStatus status = m.llt.factorize(K);
  failed_ = -1;
  min_ratio_ = 0;
  min_eq_ = -1;
  if (status.ok) {
    pd_ = true;
    negative_ = 0;
    const int* perm = m.llt.permutation();
    const Eigen::VectorXd l = m.llt.diagonal();
    const Eigen::VectorXd diagonal = K.diagonal();
    min_ratio_ = 1e300;
    for (Eigen::Index k = 0; k < l.size(); ++k) {
      const int eq = perm ? perm[k] : static_cast<int>(k);
      const double ratio = l(k) * l(k) / std::abs(diagonal(eq));
      if (ratio < min_ratio_) {
        min_ratio_ = ratio;
        min_eq_ = eq;
      }
    }
    return true;
  }
  pd_ = false;
  failed_ = static_cast<int>(status.failed_column);
  K_ = K;
  ldlt_done_ = false;
  return true;
}

bool TangentSolver::ldlt() const {
  if (pd_) return true;
  Impl& m = *impl_;
  if (!ldlt_done_) {
    ldlt_done_ = true;
    if (!m.ldlt.analyzed()) m.ldlt.analyze(K_);
    negative_ = -1;
    if (!m.ldlt.factorize(K_).ok) return false;
    const Inertia inertia = m.ldlt.inertia();
    if (inertia.singular > 0) return false;
    negative_ = inertia.negative;
  }
  return negative_ >= 0;
}

int TangentSolver::negative_pivots() const {
  if (pd_) return 0;
  ldlt();
  return negative_;
}

Eigen::VectorXd TangentSolver::solve(const Eigen::VectorXd& b) const {
  if (pd_) return impl_->llt.solve(b);
  if (!ldlt()) return Eigen::VectorXd::Constant(b.size(), std::numeric_limits<double>::quiet_NaN());
  return impl_->ldlt.solve(b);
}

std::string describe_dof(const FrameMesh& mesh, int equation) {
  for (int v = 0; v < static_cast<int>(mesh.X.rows()); ++v)
    for (int c = 0; c < 6; ++c)
      if (mesh.dof[v][c] == equation) {
        if (v < mesh.num_model_nodes) return fmt::format("node {} ({})", v, kDofNames[c]);
        for (size_t m = 0; m < mesh.member_elements.size(); ++m)
          for (int e : mesh.member_elements[m])
            if (mesh.elements[e].i == v)
              return fmt::format("an interior node of member {} ({})", m, kDofNames[c]);
        return fmt::format("internal node {} ({})", v, kDofNames[c]);
      }
  return fmt::format("equation {}", equation);
}

void factorize_or_explain(TangentSolver& solver, const SpMat& K, const FrameMesh& mesh,
                          const std::string& subject) {
  const bool ok = solver.factorize(K);
  if (ok && solver.positive_definite() && solver.min_pivot_ratio() > 1e-11) return;
  int eq = solver.failed_equation();
  if (ok && solver.positive_definite()) eq = solver.min_pivot_equation();
  const std::string where = eq >= 0 ? describe_dof(mesh, eq) : std::string("some node");
  throw Error(subject, fmt::format("mechanism: the structure is not stable, {} can move freely "
                                   "(add supports or members)",
                                   where));
}

// ---------------------------------------------------------------------------------------------
// Linear static analysis

// ---------------------------------------------------------------------------------------------
// Linear static analysis of several loads (linear_cases.h)

Eigen::VectorXd load_vector(const FrameMesh& mesh, const std::vector<NodalLoad>& loads,
                            const std::string& subject) {
  const int n = static_cast<int>(mesh.X.rows());
  Eigen::VectorXd full = Eigen::VectorXd::Zero(6 * n);
  for (const NodalLoad& l : loads) {
    if (l.node < 0 || l.node >= n)
      throw Error(subject, fmt::format("a load acts on node {}, which does not exist", l.node));
    for (int c = 0; c < 3; ++c) {
      const double F = l.force(c), M = l.moment(c);
      if (F != 0 && !mesh.active[l.node][c])
        throw Error(subject, fmt::format("a force acts on node {} which no member uses", l.node));
      if (M != 0 && !mesh.active[l.node][c + 3])
        throw Error(subject,
                    fmt::format("a moment acts on node {} which has no rotational stiffness "
                                "(no beam meets it)",
                                l.node));
      full(6 * l.node + c) += F;
      full(6 * l.node + 3 + c) += M;
    }
  }
  return full;
}

namespace {

/// The figures of one solution u of K u = reduce(load_full).
LinearResult linear_solution(const FrameMesh& mesh, const FrameAssembler& assembler,
                             Eigen::VectorXd u, const Eigen::VectorXd& load_full,
                             const std::string& subject) {
  LinearResult r;
  r.u = std::move(u);
  if (!r.u.allFinite()) throw Error(subject, "the linear solve produced non-finite values");
  const Eigen::VectorXd full = assembler.expand(r.u);
  const int n = static_cast<int>(mesh.X.rows());
  r.displacement.resize(n, 3);
  for (int v = 0; v < n; ++v) r.displacement.row(v) = full.segment<3>(6 * v).transpose();
  const int ne = static_cast<int>(mesh.elements.size());
  r.axial.resize(ne);
  Eigen::VectorXd fint = Eigen::VectorXd::Zero(6 * n);
  for (int k = 0; k < ne; ++k) {
    const auto& e = mesh.elements[k];
    Vec12 ue;
    ue.head<6>() = full.segment<6>(6 * e.i);
    ue.tail<6>() = full.segment<6>(6 * e.j);
    const Vec12 fe = element_linear_stiffness(e) * ue;
    fint.segment<6>(6 * e.i) += fe.head<6>();
    fint.segment<6>(6 * e.j) += fe.tail<6>();
    r.axial[k] =
        e.beam.s.EA / e.beam.l0 * e.beam.R0.col(0).dot(ue.segment<3>(6) - ue.segment<3>(0));
  }
  r.reactions = fint - load_full;
  for (int v = 0; v < n; ++v)
    for (int c = 0; c < 6; ++c)
      if (mesh.dof[v][c] >= 0 || !mesh.active[v][c]) r.reactions(6 * v + c) = 0;
  return r;
}

}  // namespace

std::vector<LinearResult> linear_static_cases(const FrameMesh& mesh,
                                              const FrameAssembler& assembler,
                                              const std::vector<Eigen::VectorXd>& loads_full,
                                              const std::string& subject) {
  auto solver = std::make_shared<TangentSolver>();
  // The ordering needs only the pattern: it runs beside the assembly (whose adding of element
  // matrices into K is serial).
  std::future<void> analysed =
      std::async(std::launch::async, [&] { solver->analyze(assembler.pattern()); });
  const SpMat K = assembler.linear_stiffness();
  analysed.get();
  factorize_or_explain(*solver, K, mesh, subject);
  std::vector<LinearResult> out;
  out.reserve(loads_full.size());
  for (const Eigen::VectorXd& load : loads_full) {
    out.push_back(
        linear_solution(mesh, assembler, solver->solve(assembler.reduce(load)), load, subject));
    out.back().stiffness = solver;
  }
  return out;
}

LinearResult linear_static(const FrameMesh& mesh, const FrameAssembler& assembler,
                           const std::string& subject) {
  return std::move(linear_static_cases(mesh, assembler, {mesh.load_full}, subject).front());
}

std::vector<double> element_strain_energy(const FrameMesh& mesh, const FrameAssembler& assembler,
                                          const Eigen::VectorXd& u) {
  const Eigen::VectorXd full = assembler.expand(u);
  const int ne = static_cast<int>(mesh.elements.size());
  std::vector<double> energy(ne);
  tbb::parallel_for(0, ne, [&](int k) {
    const auto& e = mesh.elements[k];
    Vec12 ue;
    ue.head<6>() = full.segment<6>(6 * e.i);
    ue.tail<6>() = full.segment<6>(6 * e.j);
    energy[k] = 0.5 * ue.dot(element_linear_stiffness(e) * ue);
  });
  return energy;
}

// ---------------------------------------------------------------------------------------------
// Linearised buckling

namespace {
// y = L⁻¹ P B Pᵀ L⁻ᵀ x for K = Pᵀ L Lᵀ P: a symmetric operator whose eigenvalues are 1/λ.
// The permutations are applied directly and CHOLMOD's solve workspaces are kept, so an
// application allocates nothing; B (stored whole) is multiplied as the self-adjoint view of its
// upper triangle (the product is memory-bound: it reads the first half of every column).
class BucklingOp {
 public:
  using Scalar = double;
  BucklingOp(const SparseCholesky& llt, SpMat B)
      : llt_(llt), B_(std::move(B)), perm_(llt.permutation()), a_(B_.rows()), b_(B_.rows()) {}
  Eigen::Index rows() const { return B_.rows(); }
  Eigen::Index cols() const { return B_.cols(); }
  void perform_op(const double* x_in, double* y_out) const {
    const Eigen::Index n = rows();
    a_ = Eigen::Map<const Eigen::VectorXd>(x_in, n);
    llt_.solve_in_place(CholeskySystem::Lt, a_);             // a = L⁻ᵀ x
    unpermute(a_, b_);                                       // b = Pᵀ a
    a_.noalias() = B_.selfadjointView<Eigen::Upper>() * b_;  // a = B b
    permute(a_, b_);                                         // b = P a
    llt_.solve_in_place(CholeskySystem::L, b_);              // b = L⁻¹ b
    Eigen::Map<Eigen::VectorXd>(y_out, n) = b_;
  }
  Eigen::VectorXd back(const Eigen::VectorXd& y) const {
    a_ = y;
    llt_.solve_in_place(CholeskySystem::Lt, a_);
    Eigen::VectorXd out(rows());
    unpermute(a_, out);
    return out;
  }

 private:
  // (P v)_k = v_perm[k]; (Pᵀ v)_perm[k] = v_k.
  void permute(const Eigen::VectorXd& v, Eigen::VectorXd& out) const {
    for (Eigen::Index k = 0; k < v.size(); ++k) out(k) = perm_ ? v(perm_[k]) : v(k);
  }
  void unpermute(const Eigen::VectorXd& v, Eigen::VectorXd& out) const {
    for (Eigen::Index k = 0; k < v.size(); ++k) out(perm_ ? perm_[k] : k) = v(k);
  }
  const SparseCholesky& llt_;
  SpMat B_;
  const int* perm_;
  mutable Eigen::VectorXd a_, b_;
};

double max_translation(const FrameMesh& mesh, const Eigen::VectorXd& v) {
  double m = 0;
  for (int n = 0; n < static_cast<int>(mesh.X.rows()); ++n) {
    double s = 0;
    for (int c = 0; c < 3; ++c)
      if (mesh.dof[n][c] >= 0) s += v(mesh.dof[n][c]) * v(mesh.dof[n][c]);
    m = std::max(m, std::sqrt(s));
  }
  return m;
}
}  // namespace

BucklingResult linear_buckling(const FrameMesh& mesh, const FrameAssembler& assembler,
                               const LinearResult& linear, const BucklingOptions& options) {
  BucklingResult out;
  double nmax = 0;
  for (double N : linear.axial) nmax = std::max(nmax, std::abs(N));
  if (nmax == 0) return out;
  SpMat B = assembler.geometric_stiffness(linear.axial);
  B.coeffs() *= -1;  // in place: the operator's B is −K_G
  const int n = mesh.num_dofs;
  std::vector<std::pair<double, Eigen::VectorXd>> found;
  if (n <= 300) {
    const Eigen::MatrixXd Kd(assembler.linear_stiffness()), Bd(B);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(Bd, Kd);
    if (es.info() != Eigen::Success) return out;
    for (int i = n - 1; i >= 0; --i) {
      const double mu = es.eigenvalues()(i);
      if (!(mu > 1e-14 * es.eigenvalues().cwiseAbs().maxCoeff())) break;
      found.emplace_back(1 / mu, es.eigenvectors().col(i));
      if (static_cast<int>(found.size()) >= options.modes) break;
    }
  } else {
    // The factorised K of the linear analysis, or a fresh one when it was not kept.
    std::shared_ptr<const TangentSolver> stiffness = linear.stiffness;
    if (!stiffness) {
      auto fresh = std::make_shared<TangentSolver>();
      fresh->factorize(assembler.linear_stiffness());
      stiffness = std::move(fresh);
    }
    if (!stiffness->positive_definite()) return out;
    BucklingOp op(stiffness->impl().llt, std::move(B));
    const int nev = std::min(options.modes, n - 2);
    const int ncv = std::min(n, std::max(2 * nev + 1, 24));
    Spectra::SymEigsSolver<BucklingOp> eigs(op, nev, ncv);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestAlge, 2000, 1e-9);
    if (eigs.info() != Spectra::CompInfo::Successful) return out;
    spdlog::debug("linear buckling: {} Lanczos operations, {} restarts", eigs.num_operations(),
                  eigs.num_iterations());
    const Eigen::VectorXd mu = eigs.eigenvalues();
    const Eigen::MatrixXd Y = eigs.eigenvectors();
    for (int i = 0; i < mu.size(); ++i)
      if (mu(i) > 0) found.emplace_back(1 / mu(i), op.back(Y.col(i)));
  }
  std::sort(found.begin(), found.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& [lam, v] : found) {
    const double m = max_translation(mesh, v);
    Eigen::VectorXd mode = m > 0 ? Eigen::VectorXd(v / m) : v;
    out.lambdas.push_back(lam);
    out.modes.push_back(std::move(mode));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Section forces

std::vector<ElementSectionForces> element_section_forces(const FrameMesh& mesh,
                                                         const FrameAssembler& assembler,
                                                         const Eigen::VectorXd& u) {
  const Eigen::VectorXd full = assembler.expand(u);
  const int ne = static_cast<int>(mesh.elements.size());
  std::vector<ElementSectionForces> out(ne);
  tbb::parallel_for(0, ne, [&](int k) {
    const auto& e = mesh.elements[k];
    Vec12 ue;
    ue.head<6>() = full.segment<6>(6 * e.i);
    ue.tail<6>() = full.segment<6>(6 * e.j);
    const Vec12 fe = element_linear_stiffness(e) * ue;
    const Mat3 Rt = e.beam.R0.transpose();
    ElementSectionForces& s = out[k];
    s.N = Rt.row(0).dot(fe.segment<3>(6));
    if (e.truss) return;
    for (int end = 0; end < 2; ++end) {
      const Vec3 m = Rt * fe.segment<3>(6 * end + 3);
      s.T[end] = m(0);
      s.My[end] = m(1);
      s.Mz[end] = m(2);
    }
  });
  return out;
}

std::vector<ElementSectionForces> element_section_forces(const FrameMesh& mesh,
                                                         const FrameState& state) {
  const int ne = static_cast<int>(mesh.elements.size());
  std::vector<ElementSectionForces> out(ne);
  tbb::parallel_for(0, ne, [&](int k) {
    const auto& e = mesh.elements[k];
    const CorotState st = element_state(e, state);
    ElementSectionForces& s = out[k];
    if (e.truss) {
      truss_force(e.beam.s.EA, e.beam.l0, st.xi, st.xj, &s.N);
      return;
    }
    Vec7 d, f;
    corot_local(e.beam, st, d, f);
    s.N = f(0);
    for (int end = 0; end < 2; ++end) {
      s.T[end] = f(1 + 3 * end);
      s.My[end] = f(2 + 3 * end);
      s.Mz[end] = f(3 + 3 * end);
    }
  });
  return out;
}

std::vector<MemberForces> member_forces(const FrameMesh& mesh,
                                        const std::vector<ElementSectionForces>& elements) {
  std::vector<MemberForces> out(mesh.member_elements.size());
  for (size_t m = 0; m < mesh.member_elements.size(); ++m) {
    MemberForces& f = out[m];
    bool first = true;
    for (int k : mesh.member_elements[m]) {
      const ElementSectionForces& s = elements[k];
      f.N_max = first ? s.N : std::max(f.N_max, s.N);
      f.N_min = first ? s.N : std::min(f.N_min, s.N);
      first = false;
      for (int end = 0; end < 2; ++end) {
        f.My = std::max(f.My, std::abs(s.My[end]));
        f.Mz = std::max(f.Mz, std::abs(s.Mz[end]));
        f.T = std::max(f.T, std::abs(s.T[end]));
        f.M = std::max(f.M, std::hypot(s.My[end], s.Mz[end]));
      }
      const double l = mesh.elements[k].beam.l0;
      if (l > 0) {
        f.Vy = std::max(f.Vy, std::abs(s.Mz[0] + s.Mz[1]) / l);
        f.Vz = std::max(f.Vz, std::abs(s.My[0] + s.My[1]) / l);
      }
    }
    if (!mesh.member_elements[m].empty()) {
      const ElementSectionForces& a = elements[mesh.member_elements[m].front()];
      const ElementSectionForces& b = elements[mesh.member_elements[m].back()];
      f.My_end = {-a.My[0], b.My[1]};
      f.Mz_end = {-a.Mz[0], b.Mz[1]};
    }
  }
  return out;
}

}  // namespace gridshell::fem
