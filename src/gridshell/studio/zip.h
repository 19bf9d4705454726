#pragma once
/// \file zip.h
/// A zip archive of a few files, stored without compression (method 0): what the studio's
/// export sends. Enough for `unzip`, file managers and every zip library; no ZIP64, so the whole
/// archive must stay under 4 GB and 65535 files (checked). Cost: one CRC-32 pass over the bytes.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gridshell::studio {

/// One archive member: its path inside the archive ('/' separated) and its bytes.
struct ZipEntry {
  std::string name;
  std::string data;
};

/// The archive's bytes. Throws Error("zip", …) when it would be too large.
std::string zip_stored(const std::vector<ZipEntry>& entries);

/// Every regular file under `dir` (sorted by path), named relative to `dir`.
std::vector<ZipEntry> zip_entries_of(const std::filesystem::path& dir);

/// CRC-32 (ISO-HDLC, as in zip and PNG) of `data`.
std::uint32_t crc32(std::string_view data);

}  // namespace gridshell::studio
