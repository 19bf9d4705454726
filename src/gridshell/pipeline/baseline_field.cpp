#include "gridshell/pipeline/baseline_field.h"

#include <spdlog/spdlog.h>

#include "gridshell/fem/shell_solver.h"
#include "gridshell/field/field_io.h"

namespace gridshell {

Field baseline_field(const Surface& surface, const DesignOptions& o) {
  check_design_options(o);
  if (o.field == FieldInput::uniform) return uniform_field(surface.mesh);
  StressField stress;
  if (o.field == FieldInput::file) {
    stress = read_field_file(o.field_file, surface.mesh);
  } else {
    spdlog::info("[stress] shell analysis of {} triangles", surface.mesh.num_faces());
    stress = fem::analyze_surface_stress(surface, o.shell).stress;
  }
  FieldOptions fo = o.field_options;
  fo.D = o.D, fo.A = o.A;
  spdlog::info("[field] direction, density (D = {}), anisotropy (A = {})", o.D, o.A);
  return make_field(surface.mesh, stress, fo);
}

}  // namespace gridshell
