#pragma once
/// \file gridshell_frame.h
/// A grid-shell (polygon mesh: edges = beams, vertices = joints, faces = panels) as a frame with
/// the paper's defaults: solid circular steel bars Ø37 mm, E = 210 GPa, ν = 0.3, 7850 kg/m³,
/// pinned supports (translations fixed), each beam split into `elements` elements, and the
/// paper's load: the bars' total weight spread over the surface, each joint taking a share
/// proportional to the area of its incident faces (1/n of each n-gon's area per corner), so that
/// λ is a multiple of the structure's own weight. An optional area load (kN/m², same
/// distribution) is added; `self_weight_at_bars` puts each bar's weight at its two ends instead.
/// All loads act along −z. Cost: O(edges + face corners).

#include <vector>

#include "gridshell/fem/frame_model.h"
#include "gridshell/mesh/mesh.h"

namespace gridshell::analysis {

struct GridshellFrameOptions {
  double diameter = 0.037;  ///< [m]
  double E = 210e9;         ///< [Pa]
  double nu = 0.3;
  double density = 7850;  ///< [kg/m³]
  double g = 9.81;        ///< [m/s²]
  int elements = 2;       ///< elements per beam
  bool self_weight = true;
  bool self_weight_at_bars = false;
  double area_load_kN_m2 = 0;
};

fem::FrameModel gridshell_frame(const PolyMesh& mesh, const std::vector<int>& supports,
                                const GridshellFrameOptions& options = {});

/// Per-vertex tributary area: Σ over incident faces of area / (number of corners).
std::vector<double> tributary_areas(const PolyMesh& mesh);

}  // namespace gridshell::analysis
