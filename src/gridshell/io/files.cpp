#include "gridshell/io/files.h"

#include <unistd.h>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "gridshell/core/error.h"

namespace gridshell::io {

namespace fs = std::filesystem;

void write_file_atomic(const fs::path& path, std::string_view content) {
  fs::path tmp = path;
  tmp += fmt::format(".tmp{}", static_cast<long>(::getpid()));
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(path.string(), "cannot open for writing");
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw Error(path.string(), "write failed (disk full?)");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw Error(path.string(), "cannot rename temporary file into place");
  }
}

struct AtomicFileWriter::Stream {
  std::ofstream file;
};

AtomicFileWriter::AtomicFileWriter(const fs::path& path) : path_(path), tmp_(path) {
  tmp_ += fmt::format(".tmp{}", static_cast<long>(::getpid()));
  out_ = std::make_unique<Stream>();
  out_->file.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_->file) throw Error(path.string(), "cannot open for writing");
}

AtomicFileWriter::~AtomicFileWriter() {
  out_.reset();  // closed before it is removed
  if (!committed_) {
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
}

void AtomicFileWriter::write_buffer() {
  out_->file.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  buffer_.clear();
  if (!out_->file) throw Error(path_.string(), "write failed (disk full?)");
}

void AtomicFileWriter::append(std::string_view text) {
  buffer_ += text;
  flush_if_large();
}

void AtomicFileWriter::flush_if_large() {
  constexpr std::size_t kFlushBytes = std::size_t{8} << 20;
  if (buffer_.size() >= kFlushBytes) write_buffer();
}

void AtomicFileWriter::commit() {
  write_buffer();
  out_->file.flush();
  out_->file.close();
  if (!out_->file) throw Error(path_.string(), "write failed (disk full?)");
  std::error_code ec;
  fs::rename(tmp_, path_, ec);
  if (ec) throw Error(path_.string(), "cannot rename temporary file into place");
  committed_ = true;
}

void ensure_directory(const fs::path& dir) {
  std::error_code ec;
  if (fs::is_directory(dir, ec)) return;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw Error(dir.string(), "cannot create output directory");
}

std::string read_file(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(path.string(), "no such file");
  if (fs::is_directory(path, ec)) throw Error(path.string(), "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string(), "cannot open for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string format_number(double x) {
  if (!std::isfinite(x)) throw Error("", "internal: refusing to write a non-finite number");
  return fmt::format("{}", x);
}

}  // namespace gridshell::io
