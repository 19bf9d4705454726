#pragma once
/// \file request.h
/// What one studio request asks for, and what it answers (docs/studio.md, CONTRACT "studio").
///
/// A request is the query of `GET /api/design?surface=builtin:funicular&D=2&A=2&cells=200`:
/// surface, D, A, cells (or length), objective, symmetry, panels, analysis level and seed. It is parsed
/// with the command line's own parse_* functions and checked by check_design_options, so a bad
/// parameter gives the same one-line Error as `gridshell design` (`-D: must be a number ≥ 1`).
/// With an objective the field settings are searched (pipeline/objective.h) and D, A are not
/// read; otherwise one design at D and A. The analysis is `buckling` (linear + LBA) unless
/// `analyze=nonlinear` (or linear/none) is asked for.
///
/// The answer (design_answer) is one JSON object: the mesh (vertices, faces, supports), the
/// beams and their axial forces, report.json's blocks (`mesh`, `design`, `structure`,
/// `timings_s`, `objective`), the config.json that `gridshell design --config` repeats it with,
/// and `view`: the data block report.html's viewer reads (report/report_html.h).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "gridshell/analysis/frame_analysis.h"
#include "gridshell/core/progress.h"
#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/objective.h"

namespace gridshell::studio {

/// The query parameters of a request, in order (a repeated name: the last one counts).
using Params = std::vector<std::pair<std::string, std::string>>;

struct StudioRequest {
  std::string surface = "builtin:funicular";  ///< builtin:NAME, or upload:N (an uploaded file)
  double D = 2, A = 2;
  int cells = 300;                     ///< 0 when `length` is given
  double length = 0;                   ///< total beam length (m), 0 = by cells
  std::optional<Objective> objective;  ///< set: search the field settings, D and A unused
  Symmetry symmetry = Symmetry::none;
  PanelMode panels = PanelMode::free;  ///< `panels=flat`: every panel exactly planar
  analysis::AnalysisLevel analyze = analysis::AnalysisLevel::buckling;
  std::uint64_t seed = 1;
};

/// Parses and checks the parameters (unknown names are an error too). Throws Error with the
/// command line's subject (`-D`, `--cells`, `--objective`, …) and message. The studio's own
/// bounds: cells ≤ 5000, D and A ≤ 10; a built-in surface's spec is checked and written in its
/// canonical form (canonical_builtin).
StudioRequest parse_request(const Params& params);

/// Refuses (Error) a request whose `length` would make more than the studio's cell cap on
/// `surface`: a tessellation of total length L over area S has about (√3/6)·L²/S cells when
/// uniform and at most D times that when graded (D = 4, the search's largest, with an
/// objective), so L may be at most √(6·S·5000 / (√3·D)).
void check_request_size(const StudioRequest& request, const Surface& surface);

/// The same request as query text (a canonical key: equal requests give equal text).
std::string request_query(const StudioRequest& request);

/// The pipeline's options for a request (what `gridshell design` would build from its config).
DesignOptions design_options(const StudioRequest& request);

/// A designed request.
struct StudioDesign {
  StudioRequest request;
  DesignResult result;
  std::optional<ObjectiveResult> search;  ///< with an objective (its `design` moved to result)
  nlohmann::json report;                  ///< report.json as `design` writes it (no fabrication)
  double seconds = 0;
};

/// What requests may share one DesignCache (pipeline/design.h) of their surface: the request's
/// canonical text without D, A and the seed (the cache keys its fields and M′ by D and A
/// itself). Requests with an objective share none (the search keeps its own cache).
std::string design_cache_key(const StudioRequest& request);

/// Designs a request on a loaded surface (run_design, or design_for_objective). When `stop`
/// answers true the design stops and throws `Stopped` (the server asks it whether a newer
/// request came in): a single design's non-linear path at its next step, an objective search
/// before its next candidate (its candidates of one round run in parallel and each finishes).
/// `cache` (a single design only; null: none): what earlier requests of the same surface and
/// design_cache_key computed — the analysis surface, the shell stress, and per (D, A) the field
/// and M′ —, which a design from it takes instead of computing them again; the design is the
/// same either way.
StudioDesign design_request(const Surface& surface, const StudioRequest& request,
                            const StopRequest& stop = {}, DesignCache* cache = nullptr);

/// config.json for `gridshell design --config` (`surface_arg`: the positional argument, e.g. the
/// built-in's name or the uploaded file's name).
nlohmann::json request_config(const StudioRequest& request, const std::string& surface_arg);

/// The JSON answer of /api/design (see above).
nlohmann::json design_answer(const StudioDesign& design, const std::string& surface_arg);

/// Writes what `gridshell design -o DIR` writes for this design into `dir` (created), with the
/// one writer `gridshell design` calls (report/design_folder.h): the grid-shell, fabrication and
/// frame files, field.vtp, modes.csv, figures, report.json (with the load combinations),
/// config.json (request_config) and report.html. `surface`: the surface it was designed on.
void write_design_folder(const std::filesystem::path& dir, const StudioDesign& design,
                         const Surface& surface, const std::string& surface_arg);

}  // namespace gridshell::studio
