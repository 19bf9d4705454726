// Linear static shell analysis: assembly, constraints, CHOLMOD solve, stresses. See shell_solver.h.

#include "gridshell/fem/shell_solver.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <future>
#include <mutex>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>

#include "gridshell/core/cholmod_support.h"
#include "gridshell/core/sparse_cholesky.h"
#include "gridshell/core/error.h"
#include "gridshell/fem/shell_element.h"
#include "gridshell/fem/split_cholesky.h"
#include "gridshell/mesh/topology.h"

namespace gridshell::fem {

namespace {

using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// The monolithic factorisation's options: supernodal LLᵀ of K's upper triangle. Its ordering
// is normally given (analyze_by_nodes); the fallback is METIS nested dissection of the dofs: on
// shell meshes it beats AMD (14.8 vs 24 GFlop at 50 K triangles).
SparseCholeskyOptions shell_llt_options() {
  SparseCholeskyOptions o;
  o.ordering = CholeskyOrdering::metis;
  o.triangle = StoredTriangle::upper;
  return with_environment(o);
}

/// Symbolic analysis with METIS nested dissection of the node graph (6× smaller than the dof
/// graph), each node's 6 dofs kept together. `graph` is the upper pattern of the node graph
/// (with diagonal) in CSC; K the upper triangle of the stiffness (CSC, 6 dofs per node).
/// Returns whether the METIS node ordering was used (else the options' METIS of the dofs); the
/// analysis's success is `llt.analyzed()`.
bool analyze_by_nodes(SparseCholesky& llt, const cholmod_sparse& K, const std::vector<int>& gp,
                      const std::vector<int>& gi) {
  const int nn = static_cast<int>(gp.size()) - 1;
  std::vector<int> node_perm(nn), perm(6 * static_cast<std::size_t>(nn));
  // One METIS call at a time (core/cholmod_support.h; test:
  // ShellSolver.ConcurrentSolvesAreIdenticalToASerialOne): both calls hold the lock.
  if (nn > 1 && metis_graph_order(nn, gp.data(), gi.data(), node_perm.data())) {
    for (int q = 0; q < nn; ++q)
      for (int k = 0; k < 6; ++k) perm[6 * q + k] = 6 * node_perm[q] + k;
    SparseCholeskyOptions given = shell_llt_options();
    given.ordering = CholeskyOrdering::given;
    llt = SparseCholesky(given);
    llt.analyze(K, perm.data());
    return true;
  }
  llt.analyze(K);
  return false;
}

const char* kDofNames[6] = {"ux", "uy", "uz", "rx", "ry", "rz"};

std::string vec_str(const Vec3& v) {
  auto f = [](double x) { return std::abs(x) < 5e-13 ? 0.0 : x; };
  return fmt::format("({:.4g}, {:.4g}, {:.4g})", f(v.x()), f(v.y()), f(v.z()));
}

std::string axis_name(const Vec3& d) {
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k)
    if (std::abs(std::abs(d(k)) - 1) < 1e-9) return names[k];
  return vec_str(d);
}

// Connected components of the facets (by shared vertices); -1 for unreferenced vertices.
std::vector<int> vertex_components(const TriMesh& m, int& count) {
  const int n = m.num_vertices();
  DisjointSets sets(n);
  std::vector<char> used(n, 0);
  for (int f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      used[m.F(f, k)] = 1;
      sets.unite(m.F(f, 0), m.F(f, k));
    }
  std::vector<int> comp(n, -1), id(n, -1);
  count = 0;
  for (int v = 0; v < n; ++v) {
    if (!used[v]) continue;
    const int r = sets.find(v);
    if (id[r] < 0) id[r] = count++;
    comp[v] = id[r];
  }
  return comp;
}

// Refuses a model whose supports leave a rigid-body motion of a connected part free.
void check_rigid_body_modes(const ShellModel& model, const std::vector<char>& fixed) {
  const TriMesh& m = model.mesh;
  int ncomp = 0;
  const std::vector<int> comp = vertex_components(m, ncomp);
  for (int c = 0; c < ncomp; ++c) {
    std::vector<int> nodes;
    for (int v = 0; v < m.num_vertices(); ++v)
      if (comp[v] == c) nodes.push_back(v);
    Vec3 centre = Vec3::Zero();
    for (int v : nodes) centre += m.vertex(v);
    centre /= static_cast<double>(nodes.size());
    double L = 0;
    for (int v : nodes) L = std::max(L, (m.vertex(v) - centre).norm());
    if (!(L > 0)) L = 1;
    // Constraint matrix: rows = fixed dofs, columns = the 6 rigid modes (3 translations,
    // 3 rotations of angle 1/L about axes through the centre).
    Eigen::Matrix<double, 6, 6> G = Eigen::Matrix<double, 6, 6>::Zero();
    for (int v : nodes) {
      const Vec3 r = (m.vertex(v) - centre) / L;
      for (int k = 0; k < 6; ++k) {
        if (!fixed[6 * v + k]) continue;
        Eigen::Matrix<double, 6, 1> row = Eigen::Matrix<double, 6, 1>::Zero();
        if (k < 3) {
          row(k) = 1;
          for (int a = 0; a < 3; ++a) row(3 + a) = Vec3::Unit(a).cross(r)(k);
        } else {
          row(k) = 1 / L;
        }
        G += row * row.transpose();
      }
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(G);
    std::vector<std::string> free;
    for (int i = 0; i < 6; ++i) {
      if (es.eigenvalues()(i) > 1e-10) continue;
      const Eigen::Matrix<double, 6, 1> q = es.eigenvectors().col(i);
      const Vec3 t = q.head<3>(), w = q.tail<3>();
      if (w.norm() < 1e-6) {
        free.push_back("translation along " + axis_name(t.normalized()));
      } else {
        // u(x) = t + w × (x − c)/L: the axis passes through c + L (w × t)/|w|².
        const Vec3 p = centre + L * w.cross(t) / w.squaredNorm();
        free.push_back("rotation about an axis along " + axis_name(w.normalized()) + " through " +
                       vec_str(p));
      }
    }
    if (!free.empty()) {
      std::string what = "the structure is a mechanism: ";
      for (std::size_t i = 0; i < free.size(); ++i) what += (i ? ", " : "") + free[i];
      what += fmt::format(" {} not restrained by the supports", free.size() > 1 ? "are" : "is");
      if (ncomp > 1)
        what += fmt::format(" (part {} of {}, containing vertex {})", c + 1, ncomp, nodes.front());
      throw Error("model", what);
    }
  }
}

// The nodal load vector (6 per node): distributed loads lumped equally to the facet corners.
Eigen::VectorXd load_vector(const ShellModel& model, const std::vector<FacetFrame>& frames) {
  const TriMesh& m = model.mesh;
  const int n = m.num_vertices();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(6 * n);
  for (const ShellLoad& L : model.loads) {
    if (L.kind == ShellLoad::Kind::kNode) {
      if (L.node < 0 || L.node >= n)
        throw Error("model", fmt::format("load on missing node {}", L.node));
      rhs.segment<3>(6 * L.node) += L.force;
      rhs.segment<3>(6 * L.node + 3) += L.moment;
      continue;
    }
    for (int f = 0; f < m.num_faces(); ++f) {
      const Vec3 nrm = frames[f].R.row(2).transpose();
      const double A = frames[f].area;
      Vec3 F = Vec3::Zero();
      switch (L.kind) {
        case ShellLoad::Kind::kSurface:
          F = L.q * A;
          break;
        case ShellLoad::Kind::kProjected:
          F = L.q * (A * std::abs(nrm.z()));
          break;
        case ShellLoad::Kind::kPressure:
          F = -L.p * A * nrm;
          break;
        case ShellLoad::Kind::kSelfWeight:
          F = Vec3(0, 0, -model.material.density * L.g * model.thickness * A);
          break;
        default:
          break;
      }
      for (int k = 0; k < 3; ++k) rhs.segment<3>(6 * m.F(f, k)) += F / 3;
    }
  }
  return rhs;
}

}  // namespace

PrincipalStress principal_membrane_stress(const Eigen::Vector3d& s, const Eigen::Matrix3d& R) {
  PrincipalStress p;
  const double mean = 0.5 * (s(0) + s(1));
  const double dev = 0.5 * (s(0) - s(1));
  const double rad = std::hypot(dev, s(2));
  p.s1 = mean + rad;
  p.s2 = mean - rad;
  const double th = 0.5 * std::atan2(2 * s(2), s(0) - s(1));
  const Vec3 ex = R.row(0).transpose(), ey = R.row(1).transpose();
  p.d1 = std::cos(th) * ex + std::sin(th) * ey;
  p.d2 = -std::sin(th) * ex + std::cos(th) * ey;
  return p;
}

namespace {

void check_shell_model(const ShellModel& model) {
  const TriMesh& m = model.mesh;
  const int n = m.num_vertices(), nf = m.num_faces();
  if (n == 0 || nf == 0) throw Error("model", "the shell has no triangles");
  if (!(model.thickness > 0) || !std::isfinite(model.thickness))
    throw Error("model", "thickness must be positive");
  if (!(model.material.E > 0) || !std::isfinite(model.material.E))
    throw Error("model", "Young's modulus E must be positive");
  if (!(model.material.nu > -1 && model.material.nu < 0.5))
    throw Error("model", "Poisson's ratio must lie in (-1, 0.5)");
  if (!model.fixed.empty() && static_cast<int>(model.fixed.size()) != n)
    throw Error("model", "fixity list does not match the number of nodes");
  if (!m.V.allFinite()) throw Error("model", "non-finite node coordinates");
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      if (m.F(f, k) < 0 || m.F(f, k) >= n)
        throw Error("model", fmt::format("triangle {} refers to missing node {}", f, m.F(f, k)));
}

/// Facet frames; refuses degenerate facets.
std::vector<FacetFrame> checked_facet_frames(const TriMesh& m) {
  const double diag = (m.V.colwise().maxCoeff() - m.V.colwise().minCoeff()).norm();
  std::vector<FacetFrame> frames(m.num_faces());
  for (int f = 0; f < m.num_faces(); ++f) {
    frames[f] = facet_frame(m.vertex(m.F(f, 0)), m.vertex(m.F(f, 1)), m.vertex(m.F(f, 2)));
    if (!(frames[f].area > 1e-14 * diag * diag))
      throw Error("model", fmt::format("triangle {} is degenerate (zero area)", f));
  }
  return frames;
}

/// The sparsity pattern of K's upper triangle in node blocks: column 6v+k holds the rows of the
/// nodes u ≤ v adjacent to v (all 6 dofs for u < v, dofs 0..k for u = v).
struct NodePattern {
  std::vector<std::vector<int>> nbr;  ///< per node v: the adjacent nodes u ≤ v, sorted (v too)
  std::vector<int> colptr, rowidx;
};

NodePattern node_block_pattern(const TriMesh& m) {
  const int n = m.num_vertices(), nf = m.num_faces(), ndof = 6 * n;
  NodePattern p;
  std::vector<std::vector<int>> vfaces(n);
  p.nbr.resize(n);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) vfaces[m.F(f, k)].push_back(f);
  for (int v = 0; v < n; ++v) {
    auto& nb = p.nbr[v];
    nb.push_back(v);
    for (int f : vfaces[v])
      for (int k = 0; k < 3; ++k)
        if (m.F(f, k) < v) nb.push_back(m.F(f, k));
    std::sort(nb.begin(), nb.end());
    nb.erase(std::unique(nb.begin(), nb.end()), nb.end());
  }
  p.colptr.assign(ndof + 1, 0);
  for (int v = 0; v < n; ++v) {
    const int below = static_cast<int>(p.nbr[v].size()) - 1;
    for (int k = 0; k < 6; ++k) p.colptr[6 * v + k + 1] = 6 * below + k + 1;
  }
  for (int j = 0; j < ndof; ++j) p.colptr[j + 1] += p.colptr[j];
  p.rowidx.resize(p.colptr[ndof]);
  tbb::parallel_for(0, n, [&](int v) {
    for (int k = 0; k < 6; ++k) {
      int q = p.colptr[6 * v + k];
      for (int u : p.nbr[v])
        for (int i = 0; i < (u < v ? 6 : k + 1); ++i) p.rowidx[q++] = 6 * u + i;
    }
  });
  return p;
}

/// Element matrices, computed in parallel by chunks (bounded memory) and added into `vals` in
/// face order (results independent of the thread count).
void assemble_stiffness(const TriMesh& m, const ShellSection& sec, const NodePattern& p,
                        std::vector<double>& vals) {
  const int nf = m.num_faces();
  constexpr int kChunk = 8192;
  std::vector<Mat18> Ke(std::min(nf, kChunk));
  for (int f0 = 0; f0 < nf; f0 += kChunk) {
    const int f1 = std::min(nf, f0 + kChunk);
    tbb::parallel_for(f0, f1, [&](int f) {
      Ke[f - f0] = shell_element_stiffness(m.vertex(m.F(f, 0)), m.vertex(m.F(f, 1)),
                                           m.vertex(m.F(f, 2)), sec);
    });
    for (int f = f0; f < f1; ++f) {
      const Mat18& Kf = Ke[f - f0];
      for (int b = 0; b < 3; ++b) {
        const int v = m.F(f, b);
        const auto& nb = p.nbr[v];
        for (int a = 0; a < 3; ++a) {
          const int u = m.F(f, a);
          if (u > v) continue;
          const int pos =
              static_cast<int>(std::lower_bound(nb.begin(), nb.end(), u) - nb.begin()) * 6;
          for (int kj = 0; kj < 6; ++kj) {
            const int base = p.colptr[6 * v + kj] + pos;
            const int imax = u < v ? 6 : kj + 1;
            for (int ki = 0; ki < imax; ++ki) vals[base + ki] += Kf(6 * a + ki, 6 * b + kj);
          }
        }
      }
    }
  }
}

/// Supports: zero rows/columns of fixed dofs, keep their diagonal (u = 0 there).
void hold_fixed_dofs(const NodePattern& p, const std::vector<char>& fixed,
                     std::vector<double>& vals, Eigen::VectorXd& rhs) {
  const int ndof = static_cast<int>(fixed.size());
  for (int j = 0; j < ndof; ++j)
    for (int q = p.colptr[j]; q < p.colptr[j + 1]; ++q) {
      const int i = p.rowidx[q];
      if ((fixed[i] || fixed[j]) && i != j) vals[q] = 0;
      if (i == j && fixed[j] && !(vals[q] > 0)) vals[q] = 1;
    }
  for (int j = 0; j < ndof; ++j)
    if (fixed[j]) rhs(j) = 0;
}

/// Displacements, the largest one, reactions r = K_full u − f at the fixed dofs, and the
/// membrane stresses per facet.
void record_shell_results(const ShellModel& model, const ShellSection& sec,
                          const std::vector<FacetFrame>& frames, const std::vector<char>& fixed,
                          const std::vector<char>& used, const Eigen::VectorXd& u,
                          ShellResult& res) {
  const TriMesh& m = model.mesh;
  const int n = m.num_vertices(), nf = m.num_faces(), ndof = 6 * n;
  res.displacement =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>>(u.data(), n, 6);
  for (int v = 0; v < n; ++v) {
    const double d = res.displacement.row(v).head<3>().norm();
    if (d > res.max_displacement || res.max_displacement_vertex < 0) {
      res.max_displacement = d;
      res.max_displacement_vertex = v;
    }
  }
  std::vector<Eigen::Matrix<double, 18, 1>> fe(nf);
  tbb::parallel_for(0, nf, [&](int f) {
    Eigen::Matrix<double, 18, 1> ue;
    for (int a = 0; a < 3; ++a) ue.segment<6>(6 * a) = u.segment<6>(6 * m.F(f, a));
    fe[f] = shell_element_stiffness(m.vertex(m.F(f, 0)), m.vertex(m.F(f, 1)),
                                    m.vertex(m.F(f, 2)), sec) *
            ue;
  });
  Eigen::VectorXd Ku = Eigen::VectorXd::Zero(ndof);
  for (int f = 0; f < nf; ++f)
    for (int a = 0; a < 3; ++a) Ku.segment<6>(6 * m.F(f, a)) += fe[f].segment<6>(6 * a);
  res.reaction = Eigen::MatrixXd::Zero(n, 6);
  const Eigen::VectorXd fl = load_vector(model, frames);
  for (int v = 0; v < n; ++v)
    for (int k = 0; k < 6; ++k)
      if (fixed[6 * v + k] && used[v]) res.reaction(v, k) = Ku(6 * v + k) - fl(6 * v + k);
  for (int v = 0; v < n; ++v) res.reaction_force += res.reaction.row(v).head<3>().transpose();
  res.membrane.resize(nf, 3);
  res.stress.resize(nf);
  tbb::parallel_for(0, nf, [&](int f) {
    Eigen::Matrix<double, 18, 1> ue;
    for (int a = 0; a < 3; ++a) ue.segment<6>(6 * a) = u.segment<6>(6 * m.F(f, a));
    const Eigen::Vector3d s = shell_membrane_stress(frames[f], sec, ue);
    res.membrane.row(f) = s.transpose();
    res.stress[f] = principal_membrane_stress(s, frames[f].R);
  });
}

}  // namespace

ShellResult solve_shell(const ShellModel& model, const ShellOptions& options) {
  Stopwatch clock;
  check_shell_model(model);
  const TriMesh& m = model.mesh;
  const int n = m.num_vertices(), nf = m.num_faces();
  const ShellSection sec{model.material.E, model.material.nu, model.thickness};
  const int ndof = 6 * n;

  // Fixities; vertices used by no triangle have no stiffness and are held.
  std::vector<char> fixed(ndof, 0), used(n, 0);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) used[m.F(f, k)] = 1;
  for (int v = 0; v < n; ++v)
    for (int k = 0; k < 6; ++k)
      fixed[6 * v + k] = !used[v] || (!model.fixed.empty() && model.fixed[v][k]);
  const std::vector<FacetFrame> frames = checked_facet_frames(m);
  if (options.check_mechanism) check_rigid_body_modes(model, fixed);

  ShellResult res;
  Eigen::VectorXd rhs = load_vector(model, frames);
  if (!rhs.allFinite()) throw Error("model", "non-finite load");
  for (int v = 0; v < n; ++v) res.applied_force += rhs.segment<3>(6 * v);

  NodePattern pattern = node_block_pattern(m);
  std::vector<double> vals(pattern.rowidx.size(), 0.0);
  // Fill-reducing ordering and symbolic analysis need only the pattern: they run on their own
  // thread while the element matrices are computed and added (a pattern-only view of K, so the
  // analysis never reads the values being written).
  cholmod_sparse K = upper_csc_view(ndof, pattern.colptr.data(), pattern.rowidx.data());
  SparseCholesky llt(shell_llt_options());
  SplitCholesky split;
  bool use_split = false;
  std::future<double> analysis = std::async(std::launch::async, [&, Kp = K]() mutable {
    const Stopwatch order_clock;
    std::vector<int> gp(n + 1, 0), gi;
    for (int v = 0; v < n; ++v) gp[v + 1] = gp[v] + static_cast<int>(pattern.nbr[v].size());
    gi.reserve(gp[n]);
    for (int v = 0; v < n; ++v) gi.insert(gi.end(), pattern.nbr[v].begin(), pattern.nbr[v].end());
    use_split = ndof >= options.split_min_dofs && split.analyze(Kp, 6, gp, gi);
    if (use_split)
      res.ordering = "split-metis-nodes";
    else
      res.ordering = analyze_by_nodes(llt, Kp, gp, gi) ? "metis-nodes" : "cholmod-default";
    return order_clock.seconds();
  });
  assemble_stiffness(m, sec, pattern, vals);
  hold_fixed_dofs(pattern, fixed, vals, rhs);
  K.x = vals.data();
  K.xtype = CHOLMOD_REAL;
  res.dofs = ndof;
  res.free_dofs = static_cast<int>(std::count(fixed.begin(), fixed.end(), 0));
  res.timings.add("assemble", clock.lap());

  // Factorise and solve.
  res.timings.add("order", analysis.get());  // its own duration, overlapped with the assembly
  if (!use_split && !llt.analyzed())
    throw Error("model", "sparse analysis failed (out of memory?)");
  clock.lap();
  const std::clock_t c1 = std::clock();
  long col = -1;
  bool ok = true;
  if (use_split) {
    col = split.factorize(K);
    ok = col < 0;
  } else {
    const CholeskyStatus status = llt.factorize(K);
    ok = status.ok;
    col = status.failed_column;
  }
  res.cpu_factor = static_cast<double>(std::clock() - c1) / CLOCKS_PER_SEC;
  res.timings.add("factorize", clock.lap());
  res.factor_nnz = use_split ? split.factor_nnz() : llt.factor_nonzeros();
  res.factor_flops = use_split ? split.factor_flops() : llt.factor_flops();
  if (!ok) {
    if (col >= 0)
      throw Error("model", fmt::format("the structure is a mechanism or ill-conditioned: the "
                                       "stiffness matrix is singular at vertex {} dof {} ({})",
                                       col / 6, kDofNames[col % 6],
                                       col % 6 < 3 ? "free translation" : "free rotation"));
    throw Error("model", "the stiffness matrix could not be factorised (a mechanism?)");
  }
  clock.lap();
  const Eigen::VectorXd u = use_split ? split.solve(rhs) : Eigen::VectorXd(llt.solve(rhs));
  res.timings.add("solve", clock.lap());
  if (!u.allFinite())
    throw Error("model", "the solution is not finite (the structure is a mechanism)");

  clock.lap();
  record_shell_results(model, sec, frames, fixed, used, u, res);
  res.timings.add("stress", clock.lap());
  spdlog::info(
      "shell: {} vertices, {} triangles, {} free dofs; assembly {:.3f} s, ordering "
      "{:.3f} s, factor {:.3f} s, solve {:.3f} s",
      n, nf, res.free_dofs, res.timings.get("assemble"), res.timings.get("order"),
      res.timings.get("factorize"), res.timings.get("solve"));
  return res;
}

ShellModel surface_shell_model(const Surface& surface, const ShellDefaults& d) {
  ShellModel model;
  model.mesh = surface.mesh;
  model.material = d.material;
  model.thickness = d.thickness;
  const int n = surface.mesh.num_vertices();
  model.fixed.assign(n, {false, false, false, false, false, false});
  for (int v : surface.supports) {
    if (v < 0 || v >= n) throw Error("supports", fmt::format("vertex {} does not exist", v));
    for (int k = 0; k < (d.clamped ? 6 : 3); ++k) model.fixed[v][k] = true;
  }
  ShellLoad q;
  q.kind = ShellLoad::Kind::kProjected;
  q.q = Vec3(0, 0, -d.projected_load);
  model.loads.push_back(q);
  if (d.self_weight) {
    ShellLoad w;
    w.kind = ShellLoad::Kind::kSelfWeight;
    model.loads.push_back(w);
  }
  return model;
}

ShellResult analyze_surface_stress(const Surface& surface, const ShellDefaults& defaults,
                                   const ShellOptions& options) {
  return solve_shell(surface_shell_model(surface, defaults), options);
}

}  // namespace gridshell::fem
