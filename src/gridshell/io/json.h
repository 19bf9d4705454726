#pragma once
/// \file json.h
/// Reading JSON that a user gives (MODEL.json, config.json, supports lists): nesting deeper than
/// kMaxJsonDepth is refused while parsing, before the document is built, so a file of a million
/// `[` cannot exhaust the stack of anything that walks the document afterwards (printing,
/// comparing and destroying a nlohmann::json recurse).

#include <string>

#include <nlohmann/json.hpp>

namespace gridshell::io {

/// Deeper than any file the program reads or writes (theirs nest at most 4 levels).
inline constexpr int kMaxJsonDepth = 64;

/// Parses `text`. Throws Error(subject, …) for nesting deeper than kMaxJsonDepth, and
/// nlohmann::json::parse_error for malformed text (callers say what they expected).
nlohmann::json parse_json(const std::string& text, const std::string& subject);

}  // namespace gridshell::io
