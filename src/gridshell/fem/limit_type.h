#pragma once
/// \file limit_type.h
/// What a non-linear path's critical point is (fem/frame_arclength.h): its words are those of
/// report.json `structure.limit_type` (CONTRACT: "limit point" | "bifurcation" | "none").

#include <string>

namespace gridshell::fem {

enum class LimitType {
  none,         ///< the path stopped before a critical point (or was not followed)
  limit_point,  ///< a load maximum: the tangent's zero mode carries load (φᵀf ≠ 0)
  bifurcation,  ///< φ ⟂ f: the path could go on with rising λ
};

/// "none", "limit point", "bifurcation".
const char* to_string(LimitType type);
/// The type of a word above; throws Error("limit_type", …) naming them otherwise.
LimitType parse_limit_type(const std::string& word);

}  // namespace gridshell::fem
