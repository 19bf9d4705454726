// One frame under several loads on one factorisation of K (analysis/frame_loads.h,
// fem/linear_cases.h): every combination's figures equal those of its own analysis
// (analyze_frame, one assembly and factorisation per combination) to round-off; the solutions
// superpose (Σ γ_i × case_i is the combination's solution: the analysis is linear); λ_LBA scales
// inversely with the load (K_G is linear in the axial forces).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/frame_loads.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/analysis/load_cases.h"
#include "gridshell/core/error.h"
#include "gridshell/fem/frame_solver.h"
#include "gridshell/fem/linear_cases.h"

using namespace gridshell;
using namespace gridshell::analysis;

namespace {

/// A shallow dome of n × n quads over 12 m × 12 m (rise 1.5 m), its boundary joints pinned.
struct Dome {
  PolyMesh mesh;
  std::vector<int> supports;
};
Dome dome(int n) {
  Dome d;
  d.mesh.V.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = 12.0 * i / n - 6, y = 12.0 * j / n - 6;
      d.mesh.V.row(j * (n + 1) + i) << x, y, 1.5 * (1 - (x * x + y * y) / 72);
      if (i == 0 || j == 0 || i == n || j == n) d.supports.push_back(j * (n + 1) + i);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      d.mesh.faces.push_back({a, a + 1, a + n + 2, a + n + 1});
    }
  return d;
}

GridshellFrameOptions eurocode_frame() {
  GridshellFrameOptions o;
  o.loads = LoadModel::eurocode;
  o.section = "CHS 60.3x3.2";
  o.snow_kN_m2 = 1.5;
  return o;
}

std::vector<fem::NodalLoad> nodal(const std::vector<Vec3>& F) {
  std::vector<fem::NodalLoad> out;
  for (int v = 0; v < static_cast<int>(F.size()); ++v)
    if (F[v].squaredNorm() > 0) out.push_back({v, F[v], Vec3::Zero()});
  return out;
}

/// |a − b| ≤ tol × scale.
void expect_close(double a, double b, double scale, double tol, const std::string& what) {
  EXPECT_LE(std::abs(a - b), tol * std::max(scale, 1e-300)) << what << ": " << a << " vs " << b;
}

}  // namespace

TEST(FrameLoads, EveryCombinationEqualsItsOwnAnalysis) {
  const Dome d = dome(8);
  const GridshellFrameOptions frame = eurocode_frame();
  const fem::FrameModel model = gridshell_frame(d.mesh, d.supports, frame);
  const std::vector<LoadCase> cases =
      eurocode_cases(d.mesh, bar_weights_per_m(model, frame), frame);
  const std::vector<LoadCombination> combos = eurocode_combinations(cases);
  ASSERT_EQ(combos.size(), 10u);  // 5 snow arrangements, ULS and SLS each
  std::vector<FrameLoad> loads;
  for (const LoadCombination& c : combos) loads.push_back({nodal(combine(cases, c)), c.uls});
  const std::vector<FrameResult> shared = analyze_frame_loads(model, loads);
  ASSERT_EQ(shared.size(), combos.size());
  for (std::size_t k = 0; k < combos.size(); ++k) {
    GridshellFrameOptions f = frame;
    f.combination_name = combos[k].name;
    const FrameResult own =
        analyze_frame(gridshell_frame(d.mesh, d.supports, f),
                      at_level({}, combos[k].uls ? AnalysisLevel::buckling : AnalysisLevel::linear));
    const FrameResult& r = shared[k];
    const std::string& name = combos[k].name;
    ASSERT_GT(own.delta_max_m, 0) << name;
    expect_close(r.delta_max_m, own.delta_max_m, own.delta_max_m, 1e-9, name + " delta");
    EXPECT_EQ(r.delta_node, own.delta_node) << name;
    EXPECT_EQ(r.delta_pass, own.delta_pass) << name;
    expect_close(r.equilibrium_error, own.equilibrium_error, 1, 1e-9, name + " equilibrium");
    double nmax = 0;
    for (double n : own.axial_force) nmax = std::max(nmax, std::abs(n));
    ASSERT_EQ(r.member_forces.size(), own.member_forces.size());
    for (std::size_t m = 0; m < own.axial_force.size(); ++m) {
      expect_close(r.axial_force[m], own.axial_force[m], nmax, 1e-9, name + " N");
      expect_close(r.member_forces[m].M, own.member_forces[m].M, nmax, 1e-9, name + " M");
      expect_close(r.member_forces[m].N_min, own.member_forces[m].N_min, nmax, 1e-9, name);
    }
    expect_close(r.checks.section_max, own.checks.section_max, own.checks.section_max, 1e-9,
                 name + " utilisation");
    expect_close(r.checks.buckling_max, own.checks.buckling_max, own.checks.buckling_max, 1e-9,
                 name + " buckling utilisation");
    EXPECT_EQ(r.checks.section_worst, own.checks.section_worst) << name;
    ASSERT_EQ(r.lambda_linear_buckling.has_value(), own.lambda_linear_buckling.has_value()) << name;
    if (!own.lambda_linear_buckling) continue;
    expect_close(*r.lambda_linear_buckling, *own.lambda_linear_buckling,
                 *own.lambda_linear_buckling, 1e-9, name + " lambda_LBA");
    ASSERT_EQ(r.mode_energy.size(), own.mode_energy.size());
  }
}

TEST(FrameLoads, CaseSolutionsSuperposeIntoTheCombinations) {
  const Dome d = dome(6);
  const GridshellFrameOptions frame = eurocode_frame();
  const fem::FrameModel model = gridshell_frame(d.mesh, d.supports, frame);
  const std::vector<LoadCase> cases =
      eurocode_cases(d.mesh, bar_weights_per_m(model, frame), frame);
  std::vector<FrameLoad> loads;
  std::map<std::string, std::size_t> index;
  for (const LoadCase& c : cases) {
    index[c.name] = loads.size();
    loads.push_back({nodal(c.F), false});
  }
  const std::vector<FrameResult> per_case = analyze_frame_loads(model, loads);
  const std::vector<LoadCombination> combos = eurocode_combinations(cases);
  std::vector<FrameLoad> combined;
  for (const LoadCombination& c : combos) combined.push_back({nodal(combine(cases, c)), false});
  const std::vector<FrameResult> per_combination = analyze_frame_loads(model, combined);
  for (std::size_t k = 0; k < combos.size(); ++k) {
    Points u = Points::Zero(per_combination[k].displacement.rows(), 3);
    std::vector<double> N(per_combination[k].axial_force.size(), 0.0);
    for (const auto& [name, gamma] : combos[k].factors) {
      const FrameResult& c = per_case[index.at(name)];
      u += gamma * c.displacement;
      for (std::size_t m = 0; m < N.size(); ++m) N[m] += gamma * c.axial_force[m];
    }
    const FrameResult& r = per_combination[k];
    EXPECT_LE((u - r.displacement).cwiseAbs().maxCoeff(), 1e-9 * r.delta_max_m) << combos[k].name;
    double nmax = 0;
    for (double n : r.axial_force) nmax = std::max(nmax, std::abs(n));
    for (std::size_t m = 0; m < N.size(); ++m)
      EXPECT_LE(std::abs(N[m] - r.axial_force[m]), 1e-9 * nmax) << combos[k].name;
  }
}

TEST(FrameLoads, LbaFactorScalesInverselyWithTheLoad) {
  const Dome d = dome(6);
  const GridshellFrameOptions frame = eurocode_frame();
  const fem::FrameModel model = gridshell_frame(d.mesh, d.supports, frame);
  std::vector<fem::NodalLoad> twice = model.loads;
  for (fem::NodalLoad& l : twice) l.force *= 2.5;
  const std::vector<FrameResult> r = analyze_frame_loads(model, {{model.loads, true}, {twice, true}});
  ASSERT_TRUE(r[0].lambda_linear_buckling && r[1].lambda_linear_buckling);
  EXPECT_NEAR(*r[1].lambda_linear_buckling * 2.5, *r[0].lambda_linear_buckling,
              1e-8 * *r[0].lambda_linear_buckling);
  EXPECT_NEAR(r[1].delta_max_m, 2.5 * r[0].delta_max_m, 1e-10 * r[1].delta_max_m);
}

TEST(FrameLoads, LoadsOnMissingOrNoNodesAreOneLineErrors) {
  const Dome d = dome(4);
  const fem::FrameModel model = gridshell_frame(d.mesh, d.supports, eurocode_frame());
  EXPECT_THROW(analyze_frame_loads(model, {{{}, false}}), Error);
  EXPECT_THROW(analyze_frame_loads(model, {{{{100000, Vec3(0, 0, -1), Vec3::Zero()}}, false}}),
               Error);
  const fem::FrameMesh mesh = fem::discretize(model);
  EXPECT_EQ(fem::load_vector(mesh, model.loads), mesh.load_full);
}
