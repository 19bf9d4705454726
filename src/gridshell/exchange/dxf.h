#pragma once
/// \file dxf.h
/// Flat drawings as DXF files, the format laser cutters', water-jet and glass shops' CAM and
/// every CAD program open: closed outlines (LWPOLYLINE), lines and text labels on named,
/// coloured layers, in stated units (the header's $INSUNITS), AutoCAD 2000 ASCII, written
/// through dxflib (Debian libdxflib-dev). Coordinates are written with 16 decimals (dxflib);
/// the file appears atomically (written under a temporary name, then renamed).
///
/// Used for panels.dxf and beams.dxf in every design folder (fabrication/fabrication_files.h)
/// and for the model kit's laser-cut panels (kit/kit.h). Cost: linear in the entities.

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace gridshell::exchange {

enum class DxfUnits { millimetres, metres };

struct DxfLayer {
  std::string name;
  int colour = 7;  ///< AutoCAD colour index (1 red, 2 yellow, 3 green, 4 cyan, 5 blue, 7 black)
};

/// A polyline: closed (a cut outline) or open.
struct DxfPolyline {
  std::string layer;
  std::vector<Eigen::Vector2d> points;
  bool closed = true;
};

/// One line of text, its insertion point at the middle of its height and width.
struct DxfText {
  std::string layer;
  Eigen::Vector2d at = Eigen::Vector2d::Zero();
  double height = 1;  ///< in drawing units
  std::string text;
};

struct DxfDrawing {
  DxfUnits units = DxfUnits::millimetres;
  std::vector<DxfLayer> layers;  ///< every layer an entity names must be listed
  std::vector<DxfPolyline> polylines;
  std::vector<DxfText> texts;
};

/// Writes `drawing` to `path`. Throws Error(path) when it cannot be written, or when a number
/// is not finite or an entity names a layer that is not listed.
void write_dxf(const std::filesystem::path& path, const DxfDrawing& drawing);

}  // namespace gridshell::exchange
