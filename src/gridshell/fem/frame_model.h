#pragma once
/// \file frame_model.h
/// The structural model of a rigid-jointed 3D frame (a grid-shell): nodes, members with their
/// sections and materials, supports and nodal loads. SI units unless a model file says
/// otherwise (then every quantity is in that file's consistent units).
///
/// Section axes: local x runs from node i to node j; local z is the member's `up` when it has one,
/// else its section's `up`, else the default (global z, or global x for a (nearly) vertical
/// member), made orthogonal to x; local y = z × x. Iy resists deflection along local z (an RHS's
/// height h lies along z), Iz along local y, J is the torsion constant. docs/frame.md.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "gridshell/mesh/mesh.h"
#include "gridshell/sections/sections.h"

namespace gridshell::fem {

struct FrameSection {
  std::string name;
  double A = 0;            ///< area [m²]
  double Iy = 0;           ///< second moment about local y [m⁴]
  double Iz = 0;           ///< second moment about local z [m⁴]
  double J = 0;            ///< torsion constant [m⁴]
  Vec3 up = Vec3::Zero();  ///< local z hint; zero = default rule
  /// Outer-fibre distance [m] for the elastic section modulus W = I / c of the member checks
  /// (checks/member_checks.h); 0 = that of the solid circle of area A (√(A/π)).
  double c = 0;
  /// The shape it was made from (sections/sections.h): a bar, CHS or RHS, which the member checks
  /// use (class, plastic moduli, buckling curve); empty = given only by its constants (MODEL.json
  /// {A, Iy, Iz, J}), checked like the solid bar.
  std::optional<sections::Section> profile;
};

/// Solid circular section of diameter d: A = πd²/4, Iy = Iz = πd⁴/64, J = 2I (profile: bar d).
FrameSection circle_section(double diameter, const std::string& name = "circle");
/// The section of a profile: A, Iy, Iz and J = It from sections::properties, c = the outer-fibre
/// distance; `name` empty = its designation. Throws Error("section") for an invalid profile.
FrameSection profile_section(const sections::Section& profile, const std::string& name = "");

struct FrameMaterial {
  std::string name;
  double E = 0;        ///< Young's modulus [Pa]
  double nu = 0.3;     ///< Poisson's ratio (G = E / (2(1 + nu)))
  double density = 0;  ///< [kg/m³]
  double fy = 0;       ///< yield strength for the member checks [Pa]; 0 = the checks' default
};

enum class MemberType { beam, truss };

struct FrameMember {
  int i = -1, j = -1;  ///< node ids (0-based)
  int section = 0;     ///< index into FrameModel::sections
  int material = 0;    ///< index into FrameModel::materials
  MemberType type = MemberType::beam;
  int elements = 1;  ///< number of beam elements the member is subdivided into (trusses: 1)
  /// Local z hint of this member (e.g. the surface normal at a grid-shell beam); zero = the
  /// section's `up` rule (frame_model.h's axes).
  Vec3 up = Vec3::Zero();
};

/// Restrained degrees of freedom of a node: ux, uy, uz, rx, ry, rz.
struct FrameSupport {
  int node = -1;
  std::array<bool, 6> fix{};
};

/// A nodal force [N] and moment [N·m] at the reference load factor 1.
struct NodalLoad {
  int node = -1;
  Vec3 force = Vec3::Zero();
  Vec3 moment = Vec3::Zero();
};

struct FrameModel {
  Points nodes;
  std::vector<FrameMember> members;
  std::vector<FrameSection> sections;
  std::vector<FrameMaterial> materials;
  std::vector<FrameSupport> supports;
  std::vector<NodalLoad> loads;
  /// Optional panels (node id cycles), kept for output and area loads.
  std::vector<std::vector<int>> faces;

  int num_nodes() const { return static_cast<int>(nodes.rows()); }
};

/// Checks references, lengths, sections, materials and loads; throws Error(subject, what) with
/// `subject` (e.g. the file name) for the first problem found.
void validate(const FrameModel& model, const std::string& subject = "model");

/// Length of member m [m].
double member_length(const FrameModel& model, int m);

/// Total member length [m] and mass [kg].
double total_length(const FrameModel& model);
double total_mass(const FrameModel& model);

/// Sum of nodal forces [N].
Vec3 total_load(const FrameModel& model);

}  // namespace gridshell::fem
