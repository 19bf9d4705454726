#pragma once
/// \file enum_words.h
/// The words of a mode enum (`AnalysisLevel`, `Symmetry`, `Objective`, …) kept in one table per
/// enum, which both its `to_string` and its `parse_*` read: the two cannot drift apart, and an
/// error lists exactly the words that parse.
///
///     constexpr EnumWords<Mode, 2> kModeWords{{{"fast", Mode::fast}, {"exact", Mode::exact}}};
///     const char* to_string(Mode m) { return word_of(m, kModeWords); }
///     Mode parse_mode(const std::string& w) { return parse_word(w, "--mode", kModeWords); }

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "gridshell/core/error.h"

namespace gridshell {

/// An enum's (word, value) pairs, in the order an error message lists them.
template <class Enum, std::size_t N>
using EnumWords = std::array<std::pair<const char*, Enum>, N>;

/// The word of `value`; "?" for a value the table does not name.
template <class Enum, std::size_t N>
const char* word_of(Enum value, const EnumWords<Enum, N>& words) {
  for (const auto& [name, v] : words)
    if (v == value) return name;
  return "?";
}

/// The value named `word`, if the table has it.
template <class Enum, std::size_t N>
std::optional<Enum> find_word(const std::string& word, const EnumWords<Enum, N>& words) {
  for (const auto& [name, value] : words)
    if (word == name) return value;
  return std::nullopt;
}

/// The words joined as "a, b, c".
template <class Enum, std::size_t N>
std::string word_list(const EnumWords<Enum, N>& words) {
  std::string list;
  for (const auto& [name, value] : words) list += list.empty() ? name : std::string(", ") + name;
  return list;
}

/// The value named `word`; throws Error(option, "'word' is not one of a, b, c") otherwise.
template <class Enum, std::size_t N>
Enum parse_word(const std::string& word, const char* option, const EnumWords<Enum, N>& words) {
  if (const std::optional<Enum> value = find_word(word, words)) return *value;
  throw Error(option, fmt::format("'{}' is not one of {}", word, word_list(words)));
}

}  // namespace gridshell
