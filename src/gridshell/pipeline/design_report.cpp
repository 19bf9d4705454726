#include "gridshell/pipeline/design_report.h"

#include "gridshell/fabrication/fabrication_files.h"

namespace gridshell {

GridShellOutput design_output(const DesignResult& r) {
  GridShellOutput out;
  out.mesh = r.mesh;
  out.raw = r.raw;
  out.supports = r.supports;
  out.d_target = r.d_target;
  out.a_target = r.a_target;
  out.planarity = r.metrics.planarity;
  out.regularity = r.metrics.regularity;
  if (r.structure) add_structure(out, *r.structure);
  return out;
}

nlohmann::json design_report(const DesignResult& r, const DesignOptions& options) {
  nlohmann::json report;
  nlohmann::json mesh = mesh_block(design_output(r));
  mesh["planarity_mean_raw"] = r.raw_metrics.planarity_mean;
  mesh["regularity_mean_raw"] = r.raw_metrics.regularity_mean;
  mesh["edge_length_cv_raw"] = r.raw_metrics.edge_length_cv;
  mesh["total_length_raw_m"] = r.raw_metrics.total_length;
  const Tessellation& t = r.tessellation;
  mesh["hex_share_interior_raw"] = t.quality.hex_share_interior;
  mesh["radius_m"] = t.radius;
  mesh["lloyd_iterations"] = t.iterations;
  mesh["lloyd_converged"] = t.converged;
  mesh["support_mesh_vertices"] = t.support_vertices;
  mesh["length_runs"] = t.length_runs;
  if (options.tessellation.length > 0) {
    mesh["target_length_m"] = options.tessellation.length;
    mesh["length_error"] = r.metrics.total_length / options.tessellation.length - 1;
  }
  report["mesh"] = mesh;
  report["design"] = r.details;
  report["design"]["regularized"] = options.regularize && !options.planarize;
  report["design"]["planarized"] = options.planarize;
  report["design"]["restretch"] = options.regularize_options.restretch;
  report["design"]["size_evening"] = options.regularize_options.size_evening;
  report["design"]["analysis"] = to_string(options.analyze);
  if (r.structure) report["structure"] = structure_block(*r.structure);
  return report;
}

nlohmann::json timings_block(const Timings& timings, const Timings& extra, double total) {
  Timings all = extra;
  for (const auto& [stage, s] : timings) all.add(stage, s);
  nlohmann::json block = all;
  block["total"] = total;
  return block;
}

nlohmann::json fabrication_report(const std::filesystem::path& dir, const PolyMesh& mesh,
                                  const std::vector<int>& supports,
                                  const analysis::FrameResult* structure,
                                  const analysis::GridshellFrameOptions& frame,
                                  const fabrication::SheetOptions& sheet) {
  fabrication::FabricationFileOptions o;
  o.sheet = sheet;
  o.bar_diameter = frame.diameter;
  o.bar_density = frame.density;
  fabrication::BeamResults beams;
  if (structure) {
    beams.axial_force = structure->axial_force;
    for (const checks::MemberCheck& c : structure->checks.members) {
      beams.utilisation.push_back(c.section);
      beams.buckling_utilisation.push_back(c.buckling);
    }
  }
  return fabrication::write_fabrication_files(dir, mesh, supports, beams, o);
}

}  // namespace gridshell
