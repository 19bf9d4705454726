#pragma once
/// \file objective.h
/// `design --objective lambda|delta|balanced`: instead of one field setting, search the ways a
/// field can drive the tessellation and keep the design the frame analysis judges best, all at
/// the same total beam length (the same steel).
///
/// Why a search: which reading of the stress makes a stronger grid-shell is not settled by the
/// paper and depends on the surface (docs/field.md, "Conventions"): stretching cells across the
/// stress instead of along it raised λ_LBA by 70 % on one shared surface and halved it on
/// another. So the candidates are judged, not assumed:
///
///   1. the isotropic Voronoi design (D = A = 1) at the requested length — the reference every
///      other candidate must beat; with `--cells`/`--radius` its length becomes the length of
///      all others;
///   2. shell-stress fields in four conventions (field/field.h): the paper's (magnitude, along,
///      rising), small cells where the stress is low (falling), cells long across the stress,
///      and tension only (stressDrivenMesh's reading); at D = A = 2;
///   3. frame-response fields (field/frame_response.h) from the reference's own analysis: the
///      strain energy of its first buckling modes (for λ) and under the load (for δ); density
///      only (D = 2, A = 1);
///   4. local rounds around the best-λ and the best-δ candidates — D one up and half down, A one
///      up, and half their contrast (a gain in one figure often costs the other less than
///      proportionally less) — repeated while either best changes (3 rounds, 16 designs at
///      most). The pool is the same for every objective: each objective's choice is the best of
///      it by its own rule.
/// docs/field.md ("Conventions", "Objective search") has what each
/// candidate gave on ten surfaces, and what was tried and left out.
///
/// Every candidate is designed by run_design with analysis "buckling" (linear + LBA: δ and
/// λ_LBA), candidates of one round in parallel; one whose total length missed the target (the
/// requested --length, or the reference's) by more than its tolerance (5 %) is set aside as
/// failed: only designs of the same steel are compared. The choice:
///   lambda   the largest λ_LBA;
///   delta    the smallest δ;
///   balanced the largest gain in one of the two figures among the candidates whose other figure
///            is no more than `tolerance` (2 %) worse than the reference's; the reference itself
///            when none improves anything.
/// The chosen design is then analysed at the level the user asked for. Deterministic for a seed.
///
/// `mass` asks another question: the lightest steel that passes every check. Beam length is no
/// longer fixed — every candidate's members are sized (sizing/sizing.h) — so the candidates also
/// vary the cell size. 11 designs at most (pipeline/objective_mass.cpp, docs/field.md
/// "Objective mass"):
///   1. the isotropic Voronoi at the requested size (the reference), then in parallel the
///      isotropic Voronoi at 0.75× and 1.33× the cell count, the four shell-stress conventions
///      (D = A = 2) and the two frame-response fields of the reference (D = 2, A = 1);
///   2. the lightest field candidate of round 1 at 0.75× and 1.33× the cell count
///      (`rounds` = 1 leaves it out; `max_designs` below 11 cuts the lists short).
/// The choice is the lightest candidate that is sized (ties: the first); report.json's
/// `mass_saving_vs_isotropic` compares it with the lightest sized isotropic candidate, both at
/// the search level.
/// Each candidate is sized at analysis level `buckling` (the λ check is λ_LBA ≥ λ_min, cheap);
/// the lightest sized candidate (the reference when none is) is then sized again at the user's
/// level (default nonlinear: the imperfect non-linear λ) exactly as `design --size` does, so the
/// reported verdict (report.json `sizing`) is the full one. `base.sizing_options` gives the
/// section list (the hot-finished CHS series when empty); `base.sizing` is not read.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gridshell/core/progress.h"
#include "gridshell/field/field.h"
#include "gridshell/pipeline/design.h"

namespace gridshell {

enum class Objective { lambda, delta, balanced, mass };
Objective parse_objective(const std::string& word);  ///< throws Error("--objective", ...)
const char* to_string(Objective o);

/// What drives a candidate's field.
enum class FieldSource {
  uniform,       ///< isotropic cells (the reference)
  shell_stress,  ///< the continuous shell's membrane stresses (the paper)
  frame_mode,    ///< strain energy of the reference frame's first buckling mode
  frame_energy,  ///< strain energy of the reference frame under the load
};
const char* to_string(FieldSource s);

/// One field setting tried by the search.
struct FieldSetting {
  FieldSource source = FieldSource::uniform;
  double D = 1, A = 1;
  StressMeasure measure = StressMeasure::magnitude;
  StretchAxis stretch = StretchAxis::along;
  DensityTrend density = DensityTrend::rising;
  int feedback = 0;  ///< frame-response fields: 1 = from the reference, 2 = from a candidate
  /// `mass`: the cell count relative to the requested size (radius ÷ √size, length × √size)
  double size = 1;
  std::string label() const;
};

struct ObjectiveOptions {
  Objective objective = Objective::balanced;
  double tolerance = 0.02;  ///< balanced: how much worse the other figure may get (relative)
  int rounds = 3;        ///< 1 = the first round only; then local rounds while a best changes
  int max_designs = 16;  ///< candidates at most, the reference included (the default design
                         ///< stays within 10 s: docs/field.md)
  Progress progress = {};  ///< told after every candidate (empty: nobody listens)
  /// Asked before every candidate starts and before the chosen design's final analysis: once it
  /// answers true, no further candidate starts, and the search throws `Stopped` when the
  /// running ones are done (at most one candidate's time later). The studio uses it to drop a
  /// superseded search instead of finishing it.
  StopRequest stop = {};
};

/// A candidate as judged.
struct Candidate {
  FieldSetting setting;
  int round = 1;
  bool ok = false;
  std::string error;  ///< why it could not be designed or analysed
  double lambda = 0;  ///< λ_LBA (0 when none was found)
  double delta = 0;   ///< δ (m)
  double length = 0;  ///< total beam length (m)
  int cells = 0;
  double seconds = 0;
  /// The earlier candidate whose field this one's equals bit for bit (its label): the same
  /// design, taken over instead of made again (report.json `same_design_as`); empty otherwise.
  std::string same_as;
  /// `mass`: the candidate's members sized at the search level (`ok` = designed and sized)
  bool sized = false;
  double mass_kg = 0;      ///< steel of the sized (or, when not sized, last tried) members
  std::string governing;   ///< the check closest to its limit ("member", "deflection", "stability")
  double governing_ratio = 0;  ///< that check's utilisation (≤ 1 when sized)
  /// `mass`: why its sizing again at the user's level failed, when it was tried there and
  /// failed (the search then tries the next lightest); empty otherwise.
  std::string final_failure;
};

struct ObjectiveResult {
  Objective objective = Objective::balanced;  ///< what was searched for
  DesignResult design;  ///< the chosen design, analysed at `base.analyze`
  std::vector<Candidate> candidates;
  int chosen = 0;       ///< index into candidates (0 = the isotropic reference)
  /// What each objective would have chosen from the same candidates (lambda, delta, balanced).
  std::array<int, 3> choice{};
  std::string reason;   ///< one sentence: why this one
  double seconds = 0;
  /// `mass`: the chosen design's steel after its final sizing at the user's level, the lightest
  /// sized isotropic candidate (-1: none) and the chosen candidate's saving against it (both at
  /// the search level: 1 − chosen / isotropic).
  double mass_kg = 0;
  analysis::AnalysisLevel search_level = analysis::AnalysisLevel::buckling;
  int isotropic_best = -1;
  double mass_saving_vs_isotropic = 0;
  nlohmann::json report() const;  ///< report.json's "objective" block
};

/// `design --field frame-mode|frame-energy` with the given D, A and conventions: the isotropic
/// design of the same size (analysed with LBA), its response field (field/frame_response.h), and
/// the design driven by it at the isotropic design's length (or `options`' --length). `source`
/// must be frame_mode or frame_energy. The result is analysed at `options.analyze`.
DesignResult design_from_frame_response(const Surface& surface, const DesignOptions& options,
                                        FieldSource source);
/// Parses "frame-mode" / "frame-energy"; nullopt for any other word.
std::optional<FieldSource> parse_frame_source(const std::string& word);

/// Searches the field settings for `options.objective`. `base` gives everything else (size,
/// seed, regularization, frame, analysis level); its D, A and field are not read. Throws Error
/// for bad options or input, or when even the isotropic reference cannot be designed.
ObjectiveResult design_for_objective(const Surface& surface, const DesignOptions& base,
                                     const ObjectiveOptions& options = {});

}  // namespace gridshell
