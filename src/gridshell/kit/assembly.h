#pragma once
/// \file assembly.h
/// The kit's assembly page (OUT/assembly.html): the joints in the order to put them together,
/// each step naming the joint to place and the rods that join it to what already stands.
///
/// Order: the supported joints first (they stand on the base board), sorted by id; then, as in
/// a breadth-first search over the beams, every joint joined to the assembled part, the one
/// with most rods into it first (the stiffest next piece), ties by height (lowest first), then
/// id. A joint glued to the one just placed by a printed bridge (kit.h, "Bridges") comes next,
/// before any other: glued pairs go in together (a chain of bridges in the order it is reached).
/// A joint not connected to any support (a free part of the grid) starts a new group.
///
/// The page is one self-contained file (inline SVG and script, nothing fetched), like
/// report.html: a plan view of the grid-shell with the assembled part drawn dark and the
/// current joint and its new rods in red, step buttons and a slider, and the whole list as a
/// table that prints. Cost: O(joints + beams).

#include <string>
#include <vector>

#include "gridshell/kit/kit.h"

namespace gridshell::kit {

struct AssemblyStep {
  int joint = 0;
  std::vector<int> rods;   ///< rods (beam ids) joining it to joints placed before it
  std::vector<int> glued;  ///< bridged beams gluing it to joints placed before it
};

/// The assembly order of the frame's joints (every joint with a beam appears once); `bridged`
/// (per beam id, bridged_beams; empty: none) marks the beams that are glued, not rods.
std::vector<AssemblyStep> assembly_order(const KitFrame& frame,
                                         const std::vector<char>& bridged = {});

/// The page's HTML.
std::string assembly_html(const KitFrame& frame, const std::vector<AssemblyStep>& steps,
                          const std::vector<Rod>& rods, const KitOptions& options);

}  // namespace gridshell::kit
