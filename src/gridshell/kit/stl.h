#pragma once
/// \file stl.h
/// Binary STL as the kit writes and reads it: an 80-byte header (the part's name), the triangle
/// count (uint32), and per triangle its unit normal, its three corners (counter-clockwise seen
/// from outside) as little-endian float32 and a zero attribute word — 50 bytes a triangle.

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace gridshell::kit {

/// One triangle of a solid's surface, its corners in float32 as the STL holds them [mm].
using Triangle = std::array<Eigen::Vector3f, 3>;

/// The binary STL of `triangles`, `name` (cut to 80 characters) in the header. A degenerate
/// triangle gets a zero normal.
std::string stl_bytes(const std::vector<Triangle>& triangles, const std::string& name);

/// The triangles of a binary STL. Throws Error(`what`, …) when the bytes are not one (too
/// short, or a size that disagrees with the triangle count).
std::vector<Triangle> read_stl(std::string_view bytes, const std::string& what);

}  // namespace gridshell::kit
