#include "gridshell/pipeline/baseline_field.h"

#include <spdlog/spdlog.h>

#include "gridshell/fem/shell_solver.h"
#include "gridshell/field/field_io.h"
#include "gridshell/mesh/geometry.h"
#include "gridshell/optimize/projector.h"

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
  spdlog::info("[field] direction, density (D = {}), anisotropy (A = {})", o.field_options.D,
               o.field_options.A);
  return make_field(surface.mesh, stress, o.field_options);
}

std::optional<Surface> baseline_surface(const Surface& surface, const DesignOptions& options,
                                        double length) {
  if (!(length > 0) || options.field == FieldInput::file) return std::nullopt;
  DesignOptions o = options;
  o.tessellation.length = length;
  o.tessellation.radius = 0;
  o.tessellation.cells = 0;
  std::optional<Surface> coarse = design_analysis_surface(surface, o);
  if (coarse)
    spdlog::info("[coarsen] {} triangles to {} for the field and the extraction",
                 surface.mesh.num_faces(), coarse->mesh.num_faces());
  return coarse;
}

void move_onto_input(PolyMesh& grid, const TriMesh& coarse, const TriMesh& input) {
  const SurfaceProjector from(coarse), onto(input);
  const double tol = 1e-6 * bbox_diagonal(input.V);
  for (int v = 0; v < grid.num_vertices(); ++v) {
    const Vec3 x = grid.vertex(v);
    const bool boundary = from.has_boundary() && from.boundary_distance(x) <= tol;
    grid.V.row(v) = (boundary ? onto.closest_boundary_point(x) : onto.closest_point(x)).transpose();
  }
}

}  // namespace gridshell
