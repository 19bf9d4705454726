#pragma once
/// \file figures.h
/// The pictures a run writes into DIR/figures/ (docs/figures.md), drawn with Cairo
/// (figures/plot.h), each with a heading saying what it shows and the run's title below:
///
///   - top.png             plan view; beams coloured by linear axial force (compression red,
///                         tension blue, as in the paper), supports as squares, scale bar in m;
///                         the input surface's boundary (thin green) when `surface` is given;
///   - perspective.png     a fixed 3D view (azimuth −60°, elevation 30°), panels as light glass,
///                         beams by axial force, drawn far to near; supports as triangles;
///   - field.png           the design field on the input surface (plan): density d by colour,
///                         short segments along the stretch direction u whose length and
///                         opacity grow with the anisotropy a;
///   - buckling_mode.png   the first buckling mode at 10 % of the span over the undeformed grid
///                         (light grey), coloured by the mode's displacement, λ₁ in the heading;
///   - load_path.png       the non-linear path: λ against the largest displacement [mm], the
///                         linear response, λ_LBA (dashed), the displacement limit and λ_δ;
///   - lambda_heatmap.png, delta_heatmap.png (sweep): mean λ and δ over (D, A), values written
///                         in the cells.
///
/// A figure whose data is absent (no analysis, no LBA, no path, no field) is skipped, not an
/// error. Everything is deterministic; no figure changes a result. Cost (1600 × 1200): ~0.1 s
/// per figure, most of it the PNG encoding.

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/field/field.h"
#include "gridshell/figures/plot.h"
#include "gridshell/mesh/mesh.h"
#include "gridshell/pipeline/sweep.h"

namespace gridshell::figures {

struct FigureOptions {
  bool enabled = true;  ///< false: write_figures draws nothing (`--figures none`)
  int width = 1600;     ///< pixels
  int height = 1200;    ///< pixels
};

/// Parses the `--figures` word: "WxH" in pixels (each 64 … 8192, e.g. 1600x1200) or "none".
/// Throws Error("--figures", …).
FigureOptions parse_figure_options(const std::string& word);

/// What the figures of one grid-shell are drawn from. Null pointers are absent data.
struct FigureInput {
  std::string title{};                  ///< what was run: command, surface, key options
  const PolyMesh* gridshell = nullptr;  ///< joints = vertices (= frame model nodes), panels = faces
  /// Beams as joint pairs in frame member order; empty = the grid-shell's topology edges
  /// (Topology order: the members of analysis::gridshell_frame).
  std::vector<std::array<int, 2>> beams{};
  std::vector<int> supports{};                       ///< supported joints
  const analysis::FrameResult* structure = nullptr;  ///< axial forces, modes, path
  const TriMesh* surface = nullptr;  ///< the input surface (of `field`; its edge in top.png)
  const Field* field = nullptr;                      ///< per triangle of `surface`
};

/// The data → pixel mapping of top.png (plan x, y in metres, equal scale) for joints `V`.
Axes plan_axes(const Points& V, const FigureOptions& options);

/// top.png. Needs `gridshell`; beams are grey when there is no analysis.
Canvas draw_plan(const FigureInput& in, const FigureOptions& options);
/// perspective.png. Needs `gridshell`.
Canvas draw_perspective(const FigureInput& in, const FigureOptions& options);
/// field.png. Needs `surface` and `field` of the same size.
Canvas draw_field(const FigureInput& in, const FigureOptions& options);
/// buckling_mode.png. Needs `gridshell` and `structure` with a buckling mode.
Canvas draw_buckling_mode(const FigureInput& in, const FigureOptions& options);
/// load_path.png. Needs `structure` with a non-linear path of at least two points.
Canvas draw_load_path(const FigureInput& in, const FigureOptions& options);

/// What a heatmap shows: `value_label` with its unit, `scale` multiplies the grid's values
/// (e.g. 1000 for m → mm).
struct HeatmapLabels {
  std::string heading, subtitle, value_label;
  double scale = 1;
};
/// A heatmap of grid.mean over (D, A): one cell per pair with its value written in it, grey
/// with "–" where there is no value.
Canvas draw_heatmap(const SweepGrid& grid, const HeatmapLabels& labels,
                    const FigureOptions& options);

/// Figures as PNG bytes, each with its file name ("top.png").
using EncodedFigures = std::vector<std::pair<std::string, std::string>>;
/// The figures that read only the linear analysis of `in.structure` (its axial forces): top.png
/// and perspective.png, drawn and encoded on the calling thread — a caller makes them while the
/// LBA or the path runs (`analyze`: FrameAnalysisOptions::after_linear) and hands them to
/// write_figures. Empty when `options.enabled` is false or there is no grid-shell.
EncodedFigures encode_linear_figures(const FigureInput& in, const FigureOptions& options);
/// Draws every figure whose data `in` has into DIR/figures/ and returns their paths relative
/// to DIR ("figures/top.png", …) in a fixed order; nothing when `options.enabled` is false.
/// `linear`: top.png and perspective.png as encode_linear_figures made them (the same bytes as
/// drawing them here from the same axial forces), written first instead of drawn again.
/// Throws Error for a bad size or an unwritable folder.
std::vector<std::string> write_figures(const std::filesystem::path& dir, const FigureInput& in,
                                       const FigureOptions& options = {},
                                       std::optional<EncodedFigures> linear = std::nullopt);

/// The sweep's figures: lambda_heatmap.png and delta_heatmap.png (δ in mm) of `rows` in
/// DIR/figures/; returns their paths relative to DIR.
std::vector<std::string> write_sweep_figures(const std::filesystem::path& dir,
                                             const std::vector<SweepRow>& rows,
                                             const std::string& title,
                                             const FigureOptions& options = {});

}  // namespace gridshell::figures
