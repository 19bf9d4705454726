#pragma once
/// \file frame_model_json.h
/// Reading a structural model (MODEL.json, see CONTRACT.md) into a `fem::FrameModel`, and the
/// `# supports i j k` comment that our OBJ writer puts into grid-shell files.
///
/// Loads of type "surface" (per unit surface area), "projected" (per unit plan area, xy) and
/// "self_weight" (the members' weight at their ends) are turned into nodal forces here; surface
/// and projected loads need "faces" (or "triangles") and give each corner 1/n of the face's load.
///
/// Instead of "loads" a model may give named "load_cases" ({NAME: {"type": "permanent" |
/// "variable", "loads": [...]}}) and "combinations" ({NAME: {CASE: factor}}; absent: EN 1990
/// ULS = 1.35 Σ permanent + 1.5 Σ variable and SLS = Σ all, as `design --loads eurocode`).
/// Materials may give "fy" [Pa] for the member checks. Sections are {"shape": "circle",
/// "diameter"}, {"shape": "chs", "d", "t", "process": "hot"|"cold"}, {"shape": "rhs", "h", "b",
/// "t", "process"} (hollow sections get the full EN 1993-1-1 checks, checks/hollow_checks.h) or
/// {"A", "Iy", "Iz", "J"}; members may give "up": [x, y, z], their local z (frame_model.h).

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "gridshell/fem/frame_model.h"

namespace gridshell::io {

/// What MODEL.json's "analysis" block asks for (absent keys stay empty). The non-linear path's
/// stop rule: "stop_displacement" (largest nodal displacement, model units, > 0),
/// "stop_lambda" (load factor, > 0), "max_steps" (arc-length steps, 1..100000); without them
/// the path runs to its first critical point within the automatic caps (docs/frame.md).
struct ModelAnalysisRequest {
  std::optional<bool> linear, buckling, nonlinear;
  std::optional<double> nonlinear_static;
  std::optional<double> stop_displacement, stop_lambda;
  std::optional<int> max_steps;
};

/// A load combination of MODEL.json's load cases: factor × case, summed into nodal loads.
struct ModelCombination {
  std::string name;
  std::vector<std::pair<std::string, double>> factors;  ///< (load case, factor)
  std::vector<fem::NodalLoad> loads;
};

/// A named load case and its type ("permanent" or "variable").
struct ModelLoadCase {
  std::string name, type;
};

/// A parsed MODEL.json. With "load_cases", `model.loads` are those of the primary combination
/// (`combinations.front()`: "ULS" when there is one, else the first by name); without them
/// `combinations` is empty and `model.loads` are the "loads".
struct FrameModelFile {
  fem::FrameModel model;
  ModelAnalysisRequest analysis;
  std::vector<ModelLoadCase> load_cases;
  std::vector<ModelCombination> combinations;
};

/// Parses MODEL.json text; `subject` names the file in errors. Members without "elements" get
/// `default_elements`. Throws Error for malformed JSON, missing or wrong-typed fields, unknown
/// section/material names, bad references, non-positive sections, zero-length members.
FrameModelFile parse_frame_model(const std::string& text, const std::string& subject,
                                 int default_elements = 1);
FrameModelFile read_frame_model(const std::filesystem::path& path, int default_elements = 1);

/// A section in MODEL.json's form, as read_frame_model reads it back: {"shape": "circle",
/// "diameter"}, {"shape": "chs", "d", "t", "process"}, {"shape": "rhs", "h", "b", "t",
/// "process"} for sections made from a profile, else {"A", "Iy", "Iz", "J"}; "up" when set.
nlohmann::json section_to_json(const fem::FrameSection& section);

/// A named load case of frame.json: "permanent" or "variable", and its nodal loads.
struct NodalLoadCase {
  std::string name;
  bool permanent = false;
  std::vector<fem::NodalLoad> loads;
};

/// The frame as MODEL.json (CONTRACT.md): nodes, members (section, material, elements), sections
/// (section_to_json), materials (E, nu, density, fy when set), supports (their fixed dofs),
/// faces, and either "loads" (the model's nodal loads, when `cases` is empty) or "load_cases"
/// and "combinations" ({NAME: {CASE: factor}}). Numbers keep full precision (17 significant
/// digits), so that reading it back gives the same model bit for bit up to the circle's
/// diameter (one rounding).
nlohmann::json frame_model_to_json(
    const fem::FrameModel& model, const std::vector<NodalLoadCase>& cases = {},
    const std::vector<std::pair<std::string, std::vector<std::pair<std::string, double>>>>&
        combinations = {});

/// The vertex ids of a `# supports i j k ...` comment line in an OBJ file (empty if none).
/// Throws Error for malformed ids.
std::vector<int> read_obj_supports_comment(const std::filesystem::path& path);

}  // namespace gridshell::io
