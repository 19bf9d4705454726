// Local relaxation of a concentrated residual (fem/frame_relax.h): what it balances, what it
// leaves alone, and that the arc-length path with it is the path without it.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <tbb/global_control.h>

#include "gridshell/fem/frame_arclength.h"
#include "gridshell/fem/frame_relax.h"
#include "gridshell/fem/frame_solver.h"

using namespace gridshell;
using namespace gridshell::fem;

namespace {

// A shallow square cap of steel beams (n × n joints at 1 m, rise `rise`, edges pinned), each
// member in two elements, with a point load of 1 kN downwards at joint (ix, iy). Near its
// limit load the cap dimples under the load and nowhere else.
FrameModel shallow_cap(int n, double rise, int ix, int iy) {
  FrameModel m;
  m.nodes.resize(n * n, 3);
  const double c = 0.5 * (n - 1);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double u = (x - c) / c, v = (y - c) / c;
      m.nodes.row(y * n + x) << x, y, rise * (1 - u * u) * (1 - v * v);
    }
  m.sections = {circle_section(0.04)};
  m.materials = {{"steel", 2.1e11, 0.3, 7850}};
  const auto add = [&](int i, int j) {
    FrameMember mb;
    mb.i = i;
    mb.j = j;
    mb.elements = 2;
    m.members.push_back(mb);
  };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      if (x + 1 < n) add(y * n + x, y * n + x + 1);
      if (y + 1 < n) add(y * n + x, (y + 1) * n + x);
      if (x == 0 || y == 0 || x == n - 1 || y == n - 1)
        m.supports.push_back({y * n + x, {true, true, true, false, false, false}});
    }
  m.loads = {{iy * n + ix, Vec3(0, 0, -1000), Vec3::Zero()}};
  return m;
}

}  // namespace

TEST(LocalRelaxation, BalancesTheNodesWhereTheResidualSitsAndHoldsTheRest) {
  const FrameModel model = shallow_cap(13, 0.6, 4, 5);
  const FrameMesh mesh = discretize(model);
  const FrameAssembler asmb(mesh);
  const auto ne = node_elements(mesh);
  // At rest under λ = 10 (10 kN at one joint, about half the limit load) the whole residual is
  // the point load.
  const double lambda = 10;
  const FrameState rest = reference_state(mesh);
  FrameState st = rest;
  const Eigen::VectorXd r = lambda * mesh.load - asmb.reduce(asmb.internal_force(st));
  Eigen::VectorXd du = Eigen::VectorXd::Zero(mesh.num_dofs);
  const LocalRelaxResult lr = relax_locally(mesh, ne, lambda, r, st, du);
  ASSERT_TRUE(lr.relaxed);
  EXPECT_EQ(lr.core, 1);
  EXPECT_GT(lr.nodes, 1);
  EXPECT_LT(lr.nodes, mesh.X.rows() / 4);
  EXPECT_LE(lr.after, 1e-3 * lr.before);
  // Recomputed independently: the loaded joint is in balance. The residual now sits at the
  // region's rim, where the held nodes take the load (here, from rest, more of it than the
  // point load: the held rim stiffens the region by membrane action; the corrector keeps a
  // relaxation only when the whole residual falls).
  const int loaded = 5 * 13 + 4;
  const Eigen::VectorXd rr = asmb.expand(lambda * mesh.load - asmb.reduce(asmb.internal_force(st)));
  EXPECT_LT(rr.segment<3>(6 * loaded).norm(), 1e-3 * lambda * 1000);
  // Nodes outside the region have not moved; the loaded joint has, downwards.
  int moved = 0;
  for (int v = 0; v < mesh.X.rows(); ++v)
    if ((st.x.row(v) - rest.x.row(v)).norm() > 0 || (st.R[v] - rest.R[v]).norm() > 0) ++moved;
  EXPECT_LE(moved, lr.nodes);
  EXPECT_EQ(st.x(12 * 13 + 12, 0), rest.x(12 * 13 + 12, 0));
  EXPECT_LT(st.x(loaded, 2), rest.x(loaded, 2) - 1e-4);
  // The increment it reports is the translation it made.
  for (int v = 0; v < mesh.X.rows(); ++v)
    for (int k = 0; k < 3; ++k) {
      if (mesh.dof[v][k] >= 0) {
        EXPECT_NEAR(du(mesh.dof[v][k]), st.x(v, k) - rest.x(v, k), 1e-12);
      }
    }
}

// The element forces it hands back (the region's replaced, the rest as they were) add up to the
// internal force of the relaxed state exactly, so the corrector need not evaluate every element
// again; and the relaxation is the same on one thread as on several.
TEST(LocalRelaxation, ItsElementForcesAreTheRelaxedStatesAndDoNotDependOnThreads) {
  const FrameModel model = shallow_cap(13, 0.6, 4, 5);
  const FrameMesh mesh = discretize(model);
  const FrameAssembler asmb(mesh);
  const auto ne = node_elements(mesh);
  const auto relax = [&](FrameState& st, std::vector<Vec12>& forces) {
    const Eigen::VectorXd r =
        10 * mesh.load - asmb.reduce(asmb.internal_force(st, nullptr, &forces));
    Eigen::VectorXd du = Eigen::VectorXd::Zero(mesh.num_dofs);
    return relax_locally(mesh, ne, 10, r, st, du, {}, &forces);
  };
  FrameState st = reference_state(mesh);
  std::vector<Vec12> forces;
  ASSERT_TRUE(relax(st, forces).relaxed);
  const Eigen::VectorXd exact = asmb.internal_force(st);
  const Eigen::VectorXd summed = sum_element_forces(mesh, forces);
  ASSERT_EQ(summed.size(), exact.size());
  for (Eigen::Index i = 0; i < exact.size(); ++i) ASSERT_EQ(summed(i), exact(i)) << i;
  FrameState serial = reference_state(mesh);
  std::vector<Vec12> serial_forces;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    ASSERT_TRUE(relax(serial, serial_forces).relaxed);
  }
  EXPECT_EQ((serial.x - st.x).norm(), 0);
}

TEST(LocalRelaxation, LeavesAResidualSpreadOverTheFrameToTheGlobalIteration) {
  FrameModel model = shallow_cap(13, 0.6, 4, 5);
  model.loads.clear();
  for (int v = 0; v < model.num_nodes(); ++v)
    model.loads.push_back({v, Vec3(0, 0, -100), Vec3::Zero()});
  const FrameMesh mesh = discretize(model);
  const FrameAssembler asmb(mesh);
  FrameState st = reference_state(mesh);
  const Eigen::VectorXd r = 10 * mesh.load - asmb.reduce(asmb.internal_force(st));
  Eigen::VectorXd du = Eigen::VectorXd::Zero(mesh.num_dofs);
  const LocalRelaxResult lr = relax_locally(mesh, node_elements(mesh), 10, r, st, du);
  EXPECT_FALSE(lr.relaxed);
  EXPECT_EQ(lr.core, 0);
  EXPECT_EQ(du.norm(), 0);
  EXPECT_EQ((st.x - mesh.X).norm(), 0);
}

// The cap loaded at joint (4, 4): the corrector relaxes the dimple twice on the way to the limit
// point (and needs 29 factorisations instead of 38); the limit point is the same.
TEST(LocalRelaxation, ThePathWithItIsThePathWithoutIt) {
  const FrameModel model = shallow_cap(13, 0.6, 4, 4);
  const FrameMesh mesh = discretize(model);
  const FrameAssembler asmb(mesh);
  ArcLengthOptions opt;
  opt.initial_lambda = 5;
  opt.critical_tolerance = 1e-8;
  ArcLengthOptions plain = opt;
  plain.relaxation.reset();
  const ArcLengthResult with = arc_length(mesh, asmb, opt, reference_state(mesh));
  const ArcLengthResult without = arc_length(mesh, asmb, plain, reference_state(mesh));
  std::printf(
      "cap: lambda %.9f (%s, %d steps, %d factorisations, %d relaxations) against "
      "%.9f (%s, %d steps, %d factorisations)\n",
      with.lambda_critical, to_string(with.limit_type), with.steps, with.factorizations,
      with.relaxations, without.lambda_critical, to_string(without.limit_type), without.steps,
      without.factorizations);
  EXPECT_GT(with.relaxations, 0);
  EXPECT_EQ(without.relaxations, 0);
  EXPECT_NE(with.limit_type, LimitType::none);
  EXPECT_EQ(with.limit_type, without.limit_type);
  EXPECT_NEAR(with.lambda_critical / without.lambda_critical, 1.0, 1e-7);
}
