#pragma once
/// \file frame_loads.h
/// One frame under several loads — the load combinations of a design — analysed at the linear
/// and LBA levels with one discretisation, one assembly and one factorisation of K
/// (fem/linear_cases.h): each load is one forward and back substitution, and its LBA
/// (K + λ K_G(N) of its own axial forces N, K_G being linear in N) reuses K's factor. Each
/// result is the FrameResult analyze_frame gives for the frame carrying that load alone at
/// `linear` or `buckling` level (same figures, same matrix, factor and right-hand side: equal to
/// round-off; tests/frame_loads_test.cpp), which is what a sizing iteration needs of every
/// combination (sizing/sizing.h).
///
/// Cost: one factorisation + per load O(nnz(L)) for the solve, the member checks, and with
/// `buckling` one Lanczos run (~60 pairs of triangular solves and K_G products). The per-load
/// figures are computed in parallel; the solves and LBAs share the factor and run in turn.

#include <vector>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/fem/frame_model.h"

namespace gridshell::analysis {

/// One load the frame carries, replacing the model's own loads.
struct FrameLoad {
  std::vector<fem::NodalLoad> loads;
  bool buckling = false;  ///< also the LBA under it
};

/// Per load its result (the model's own loads are ignored; options.linear, options.buckling
/// and options.nonlinear are not read: the level is the load's; nonlinear_static and
/// after_linear are not used). Throws Error(options.subject) as analyze_frame does for invalid
/// models and mechanisms, and for a load set on no node of the model (no loads: nothing to
/// analyse).
std::vector<FrameResult> analyze_frame_loads(const fem::FrameModel& model,
                                             const std::vector<FrameLoad>& loads,
                                             const FrameAnalysisOptions& options = {});

}  // namespace gridshell::analysis
