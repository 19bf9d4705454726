#pragma once
/// \file design_report.h
/// What `gridshell design` writes, assembled in one place: the grid-shell files' content
/// (GridShellOutput) and report.json's blocks `mesh` (CONTRACT keys, statistics, the raw
/// tessellation's figures, the length target), `design` (every stage's details and the options
/// that shaped the result), `structure` (when analysed) and `timings_s`.

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "gridshell/pipeline/design.h"
#include "gridshell/pipeline/gridshell_output.h"

namespace gridshell {

/// The files' content of a design result.
GridShellOutput design_output(const DesignResult& r);

/// report.json without `surface`, `objective` and `timings_s` (the command adds those).
nlohmann::json design_report(const DesignResult& r, const DesignOptions& options);

/// report.json's `timings_s`: the stages in `timings` (a stage that ran twice is summed), the
/// extra ones given, and `total`.
nlohmann::json timings_block(const std::vector<std::pair<std::string, double>>& timings,
                             const std::vector<std::pair<std::string, double>>& extra,
                             double total);

}  // namespace gridshell
