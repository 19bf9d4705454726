#pragma once
/// \file load_cases.h
/// The named load cases and EN 1990 combinations of `--loads eurocode` (docs/checks.md, "Loads
/// and combinations"):
///
/// * G1 — the bars' self-weight (each bar's weight at its two ends), permanent;
/// * G2 — glass and cladding per m² of panel surface, permanent;
/// * S — snow, undrifted (EN 1991-1-3 §5.3.2 / §5.3.3 case (i)): s_k μ1(α) per m² of plan, μ1 of
///   Table 5.2 from each panel's slope α;
/// * S_x-, S_x+, S_y-, S_y+ — snow, drifted: the roof's plan is halved through its centre across
///   the axis; the named half (x+: x above the centre) is leeward and takes the full shape
///   factor, the other half the windward half of it. The shape factor is that of the cylindrical
///   roof (§5.3.5, μ3 = 0.2 + 10 h/b ≤ 2.0, zero where the slope exceeds 60°) when the roof is
///   curved along that axis enough for μ3 to exceed 0.8, else that of the pitched roof (§5.3.3,
///   Figure 5.3 cases (ii)/(iii): μ1(α) and 0.5 μ1(α)). h is the rise of the roof along the axis
///   (its highest joint above the highest joint within 5 % of the plan extent from either end of
///   the axis: a barrel's rise across its generators, zero along them) and b the plan extent
///   along the axis. For free-form roofs this reads each plan axis as the section of a
///   cylindrical or pitched roof; μ3 uniform over each half (the code's drift shape within a
///   half is not uniform: the uniform peak is conservative for the total load).
/// * file cases (`--load-case NAME=FILE.csv`): pressures on the input surface's vertices,
///   interpolated over the panels (read_load_case_file, load_case_forces), or joint forces or
///   panel pressures (analyze); variable (ψ0 = 0.6, γQ = 1.5) unless marked `NAME:permanent`.
///
/// Combinations (EN 1990 6.4.3.2 (6.10) and 6.5.3 (6.14b), Annex A1 Table A1.1/A1.2(B)):
/// for each leading variable action (each snow arrangement; each variable file case) one ULS
/// = 1.35 ΣG + 1.5 Q_lead + Σ 1.5 ψ0 Q_other and one SLS (characteristic) = ΣG + Q_lead +
/// Σ ψ0 Q_other. Snow is one action: its arrangements are alternatives, never together; it
/// accompanies a leading file case with its undrifted arrangement and ψ0 = 0.5 (sites at most
/// 1000 m above sea level, CEN; Finland, Iceland, Norway, Sweden and higher sites: 0.7). Each
/// variable file case is its own action and accompanies every other leading action (give
/// mutually exclusive cases — wind from two directions — in separate runs). A variable file case
/// whose net vertical force points up (suction) also leads a combination with γG = 1.0
/// (favourable permanent actions, Table A1.2(B)). Names: "ULS" / "SLS" lead with S (the primary
/// combination, analysed in full), "ULS_S_x+" etc., "ULS_NAME" for a file case, "ULS_NAME_Ginf".

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gridshell/mesh/mesh.h"

namespace gridshell::analysis {

/// A load case read from a file (`--load-case NAME=FILE.csv`).
struct FileLoadCase {
  /// What the file's rows refer to: `vertex,pressure_kN_m2` on the input surface, or (analyze)
  /// `joint,fx_kN,fy_kN,fz_kN` and `panel,pressure_kN_m2` on the grid-shell itself.
  enum class Given { surface_vertex, joint, panel };
  std::string name, path;
  bool permanent = false;
  double psi0 = 0.6;  ///< combination factor of a variable case (wind: EN 1990 Table A1.1)
  Given given = Given::surface_vertex;
  std::vector<int> ids;          ///< as read (row order)
  std::vector<double> pressure;  ///< [kN/m²] per row (surface_vertex, panel)
  std::vector<Vec3> force;       ///< [kN] per row (joint)
  /// surface_vertex: the input surface the ids refer to (set by attach_surface).
  std::shared_ptr<const TriMesh> surface;
};

/// Parses `NAME=FILE.csv` or `NAME:permanent=FILE.csv` and reads the file (header line names
/// the columns; one row per id). Throws Error("--load-case" or the file, one line) for a bad
/// spec, a missing or unreadable file, missing columns, non-numbers, NaN, negative or duplicate
/// ids, or no rows.
FileLoadCase read_load_case_file(const std::string& spec);

/// Checks a surface_vertex case against the input surface (every vertex given once, ids in
/// range) and keeps the surface for the interpolation. Throws Error(file) otherwise.
void attach_surface(FileLoadCase& c, const TriMesh& surface);

/// The case's nodal forces [N] on the grid `mesh` (one per vertex). Pressures act on each panel
/// along its normal (oriented as the input surface's, itself oriented to face up overall), a
/// positive pressure pushing onto the roof; each panel's force p × area goes 1/n to each of its
/// n corners. surface_vertex: p is the input surface's vertex pressures interpolated
/// (barycentrically) at the closest point of the input surface to the panel's area centroid
/// (searched among the triangles around the 8 input vertices nearest the centroid). joint:
/// the forces as given; panel: the panel's pressure. Throws Error(file) for ids outside the grid.
std::vector<Vec3> load_case_forces(const PolyMesh& mesh, const FileLoadCase& c);

/// One named load case as nodal forces [N] per vertex of the grid.
struct LoadCase {
  std::string name;
  bool permanent = false;
  double psi0 = 0;     ///< combination factor ψ0 (variable cases)
  std::string action;  ///< cases of one action are alternatives ("snow"; a file case: its name)
  std::string clause;  ///< where it comes from (report and frame.json)
  std::vector<Vec3> F;
};

/// An EN 1990 combination: factor × case.
struct LoadCombination {
  std::string name;
  bool uls = true;
  std::string leading;  ///< the leading variable case
  std::vector<std::pair<std::string, double>> factors;
};

/// Snow shape factor of a cylindrical roof, EN 1991-1-3 §5.3.5(3): 0.2 + 10 h/b, at most 2.0.
double cylindrical_snow_factor(double rise, double width);

/// The snow arrangement of one half (see the file comment): per face the shape factor μ, for
/// `axis` 0 (x) or 1 (y) and `side` −1 or +1 (the leeward half); axis < 0: undrifted.
/// `cylindrical` (out, may be null): whether §5.3.5 applied.
std::vector<double> snow_shape_factors(const PolyMesh& mesh, int axis, int side,
                                       bool* cylindrical = nullptr);

/// Vertical nodal forces [N] of snow with shape factors `mu` per face and s_k [kN/m²] on plan.
std::vector<Vec3> snow_forces(const PolyMesh& mesh, const std::vector<double>& mu, double s_k);

/// The combinations of `cases` (see the file comment), primary "ULS" first, then "SLS".
std::vector<LoadCombination> eurocode_combinations(const std::vector<LoadCase>& cases);

/// Σ factor × case as nodal forces [N] per vertex. Throws Error for an unknown case name.
std::vector<Vec3> combine(const std::vector<LoadCase>& cases, const LoadCombination& c);

}  // namespace gridshell::analysis
