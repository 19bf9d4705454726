#pragma once
/// \file sections.h
/// Steel member cross-sections: the paper's solid round bar and the structural hollow sections
/// of the European series, circular (CHS) and rectangular or square (RHS, SHS), hot-finished
/// (EN 10210-2) or cold-formed (EN 10219-2). Properties are computed from the nominal geometry
/// with the corner radii the standards use for their tabulated properties:
///
/// | process                 | outer radius ro            | inner radius ri |
/// |-------------------------|----------------------------|-----------------|
/// | hot-finished EN 10210-2 | 1.5 t                      | 1.0 t           |
/// | cold-formed EN 10219-2  | 2 t (t ≤ 6 mm), 2.5 t (6 < t ≤ 10 mm), 3 t (t > 10 mm) | ro − t |
///
/// A, I, Wel and Wpl are exact for the rounded-corner geometry (each corner a square less a
/// quarter disc); the torsion constant It and modulus Wt follow the standards' thin-walled
/// formulas: It = t³p/3 + 4 Ap² t / p, Wt = It / (t + 2Ap/p), with Rc = (ro + ri)/2,
/// p = 2[(b − t) + (h − t)] − 2Rc(4 − π) the median perimeter and Ap = (b − t)(h − t) −
/// Rc²(4 − π) the area it encloses. CHS: It = 2I, Wt = 2Wel. Measured against the steel makers'
/// tables within 0.5 % (tests/sections_test.cpp).
///
/// Axes: an RHS's height h lies along local z (Iy, Wy: bending about local y, the strong axis
/// when h > b), its width b along local y — in a grid-shell local z is the surface normal
/// (analysis/gridshell_frame.h), so the section stands upright.
///
/// Designations (millimetres, as the series print them): `CHS 88.9x4.0`, `RHS 120x60x4.0`,
/// `SHS 100x5.0` (or `SHS 100x100x5`), `bar 37`; a trailing word `cold` (or `hot`, the
/// default) gives the process. Sizes outside the catalogues are accepted when geometrically
/// valid (Section::standard tells). Cost: O(1) per section; the catalogues are built on call.

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace gridshell::sections {

enum class Shape { bar, chs, rhs };
enum class Process { hot, cold };
const char* to_string(Shape shape);      ///< "bar", "chs", "rhs"
const char* to_string(Process process);  ///< "hot", "cold"

/// A section's shape and nominal dimensions [m].
struct Section {
  Shape shape = Shape::bar;
  Process process = Process::hot;
  double h = 0.037;  ///< bar and CHS: outside diameter d; RHS: height (along local z)
  double b = 0;      ///< RHS: width (along local y); 0 otherwise
  double t = 0;      ///< wall thickness; 0 for the bar
};
bool operator==(const Section& a, const Section& b);

/// The paper's bar: solid round, diameter d [m].
Section bar(double d);
Section chs(double d, double t, Process process = Process::hot);
Section rhs(double h, double b, double t, Process process = Process::hot);

/// Cross-section properties, SI units (m, m², m³, m⁴, kg/m).
struct SectionProperties {
  double A = 0;                   ///< area
  double Iy = 0, Iz = 0;          ///< second moments about local y and z
  double Wel_y = 0, Wel_z = 0;    ///< elastic moduli I / (outer fibre distance)
  double Wpl_y = 0, Wpl_z = 0;    ///< plastic moduli
  double It = 0, Wt = 0;          ///< torsion constant and torsional modulus
  double iy = 0, iz = 0;          ///< radii of gyration √(I/A)
  double mass = 0;                ///< per metre at 7850 kg/m³
  double Av_y = 0, Av_z = 0;      ///< shear areas for forces along y and z (EN 1993-1-1 §6.2.6(3))
  double Am = 0;                  ///< area enclosed by the wall's median line (torsion); 0 for bar
  double ro = 0, ri = 0;          ///< RHS corner radii
};
inline constexpr double kSteelDensity = 7850;  ///< [kg/m³] the tables' density

/// The corner radii (ro, ri) [m] of an RHS of thickness t for its process (table above).
std::pair<double, double> corner_radii(double t, Process process);

/// Properties of a valid section; throws Error("section", …) for an invalid one (validate).
SectionProperties properties(const Section& section);

/// Throws Error(subject, one line) unless the section is geometrically valid: finite positive
/// dimensions within 5 mm … 2.5 m (bar 1 mm … 500 mm), t < d/2 for a CHS, corners that fit
/// (2 ro < b, h) for an RHS.
void validate(const Section& section, const std::string& subject = "--section");

/// The series' designation in millimetres: "CHS 88.9x4.0", "RHS 120x60x4.0", "SHS 100x5.0",
/// "bar 37"; " cold" appended for cold-formed hollow sections.
std::string designation(const Section& section);

/// Parses a designation (case-insensitive; `x`, `X`, `*` separate sizes; a trailing `cold` or
/// `hot`). Throws Error(subject, one line) for unknown series, malformed numbers and invalid
/// geometry. Non-catalogue sizes are accepted (see is_standard).
Section parse_section(const std::string& text, const std::string& subject = "--section");

/// A series of standard sections: the common sizes of EN 10210-2 (hot) or EN 10219-2 (cold),
/// CHS 21.3 … 508 or SHS/RHS 40x40 … 400x200, sorted by mass per metre (ties by designation).
/// `Shape::bar` gives the solid bars Ø10 … Ø80 mm in 1 mm steps.
std::vector<Section> series(Shape shape, Process process = Process::hot);
/// The series a word names: "chs", "rhs" (SHS included), "bar"; with " cold" for cold-formed.
/// Throws Error(subject) for another word.
std::vector<Section> parse_series(const std::string& word,
                                  const std::string& subject = "--sections");

/// True when the section is one of its series' catalogue sizes (dimensions within 0.01 mm; a bar:
/// a whole number of millimetres, 10 … 80).
bool is_standard(const Section& section);
/// The catalogue section of a designation, or nullopt when it is not a catalogue size; throws
/// Error("--section") when it does not parse.
std::optional<Section> find_standard(const std::string& designation);

}  // namespace gridshell::sections
