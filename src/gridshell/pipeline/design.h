#pragma once
/// \file design.h
/// `gridshell design`: the paper's pipeline in order, each stage timed. For now the field stage
/// is the uniform one (M' = M: an isotropic centroidal Voronoi tessellation); the stress field,
/// regularization and structural analysis plug in here as their modules land.

#include <string>
#include <utility>
#include <vector>

#include "gridshell/mesh/mesh.h"
#include "gridshell/voronoi/tessellation.h"

namespace gridshell {

struct DesignOptions {
  std::string field = "uniform";  ///< "uniform" (only one available yet); "stress" comes later
  double D = 1;                   ///< density ratio; only 1 until the field stage lands
  double A = 1;                   ///< anisotropy ratio; only 1 until the field stage lands
  std::string analyze = "none";   ///< "none" only for now
  bool regularize = true;         ///< recorded; regularization is not implemented yet
  TessellationOptions tessellation;
};

/// Per-face shape metrics of a polygon mesh (GUIDE stage 10 definitions).
struct FaceMetrics {
  /// Mean over faces of (mean distance of the face's vertices to its least-squares plane) /
  /// (half its perimeter). 0 for planar faces.
  double planarity_mean = 0;
  /// Mean over faces of (Σ squared distances of its vertices, projected on that plane, to the
  /// best rigidly aligned regular polygon with the same sides and perimeter) / (face area).
  double regularity_mean = 0;
};
FaceMetrics face_metrics(const PolyMesh& mesh);

struct DesignResult {
  Tessellation raw;              ///< the tessellation before regularization (gridshell_raw.obj)
  PolyMesh mesh;                 ///< the final grid-shell (identical to raw.mesh for now)
  std::vector<int> supports;     ///< support joints of `mesh`, sorted
  std::vector<double> d_target;  ///< per face: rescaled density the field asked for (≥ 1)
  std::vector<double> a_target;  ///< per face: rescaled anisotropy the field asked for (≥ 1)
  FaceMetrics metrics;           ///< of `mesh`
  /// Stage name → seconds, in pipeline order (the app adds "load", "write" and "total").
  std::vector<std::pair<std::string, double>> timings;
};

/// Runs the pipeline on `surface`. Throws Error for options that are not available yet
/// (subject = the option) or bad input.
DesignResult run_design(const Surface& surface, const DesignOptions& options);

}  // namespace gridshell
