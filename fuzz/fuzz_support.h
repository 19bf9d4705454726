#pragma once
/// \file fuzz_support.h
/// What the libFuzzer harnesses share. The readers take file names, so each input is written to
/// a file in a private temporary folder (removed at exit) under the extension the harness picks.
/// A harness lets only `gridshell::Error` end a run quietly; anything else — another exception,
/// an ASan/UBSan report, a timeout, or a broken promise checked with `require` — is a finding.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <spdlog/spdlog.h>

namespace gridshell::fuzz {

/// The folder of this process's input files (created on first use, removed at exit).
inline const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d = std::filesystem::temp_directory_path() /
                              ("gridshell-fuzz-" + std::to_string(static_cast<long>(::getpid())));
    std::filesystem::create_directories(d);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(scratch_dir(), ec);
    });
    return d;
  }();
  return dir;
}

/// Writes `size` bytes to `name` in the scratch folder and returns its path.
inline std::filesystem::path write_input(const std::string& name, const std::uint8_t* data,
                                         std::size_t size) {
  const std::filesystem::path p = scratch_dir() / name;
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!out) {
    std::fprintf(stderr, "fuzz harness: cannot write %s\n", p.c_str());
    std::abort();
  }
  return p;
}

/// A promise the reader makes about what it returns; a broken one aborts (a finding).
inline void require(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz harness: broken promise: %s\n", what);
  std::abort();
}

/// Warnings about messy but readable input are expected: keep the fuzzer's output quiet.
inline void quiet_logging() { spdlog::set_level(spdlog::level::off); }

}  // namespace gridshell::fuzz
