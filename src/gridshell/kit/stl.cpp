#include "gridshell/kit/stl.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "gridshell/core/error.h"

namespace gridshell::kit {

namespace {

constexpr std::size_t kHeader = 84, kRecord = 50;

std::uint32_t get_u32(std::string_view s, std::size_t at) {
  std::uint32_t x = 0;
  for (int b = 0; b < 4; ++b) {
    x |= static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + b])) << (8 * b);
  }
  return x;
}

float get_float(std::string_view s, std::size_t at) {
  return std::bit_cast<float>(get_u32(s, at));
}

}  // namespace

std::string stl_bytes(const std::vector<Triangle>& triangles, const std::string& name) {
  std::string out(80, ' ');
  out.replace(0, std::min<std::size_t>(80, name.size()), name.substr(0, 80));
  out.reserve(kHeader + kRecord * triangles.size());
  const auto put_u32 = [&out](std::uint32_t x) {
    for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((x >> (8 * b)) & 0xFF));
  };
  const auto put_float = [&put_u32](float x) { put_u32(std::bit_cast<std::uint32_t>(x)); };
  put_u32(static_cast<std::uint32_t>(triangles.size()));
  for (const Triangle& t : triangles) {
    const Eigen::Vector3d p0 = t[0].cast<double>(), p1 = t[1].cast<double>(),
                          p2 = t[2].cast<double>();
    const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0).normalized();
    for (int i = 0; i < 3; ++i) put_float(std::isfinite(n(i)) ? static_cast<float>(n(i)) : 0.0f);
    for (const Eigen::Vector3f& c : t) {
      for (int i = 0; i < 3; ++i) put_float(c(i));
    }
    out.push_back(0);
    out.push_back(0);
  }
  return out;
}

std::vector<Triangle> read_stl(std::string_view bytes, const std::string& what) {
  if (bytes.size() < kHeader) throw Error(what, "not a binary STL (shorter than its header)");
  const std::size_t n = get_u32(bytes, 80);
  if (bytes.size() != kHeader + kRecord * n) {
    throw Error(what, fmt::format("not a binary STL ({} bytes for {} triangles)", bytes.size(), n));
  }
  std::vector<Triangle> triangles(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t at = kHeader + kRecord * k + 12;  // past the normal
    for (int c = 0; c < 3; ++c) {
      for (int i = 0; i < 3; ++i) triangles[k][c](i) = get_float(bytes, at + 12 * c + 4 * i);
    }
  }
  return triangles;
}

}  // namespace gridshell::kit
