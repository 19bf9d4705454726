#pragma once
/// \file buildability.h
/// The buildability figures of a grid-shell as the FreeGrid benchmark defines them (IASS 2023
/// steel grid-shell benchmark, Bruno et al.; its public script `freeGridBuildability.py` in
/// github.com/flaccone/freeGrid, whose joint similarity follows Liu et al., Engineering
/// Structures 2023). Joints are the mesh's vertices, beams its unique edges (Topology edges),
/// panels its faces. docs/buildability.md gives the same definitions with measured figures.
///
/// - **face_planarity** = 1 + mean over all faces f of Δ(f), Δ(f) = (mean over the corners of
///   the distance to the face's best-fit plane) / (half the face's perimeter), i.e.
///   optimize/metrics.h `polygon_planarity`. A triangle counts as Δ = 0 (exactly, as in the
///   benchmark) and is part of the mean. 1 = every panel flat.
/// - **joints**: the vertices that end at least one beam (every vertex of a clean mesh).
/// - **joint_clusters**: the number of clusters of congruent joints. A joint's star is the set of
///   unit vectors along its beams. Two stars of the same valence k are compared by the
///   benchmark's distance: the smallest, over the k! ways to pair their beams, of the
///   root-mean-square distance between paired unit vectors after the best proper rotation
///   (Kabsch; mirror images are different joints). Stars of different valence are never in one
///   cluster. Clusters are counted per valence and summed. The benchmark clusters each valence
///   by farthest-point sampling (Gonzalez) until every star is within δ = 0.01 of a centre; here
///   a leader clustering does the same in bounded time: stars in joint order, each joins the
///   first existing centre within δ or becomes a new centre. Both results are δ-nets of the same
///   set (every star within δ of a centre, centres more than δ apart), so they agree exactly
///   whenever the joints form groups of diameter ≤ δ lying more than 2δ apart (a regular grid,
///   a grid with a few joint types); in general they are within the spread of δ-nets.
/// - **beam_length_similarity** = 1 + s/m over the beams longer than `min_beam_length` (the
///   benchmark leaves out edges of 0.1 m or less), s the sample standard deviation (n − 1),
///   m the mean. 1 = all beams equally long; 1 when fewer than two beams count.
/// - **distinct_sections**: the number of different member sections; the caller names each
///   beam's section (empty = every member the same section: 1).
///
/// Cost: O(Σ face sizes) for planarity and lengths. Joint clustering: a star's sorted pairwise
/// dot products differ from those of any star within δ by at most √(2k)·δ each, so centres are
/// hashed by valence and their three largest dot products on a grid of that step; a star is
/// compared only with the centres of the 27 cells around its own whose whole sorted list is
/// within the bound, by a search over pairings pruned by the same bound (a handful of 3 × 3
/// SVDs for the valences of grid-shells), capped by `max_search_nodes` and `max_candidates`.
/// About linear in the joints: 20 000 joints in 0.03–0.4 s (bench/buildability_bench.cpp).
/// Single-threaded; deterministic.
/// Throws Error("buildability", …) for options out of range, a face index out of range, a
/// non-finite joint and a section list whose length is not the number of beams.

#include <string>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell {

struct BuildabilityOptions {
  /// δ: two stars are congruent when their distance (above) is at most this; the benchmark's
  /// value (a root-mean-square distance of unit vectors: about 0.57° of beam direction).
  /// Range [1e-6, 1].
  double joint_tolerance = 0.01;
  /// Beams of this length or shorter (m) are left out of beam_length_similarity, as in the
  /// benchmark (which assumes metres). ≥ 0.
  double min_beam_length = 0.1;
  /// Bound on the work of one pairing search (a star against a centre), in dot products
  /// checked; a search that reaches it counts the two as different (`capped_comparisons`).
  /// Never reached by grids whose joints have at most 8 beams. ≥ 1.
  long max_search_nodes = 100000;
  /// Bound on the centres a star is compared with; past it the star becomes a centre of its own
  /// (`capped_comparisons`). Never reached by the grids of docs/buildability.md. ≥ 1.
  int max_candidates = 2000;
};

/// Clusters of one valence.
struct ValenceClusters {
  int valence = 0;
  int joints = 0;    ///< joints of this valence
  int clusters = 0;  ///< clusters among them
};

struct Buildability {
  double face_planarity = 1;                ///< 1 + mean Δ(f)
  int joints = 0;                           ///< vertices that end a beam
  int joint_clusters = 0;                   ///< Σ over valences
  std::vector<ValenceClusters> by_valence;  ///< ascending valence
  double beam_length_similarity = 1;        ///< 1 + s/m
  int beams = 0;                            ///< all beams (Topology edges)
  int short_beams = 0;                      ///< beams ≤ min_beam_length, not in the length figure
  int distinct_sections = 1;
  /// Per vertex: its cluster (0 … joint_clusters − 1, numbered in order of creation), −1 for a
  /// vertex that ends no beam.
  std::vector<int> joint_cluster;
  int capped_comparisons = 0;  ///< stars whose search hit a cap above (normally 0)
};

/// The figures above for `mesh`. `member_sections[b]` names the section of beam b (Topology
/// edge b, beams.csv's order); empty = one section for all.
Buildability buildability(const PolyMesh& mesh, const std::vector<std::string>& member_sections,
                          const BuildabilityOptions& options = {});

/// The benchmark's distance between two stars (lists of unit vectors): the smallest over all
/// pairings of the RMS distance after the best proper rotation. Infinity when the valences
/// differ, 0 for two empty stars. Exhaustive over the k! pairings: the reference for tests;
/// throws Error("buildability", …) above 9 beams.
double joint_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

/// Result of cluster_joints.
struct JointClusters {
  int clusters = 0;
  std::vector<ValenceClusters> by_valence;  ///< ascending valence
  std::vector<int> cluster;                 ///< per star, 0 … clusters − 1
  int capped_comparisons = 0;
};

/// The leader clustering above of stars (lists of unit vectors; any order, any valence).
JointClusters cluster_joints(const std::vector<std::vector<Vec3>>& stars,
                             const BuildabilityOptions& options = {});

}  // namespace gridshell
