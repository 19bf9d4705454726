#pragma once
/// \file baseline_field.h
/// The field of a design, for baselines that follow it (`baseline --kind quad-aniso`): the
/// design's stress stage and field stage at (D, A) with its conventions, without tessellating;
/// and the surface they run on — design's coarsened analysis copy of a fine input — with the
/// step that moves the grid built there back onto the input.

#include <optional>

#include "gridshell/field/field.h"
#include "gridshell/mesh/mesh.h"
#include "gridshell/pipeline/design.h"

namespace gridshell {

/// Stress (shell analysis, or the file of `options.field_file`) → make_field with
/// options.field_options (its D, A and conventions). Unlike run_design, D = A = 1 keeps the
/// stress directions u (d = a = 1): an isotropic grid that still follows the stress. With
/// FieldInput::uniform: uniform_field. Throws Error as check_design_options and make_field do.
Field baseline_field(const Surface& surface, const DesignOptions& options);

/// The surface such a baseline is built on for a total length `length` (m): the design's
/// coarsened analysis copy (design_analysis_surface) when the input is much finer than cells of
/// that length need and the field is not a file (a file gives values per input triangle), else
/// nothing (the input itself). A fine input otherwise pays its resolution in the shell analysis
/// and in every lattice start of the quad extraction, and its field would not be the design's.
std::optional<Surface> baseline_surface(const Surface& surface, const DesignOptions& options,
                                        double length);

/// Joints of a grid built on `coarse` (a coarsened copy of `input`) moved onto `input`: each to
/// its closest point, those on coarse's boundary to input's boundary (coarse's boundary is a
/// chord of input's where input's boundary vertices were removed).
void move_onto_input(PolyMesh& grid, const TriMesh& coarse, const TriMesh& input);

}  // namespace gridshell
