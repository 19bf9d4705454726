#pragma once
/// \file files.h
/// Writing result files safely: content is written to a temporary name in the same folder and
/// renamed into place, so a reader never sees a half-written file; number formatting that
/// refuses NaN/inf (an output file must never contain them).

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

namespace gridshell::io {

/// Writes `content` to `path` atomically (temp file + rename). Throws Error on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

/// A file written in pieces, atomically: appended text is buffered and written to a temporary
/// name in the same folder as it grows; commit() renames it into place. Destroyed without
/// commit() (an exception while writing), it removes the temporary file: a reader never sees a
/// half-written file, and a large file (field.vtp of a 2 M-triangle input: ~0.4 GB) is never
/// held in memory whole.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(const std::filesystem::path& path);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
  void append(std::string_view text);
  /// The buffer to append to directly (written out by the next append, flush or commit).
  std::string& buffer() { return buffer_; }
  /// Writes the buffer out when it has grown past a few MB.
  void flush_if_large();
  /// Writes what is left and renames the file into place. Throws Error on failure.
  void commit();

 private:
  void write_buffer();
  std::filesystem::path path_, tmp_;
  std::string buffer_;
  struct Stream;
  std::unique_ptr<Stream> out_;
  bool committed_ = false;
};

/// Creates `dir` (and parents) if missing; throws Error naming the option when impossible.
void ensure_directory(const std::filesystem::path& dir);

/// Reads a whole file; throws Error if missing or unreadable.
std::string read_file(const std::filesystem::path& path);

/// Shortest round-trip decimal form of a finite double; throws Error for NaN or inf.
std::string format_number(double x);

}  // namespace gridshell::io
