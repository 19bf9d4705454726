#pragma once
/// \file stl.h
/// A printed part's closed surface as the kit keeps and writes it: float32 corners (what a
/// binary STL holds) and counter-clockwise triangles (seen from outside) indexing them. Binary
/// STL is written by CGAL's STL writer (CGAL/IO/STL.h): an 80-byte header, the triangle count,
/// and per triangle its unit normal, its three corners and a two-byte attribute, 50 bytes a
/// triangle, little-endian float32.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace gridshell::kit {

struct PartMesh {
  std::vector<Eigen::Vector3f> points;  ///< [mm]
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

/// The binary STL of `part`. A degenerate triangle gets CGAL's stand-in normal (1, 0, 0).
std::string stl_bytes(const PartMesh& part);

}  // namespace gridshell::kit
