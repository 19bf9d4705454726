#pragma once
/// \file nesting.h
/// Flat panels nested on rectangular sheets (glass or laser-cut plates) of one stated size.
///
/// Method: each outline is first turned to its minimum-area bounding rectangle (an edge of its
/// convex hull along x, the rectangle lying landscape), then the rectangles, grown by `gap`, are
/// packed by first-fit decreasing height shelf packing: sorted by height (then width, then id),
/// each goes onto the first shelf of the first sheet where it fits (upright or turned 90°);
/// otherwise a new shelf opens on the first sheet with room, otherwise a new sheet. Rectangles
/// never overlap, so neither do the outlines they contain; everything stays `margin` inside the
/// sheet. A panel whose rectangle fits the sheet in neither orientation is reported as oversize
/// (sheet −1) and not placed. Cost: O(panels · shelves).

#include <string>
#include <vector>

#include <Eigen/Core>

namespace gridshell::fabrication {

/// The default `--sheet` of design, baseline and analyze: 2.5 m × 1.25 m, the size of
/// SheetOptions{}.
inline constexpr const char* kDefaultSheet = "2.5x1.25";

struct SheetOptions {
  double width = 2.5;    ///< sheet size [m] (x)
  double height = 1.25;  ///< [m] (y)
  double gap = 0.01;     ///< clear distance between panels' bounding boxes [m]
  double margin = 0.01;  ///< clear distance from the sheet's edges [m]
};

/// Parses `--sheet WxH` (metres, e.g. "2.5x1.25"); throws Error("--sheet").
SheetOptions parse_sheet(const std::string& word);

/// Where one outline goes: sheet coordinates p' = R(rotation) p + offset, for outline points p.
struct Placement {
  int sheet = -1;          ///< 0-based; −1 = oversize, not placed
  double rotation = 0;     ///< [rad], counter-clockwise
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();  ///< [m] from the sheet's lower-left corner
};

struct Nesting {
  std::vector<Placement> placements;  ///< per outline
  int sheets = 0;                     ///< sheets used
  std::vector<int> oversize;          ///< outlines that fit no sheet
  double used_area = 0;               ///< Σ placed outline areas [m²]
};

/// Nests the outlines (2D polygons) on sheets. Throws Error("--sheet") for a non-positive size.
Nesting nest_panels(const std::vector<std::vector<Eigen::Vector2d>>& outlines,
                    const SheetOptions& options = {});

/// The outline placed on its sheet.
std::vector<Eigen::Vector2d> placed_outline(const std::vector<Eigen::Vector2d>& outline,
                                            const Placement& placement);

}  // namespace gridshell::fabrication
