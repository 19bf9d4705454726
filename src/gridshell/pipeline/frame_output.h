#pragma once
/// \file frame_output.h
/// The files of a frame analysis (`gridshell analyze`), per the CONTRACT: nodes.csv
/// (`node,x,y,z,ux,uy,uz,support`), beams.csv (`beam,node_i,node_j,length,axial_force,utilisation,
/// buckling_utilisation,section,governing`: the member checks after the CONTRACT's columns, the
/// member's section name and the EN 1993-1-1 clause governing the larger utilisation),
/// path.csv (`lambda,displacement` of the non-linear path), modes.csv (write_buckling_modes),
/// nodes_nonlinear.csv (with `rx,ry,rz`, when a non-linear equilibrium was asked for) and frame.vtp
/// (ParaView lines with displacement, support flags and axial forces). All written atomically.

#include <filesystem>
#include <vector>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/fem/frame_model.h"

namespace gridshell {

/// Whether write_frame_outputs writes beams.csv: a grid-shell's fabrication files
/// (fabrication/fabrication_files.h) write their own, the same columns and more.
enum class BeamsCsv { Write, LeaveToFabrication };

/// Writes the files above into `dir` (which must exist). `supports`: supported model nodes.
void write_frame_outputs(const std::filesystem::path& dir, const fem::FrameModel& model,
                         const std::vector<int>& supports, const analysis::FrameResult& r,
                         BeamsCsv beams = BeamsCsv::Write);

/// modes.csv `mode,lambda,joint,ux,uy,uz`: the first `count` buckling modes' shapes (joint
/// translations, largest 1, sign arbitrary) with their λ. Nothing when there are no modes.
void write_buckling_modes(const std::filesystem::path& dir, const analysis::FrameResult& r,
                          int count = 3);

/// frame.json: the analysed frame as MODEL.json (io::frame_model_to_json), with the eurocode load
/// cases and combinations of `frame` (analysis/load_cases.h) or the paper's nodal loads, and an
/// "analysis" block asking for what `level` did with the grid-shell's path stop (span / 5 of
/// the joints' plan extent, the same step cap), so that `gridshell analyze frame.json` gives
/// the same δ, λ_LBA and utilisation (tests: 1e-6 relative).
void write_frame_json(const std::filesystem::path& dir, const fem::FrameModel& model,
                      const analysis::GridshellFrameOptions& frame,
                      const analysis::FrameAnalysisOptions& options, analysis::AnalysisLevel level);

}  // namespace gridshell
