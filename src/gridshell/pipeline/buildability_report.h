#pragma once
/// \file buildability_report.h
/// report.json's `buildability` block (docs/buildability.md): the FreeGrid benchmark's
/// buildability figures of a grid-shell (optimize/buildability.h), written by design and
/// baseline.
///
/// Keys: face_planarity, joints, joint_clusters, joint_clusters_by_valence ({"3": n, …}),
/// beam_length_similarity, distinct_sections, joint_tolerance (δ of the joint clustering),
/// min_beam_length_m (beams this short or shorter are not in the length figure), short_beams,
/// capped_comparisons (0 unless a joint search hit its bound), benchmark (where the definitions
/// come from); and CONTRACT.md's names of three of them: planarity (= face_planarity),
/// beam_similarity (= beam_length_similarity), sections_distinct (= distinct_sections).
/// Cost: that of `buildability` (about linear in the joints).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gridshell/mesh/mesh.h"
#include "gridshell/optimize/buildability.h"

namespace gridshell {

/// The block for `mesh`; `member_sections[b]` is the section designation of beam b (Topology
/// edge b, beams.csv's order), empty when every member has the same section.
nlohmann::json buildability_block(const PolyMesh& mesh,
                                  const std::vector<std::string>& member_sections,
                                  const BuildabilityOptions& options = {});

}  // namespace gridshell
