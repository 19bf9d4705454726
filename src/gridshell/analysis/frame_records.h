#pragma once
/// \file frame_records.h
/// The figures analyze_frame records from a linear solution and an LBA, shared with
/// analyze_frame_loads (analysis/frame_loads.h) so that both report the same figures the same
/// way. Internal to the analysis layer.

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/fem/frame_solver.h"

namespace gridshell::analysis::detail {

/// δ, displacements, axial forces, reactions, strain energies and the equilibrium error of the
/// linear solution `lin` under the full load vector `load_full` (6 per node of mesh.X).
void record_linear(const fem::FrameMesh& mesh, const fem::FrameAssembler& assembler,
                   const fem::LinearResult& lin, const Eigen::VectorXd& load_full,
                   FrameResult& res);

/// The member checks and serviceability of `lin`. Throws Error("--deflection-limit") for a
/// divisor ≤ 0.
void record_checks(const fem::FrameModel& model, const fem::FrameMesh& mesh,
                   const fem::FrameAssembler& assembler, const fem::LinearResult& lin,
                   const FrameAnalysisOptions& o, FrameResult& res);

/// λ_LBA, the buckling factors and modes, and the members' mode energy.
void record_buckling(const fem::FrameMesh& mesh, const fem::FrameAssembler& assembler,
                     const fem::BucklingResult& lba, FrameResult& res);

}  // namespace gridshell::analysis::detail
