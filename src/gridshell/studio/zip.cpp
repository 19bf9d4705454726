#include "gridshell/studio/zip.h"

#include <algorithm>
#include <array>
#include <cstdint>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"

namespace gridshell::studio {

namespace {

std::array<std::uint32_t, 256> crc_table() {
  std::array<std::uint32_t, 256> t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    t[i] = c;
  }
  return t;
}

void put16(std::string& out, std::uint32_t v) {
  out.push_back(static_cast<char>(v & 0xff));
  out.push_back(static_cast<char>((v >> 8) & 0xff));
}
void put32(std::string& out, std::uint32_t v) {
  put16(out, v & 0xffff);
  put16(out, v >> 16);
}

// 1980-01-01 00:00 in DOS format: fixed, so that an export is byte-for-byte deterministic.
constexpr std::uint32_t kDosTime = 0;
constexpr std::uint32_t kDosDate = (0 << 9) | (1 << 5) | 1;

}  // namespace

std::uint32_t crc32(std::string_view data) {
  static const std::array<std::uint32_t, 256> table = crc_table();
  std::uint32_t c = 0xffffffffu;
  for (unsigned char b : data) c = table[(c ^ b) & 0xff] ^ (c >> 8);
  return c ^ 0xffffffffu;
}

std::string zip_stored(const std::vector<ZipEntry>& entries) {
  if (entries.size() >= 0xffff) throw Error("zip", "too many files for a zip without ZIP64");
  std::string out, central;
  for (const ZipEntry& e : entries) {
    if (e.name.empty() || e.name.size() >= 0xffff) throw Error("zip", "bad member name");
    if (out.size() + e.data.size() + e.name.size() + 64 >= 0xffffffffu)
      throw Error("zip", "archive over 4 GB (no ZIP64)");
    const std::uint32_t crc = crc32(e.data);
    const auto size = static_cast<std::uint32_t>(e.data.size());
    const auto offset = static_cast<std::uint32_t>(out.size());
    // Local file header.
    put32(out, 0x04034b50);
    put16(out, 20);      // version needed: 2.0
    put16(out, 0x0800);  // flags: names are UTF-8
    put16(out, 0);       // method: stored
    put16(out, kDosTime);
    put16(out, kDosDate);
    put32(out, crc);
    put32(out, size);
    put32(out, size);
    put16(out, static_cast<std::uint32_t>(e.name.size()));
    put16(out, 0);  // extra field length
    out += e.name;
    out += e.data;
    // Central directory record.
    put32(central, 0x02014b50);
    put16(central, 0x031e);  // made by: Unix, 3.0
    put16(central, 20);
    put16(central, 0x0800);
    put16(central, 0);
    put16(central, kDosTime);
    put16(central, kDosDate);
    put32(central, crc);
    put32(central, size);
    put32(central, size);
    put16(central, static_cast<std::uint32_t>(e.name.size()));
    put16(central, 0);               // extra
    put16(central, 0);               // comment
    put16(central, 0);               // disk
    put16(central, 0);               // internal attributes
    put32(central, 0100644u << 16);  // external attributes: a regular file, rw-r--r--
    put32(central, offset);
    central += e.name;
  }
  if (out.size() + central.size() + 22 >= 0xffffffffu)
    throw Error("zip", "archive over 4 GB (no ZIP64)");
  const auto central_offset = static_cast<std::uint32_t>(out.size());
  out += central;
  // End of central directory.
  put32(out, 0x06054b50);
  put16(out, 0);
  put16(out, 0);
  put16(out, static_cast<std::uint32_t>(entries.size()));
  put16(out, static_cast<std::uint32_t>(entries.size()));
  put32(out, static_cast<std::uint32_t>(central.size()));
  put32(out, central_offset);
  put16(out, 0);
  return out;
}

std::vector<ZipEntry> zip_entries_of(const std::filesystem::path& dir) {
  std::vector<ZipEntry> entries;
  for (const auto& f : std::filesystem::recursive_directory_iterator(dir))
    if (f.is_regular_file())
      entries.push_back(
          {std::filesystem::relative(f.path(), dir).generic_string(), io::read_file(f.path())});
  std::sort(entries.begin(), entries.end(),
            [](const ZipEntry& a, const ZipEntry& b) { return a.name < b.name; });
  return entries;
}

}  // namespace gridshell::studio
