#pragma once
/// \file panel_sheets.h
/// The nested panels as a drawing, one layout for every format that shows it: panels.svg (the
/// page, y down) and panels.dxf (CAD, y up), full size in a design folder, and the model kit's
/// laser-cut panels (outlines at scale, with the laser's kerf).
///
/// Layout (page coordinates in metres of the drawing, y down from the top edge): the sheets
/// stacked top to bottom, `space` apart (0.1 m), each titled "sheet k" above it; every placed panel on
/// its sheet (fabrication/nesting.h), labelled with its id at its centroid; panels larger than
/// a sheet in a row below the sheets. `panels_dxf` draws the same outlines with y up
/// (y_dxf = height − y) in millimetres on the layers SHEETS, PANELS, OVERSIZE and LABELS.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "gridshell/exchange/dxf.h"
#include "gridshell/fabrication/nesting.h"

namespace gridshell::fabrication {

struct SheetFrame {
  int index = 0;
  double left = 0, top = 0, width = 0, height = 0;  ///< page rectangle [m]
};

struct DrawnOutline {
  int id = 0;
  int sheet = -1;  ///< −1: larger than a sheet, drawn in the oversize row
  bool oversize() const { return sheet < 0; }
  std::vector<Eigen::Vector2d> points;  ///< page coordinates [m]
  Eigen::Vector2d label = Eigen::Vector2d::Zero();
  double font = 0;  ///< label height [m]
};

struct PanelSheets {
  double width = 0, height = 0;  ///< the page [m]
  std::vector<SheetFrame> sheets;
  std::vector<DrawnOutline> outlines;  ///< every panel, placed ones first (sheet by sheet)
  double oversize_top = -1;            ///< top of the oversize row; −1 when there is none
  std::string title;
  double title_font = 0.03;  ///< height of the sheet titles [m]
  double space = 0.1;        ///< between two sheets [m]
  double stroke = 0.001;     ///< SVG line width [m]
};

struct PanelSheetOptions {
  /// Laser kerf [m]: every outline is offset outward by half of it (fabrication's
  /// offset_outline), so the part that falls out has the outline's size. 0 = as they are.
  double kerf = 0;
  double label_min = 0.01, label_max = 0.08;  ///< a panel label's height range [m]
  double title = 0.03;                         ///< the sheet titles' height [m]
  double space = 0.1;    ///< between two sheets, and around the oversize row [m]
  double stroke = 0.001;  ///< the SVG's line width [m] (a laser's hairline in the kit)
};

/// The layout of `outlines` (each a panel's flat outline [m], counter-clockwise; index = panel
/// id) as `nesting` placed them on sheets of `sheet`.
PanelSheets panel_sheets(const std::vector<std::vector<Eigen::Vector2d>>& outlines,
                         const Nesting& nesting, const SheetOptions& sheet,
                         const PanelSheetOptions& options = {});

/// The drawing as SVG (millimetres, 0.001 mm resolution).
std::string panels_svg(const PanelSheets& drawing);

/// The drawing as DXF entities (millimetres, y up).
exchange::DxfDrawing panels_dxf(const PanelSheets& drawing);

/// `outline` (counter-clockwise) offset outward by `distance` (≥ 0), corners mitred, the miter
/// limited to 4 × distance (beyond it the corner is bevelled: two points).
std::vector<Eigen::Vector2d> offset_outline(const std::vector<Eigen::Vector2d>& outline,
                                            double distance);

}  // namespace gridshell::fabrication
