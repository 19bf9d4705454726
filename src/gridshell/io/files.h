#pragma once
/// \file files.h
/// Writing result files safely: content is written to a temporary name in the same folder and
/// renamed into place, so a reader never sees a half-written file; number formatting that
/// refuses NaN/inf (an output file must never contain them).

#include <filesystem>
#include <string>
#include <string_view>

namespace gridshell::io {

/// Writes `content` to `path` atomically (temp file + rename). Throws Error on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

/// Creates `dir` (and parents) if missing; throws Error naming the option when impossible.
void ensure_directory(const std::filesystem::path& dir);

/// Reads a whole file; throws Error if missing or unreadable.
std::string read_file(const std::filesystem::path& path);

/// Shortest round-trip decimal form of a finite double; throws Error for NaN or inf.
std::string format_number(double x);

}  // namespace gridshell::io
