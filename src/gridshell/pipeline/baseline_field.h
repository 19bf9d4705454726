#pragma once
/// \file baseline_field.h
/// The field of a design, for baselines that follow it (`baseline --kind quad-aniso`): the
/// design's stress stage and field stage at (D, A) with its conventions, without tessellating.

#include "gridshell/field/field.h"
#include "gridshell/mesh/mesh.h"
#include "gridshell/pipeline/design.h"

namespace gridshell {

/// Stress (shell analysis, or the file of `options.field_file`) → make_field at (options.D,
/// options.A) with options.field_options' conventions. Unlike run_design, D = A = 1 keeps the
/// stress directions u (d = a = 1): an isotropic grid that still follows the stress. With
/// FieldInput::uniform: uniform_field. Throws Error as check_design_options and make_field do.
Field baseline_field(const Surface& surface, const DesignOptions& options);

}  // namespace gridshell
