#pragma once
/// \file exchange_files.h
/// What a design folder gives other programs besides the CSV files (fabrication_files.h):
///
/// - beams.dxf: the cut list drawn for the shop — every beam a bar of its cut length and its
///   section's outer depth, in cutting order (by section, then longest first), labelled with its
///   id, section, length [mm] and end joints (layers BEAMS and LABELS, millimetres);
/// - gridshell.glb: the grid-shell as a 3D model, beams as tubes of their sections and panels
///   as glass (exchange/glb.h).
///
/// panels.dxf, the nested panels, is drawn by panel_sheets.h like panels.svg.

#include "gridshell/exchange/dxf.h"
#include "gridshell/exchange/glb.h"
#include "gridshell/fabrication/fabrication_files.h"

namespace gridshell::fabrication {

/// The beams in cutting order: by section designation, then longest first, then id.
std::vector<int> cutting_order(const FabricationData& d);

/// beams.dxf's drawing.
exchange::DxfDrawing cut_list_dxf(const FabricationData& d);

/// gridshell.glb's model: each beam oriented by the panels beside it (the section's local z
/// along their mean normal, as the frame analysis orients an RHS).
exchange::GlbModel glb_model(const PolyMesh& mesh, const FabricationData& d);

}  // namespace gridshell::fabrication
