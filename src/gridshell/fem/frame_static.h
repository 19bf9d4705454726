#pragma once
/// \file frame_static.h
/// Geometrically non-linear equilibrium of a frame at one load factor: full Newton–Raphson with
/// the exact (non-symmetric) corotational tangent and a sparse LU, in adaptive load steps from
/// the unloaded state. The independent reference the arc-length path is checked against
/// (tests/frame_test.cpp) and `analyze --nonlinear-static`'s solver.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "gridshell/fem/frame_solver.h"

namespace gridshell::fem {

struct NonlinearStaticOptions {
  int initial_steps = 10;
  int max_iterations = 25;
  double tolerance = 1e-8;
  int max_cutbacks = 20;
};

struct NonlinearStaticResult {
  FrameState state;
  std::vector<double> axial;  ///< per element
  Eigen::VectorXd reactions;  ///< full (6 per node)
  int steps = 0, iterations = 0;
};

/// Equilibrium at load factor `lambda`. Throws Error(subject) when no equilibrium is found
/// (e.g. the factor is beyond the structure's limit load).
NonlinearStaticResult nonlinear_static(const FrameMesh& mesh, const FrameAssembler& assembler,
                                       double lambda, const NonlinearStaticOptions& options = {},
                                       const std::string& subject = "nonlinear_static");

}  // namespace gridshell::fem
