#include "gridshell/pipeline/buildability_report.h"

namespace gridshell {

nlohmann::json buildability_block(const PolyMesh& mesh,
                                  const std::vector<std::string>& member_sections,
                                  const BuildabilityOptions& options) {
  const Buildability b = buildability(mesh, member_sections, options);
  nlohmann::json j;
  j["face_planarity"] = b.face_planarity;
  j["joints"] = b.joints;
  j["joint_clusters"] = b.joint_clusters;
  nlohmann::json by = nlohmann::json::object();
  for (const ValenceClusters& v : b.by_valence) by[std::to_string(v.valence)] = v.clusters;
  j["joint_clusters_by_valence"] = by;
  j["beam_length_similarity"] = b.beam_length_similarity;
  j["distinct_sections"] = b.distinct_sections;
  j["joint_tolerance"] = options.joint_tolerance;
  j["min_beam_length_m"] = options.min_beam_length;
  j["short_beams"] = b.short_beams;
  j["capped_comparisons"] = b.capped_comparisons;
  j["benchmark"] = "FreeGrid (IASS 2023), freeGridBuildability.py";
  // The names of CONTRACT.md for the same three figures.
  j["planarity"] = b.face_planarity;
  j["beam_similarity"] = b.beam_length_similarity;
  j["sections_distinct"] = b.distinct_sections;
  return j;
}

}  // namespace gridshell
