#pragma once
/// \file baseline.h
/// `gridshell baseline`: the comparison grid-shells of the paper, one function for every kind
/// (grids/baseline_kind.h), so that a front end only parses options and writes files:
///
///   quad         an isotropic square grid in plan, at --length or --spacing   grids/quad_grid.h
///   quad-aniso   quads following the design's field (field from `field`)     grids/quad_aniso.h
///   tri          the dual triangulation of the isotropic Voronoi design      grids/dual.h
///   voronoi-iso  the isotropic Voronoi design (D = A = 1), regularized       pipeline/design.h
///   original     the surface file's own quads (triangle pairs)               grids/recover_quads.h
///
/// then, with PanelMode::flat, every panel made exactly planar (attempt_flat_panels, except
/// voronoi-iso, whose design does it), and the per-face planarity and regularity.

#include <cstdint>

#include <nlohmann/json.hpp>

#include "gridshell/core/timings.h"
#include "gridshell/grids/baseline_kind.h"
#include "gridshell/grids/quad_aniso.h"
#include "gridshell/optimize/flat_panels.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/gridshell_output.h"

namespace gridshell {

struct BaselineOptions {
  BaselineKind kind = BaselineKind::quad;
  double length = 0;     ///< target total beam length (m), 0 = by spacing / radius / cells
  double spacing = 0;    ///< quad: plan spacing (m); quad-aniso: spacing on M′
  double angle_deg = 0;  ///< quad: rotation of the grid in plan
  double radius = 0;     ///< voronoi-iso, tri: cell size R (m)
  int cells = 0;         ///< voronoi-iso, tri: number of cells
  double max_size_change = QuadAnisoOptions{}.max_scale_change;  ///< quad-aniso (≥ 1)
  std::uint64_t seed = 1;
  PanelMode panels = PanelMode::free;
  /// quad-aniso: the design's field (field, field_file, field_options with D, A and the
  /// conventions), as build_design_options makes it (pipeline/design_settings.h).
  DesignOptions field;
};

struct Baseline {
  GridShellOutput out;  ///< mesh, raw, supports, planarity, regularity (analysis: the caller's)
  nlohmann::json quad_stats;  ///< quad-aniso: report.json `quad_aniso`; else null
  nlohmann::json flat_info;   ///< report.json `flat_panels` (null: free panels asked for)
  PanelShape panels;          ///< the panels' shape against the input surface (report.json)
  Timings timings;            ///< grid, flat_panels
};

/// Builds the baseline grid-shell of `options.kind` on `surface`. Throws Error for bad options
/// (e.g. quad without --length or --spacing) or input.
Baseline make_baseline(const Surface& surface, const BaselineOptions& options);

}  // namespace gridshell
