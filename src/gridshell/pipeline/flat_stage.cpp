// The flat-panel stage with its fallback (pipeline/design.h, attempt_flat_panels).
#include <spdlog/spdlog.h>

#include "gridshell/pipeline/design.h"

namespace gridshell {

FlatPanelAttempt attempt_flat_panels(const PolyMesh& mesh, const std::vector<int>& supports,
                                     const TriMesh& surface, const SurfaceProjector& projector,
                                     const FlatPanelOptions& options) {
  FlatPanelAttempt a;
  a.info = {{"requested", "flat"}};
  try {
    FlatPanelResult f = flat_panels(mesh, supports, surface, projector, options);
    spdlog::info(
        "[flat panels] {} panels flat to {:.2g} mm in {} iterations ({} attempts), {} "
        "joints split, {} beams flipped, {} panels glazed as triangles",
        f.mesh.num_faces(), 1e3 * f.stats.out_of_plane_max, f.stats.iterations, f.stats.attempts,
        f.stats.split_joints, f.stats.flipped_beams, f.stats.triangulated_panels);
    a.info["panels"] = "flat";
    a.info["iterations"] = f.stats.iterations;
    a.info["converged"] = f.stats.converged;
    a.info["split_joints"] = f.stats.split_joints;
    a.info["flipped_beams"] = f.stats.flipped_beams;
    a.info["attempts"] = f.stats.attempts;
    a.info["triangulated_panels"] = f.stats.triangulated_panels;
    a.info["cells"] = mesh.num_faces();  // the panels before any was glazed as triangles
    a.info["surface_weight"] = f.stats.surface_weight;
    a.info["surface_distance_max_m"] = f.stats.surface_distance_max;
    a.info["shortest_beam_m"] = f.stats.shortest_beam;
    a.info["added_joints"] = f.stats.added_joints;
    a.info["energy_start"] = f.stats.energy_start;
    a.info["energy"] = f.stats.energy;
    a.info["min_det"] = f.stats.min_det;
    a.info["out_of_own_plane_max_m"] = f.stats.out_of_plane_max;
    a.flat = std::move(f);
  } catch (const FlatPanelsFailed& e) {
    // Said at info level: an objective-search candidate runs this stage too, and only the
    // design a command writes warns (app/common.h, warn_if_panels_kept_free).
    spdlog::info("[flat panels] {}: keeping the free panels", e.what());
    a.info["panels"] = "free";
    a.info["failure"] = e.what();
  }
  return a;
}

std::vector<double> per_flat_panel(const std::vector<double>& values,
                                   const std::vector<int>& source_face) {
  if (values.empty()) return {};
  std::vector<double> out(source_face.size());
  for (std::size_t f = 0; f < source_face.size(); ++f) out[f] = values.at(source_face[f]);
  return out;
}

}  // namespace gridshell
