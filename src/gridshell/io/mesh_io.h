#pragma once
/// \file mesh_io.h
/// Reading and writing polygon meshes.
///
/// Reading: PLY (ascii / binary little and big endian, any numeric property types, extra vertex
/// or face properties and extra elements; vertex colours) and ascii OFF with our own readers,
/// which check every value as they read it (CGAL's had undefined behaviour on hostile files,
/// found by fuzz/fuzz_mesh); OBJ (polygons, negative indices) with CGAL's. Declared counts must
/// fit in the file, and after reading every index and coordinate is validated, so bad input ends
/// in one `gridshell::Error`, never a crash, a hang or a huge allocation.
///
/// Writing: OBJ, PLY (ascii or binary little endian; doubles; per-vertex `support` flag and red
/// colour for supported vertices, grey otherwise, so `--supports red` reads them back), and
/// ParaView's VTK XML PolyData (`.vtp`) with point and cell attributes.

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gridshell/mesh/mesh.h"

namespace gridshell::io {

/// What a mesh file holds.
struct MeshFile {
  PolyMesh mesh;
  /// Per-vertex RGB colour when the file has one (PLY red/green/blue, r/g/b or diffuse_red/…;
  /// integer types as 0–255, float types as 0–1), else empty.
  std::vector<std::array<std::uint8_t, 3>> vertex_colors;
};

/// Reads PLY, OBJ, OFF or STL (ASCII or binary; chosen by extension, else by the file's first
/// bytes: "ply", "OFF", "solid ", else OBJ). STL has no colours (supports: the boundary or a
/// --supports list).
/// Throws Error (subject = path) for a missing, empty, truncated or malformed file, declared
/// counts that do not fit the file, out-of-range indices, non-finite coordinates, no faces.
MeshFile read_mesh(const std::filesystem::path& path);

/// Optional per-element attributes for the VTK writer: name → n×k values (k = 1 or 3).
using Attributes = std::map<std::string, Eigen::MatrixXd>;

/// Writes a polygon mesh as OBJ (`v x y z`, `f i j k ...`, 1-based); the supported vertex ids are
/// listed in a comment line `# supports i j k ...` (0-based) for the reader's information.
void write_obj(const std::filesystem::path& path, const PolyMesh& mesh,
               const std::vector<int>& supports = {});

/// Writes a polygon mesh as PLY with double coordinates, a `support` uchar flag and an RGB colour
/// per vertex (supports pure red (255,0,0), others grey).
void write_ply(const std::filesystem::path& path, const PolyMesh& mesh,
               const std::vector<int>& supports = {}, bool binary = true);

/// Writes VTK XML PolyData: polygons, plus point and cell attributes.
void write_vtp(const std::filesystem::path& path, const PolyMesh& mesh,
               const Attributes& point_data = {}, const Attributes& cell_data = {});
/// How a VTK XML file stores its arrays.
enum class VtpEncoding {
  ascii,   ///< numbers as text inside each DataArray (shortest round-trip form)
  binary,  ///< VTK's appended raw data: little-endian bytes after the XML, each array preceded by
           ///< its length (UInt64); the same values, written without formatting
};

/// The same for a triangle mesh (ascii: the same bytes as its to_poly, without that copy). The
/// file is written in pieces as it is formatted (blocks of rows on all threads, in order): a
/// 2 M-triangle field.vtp is never held in memory whole.
void write_vtp(const std::filesystem::path& path, const TriMesh& mesh,
               const Attributes& point_data = {}, const Attributes& cell_data = {},
               VtpEncoding encoding = VtpEncoding::ascii);

/// Writes VTK XML PolyData of line segments (beams) and polygons (panels) in one piece: the
/// beams are cells 0 … L−1 and the polygons cells L … L+F−1 (VTK's order). A cell array given for
/// only one kind is 0 on the other kind; the cell array `is_beam` (1 / 0) tells them apart (a
/// Threshold on it in ParaView shows one kind).
void write_vtp_beams_and_panels(const std::filesystem::path& path, const PolyMesh& mesh,
                                const std::vector<std::array<int, 2>>& lines,
                                const Attributes& point_data, const Attributes& line_data,
                                const Attributes& panel_data);

/// Writes VTK XML PolyData of line segments (beams), with point and cell (per line) attributes.
void write_vtp_lines(const std::filesystem::path& path, const Points& V,
                     const std::vector<std::array<int, 2>>& lines,
                     const Attributes& point_data = {}, const Attributes& cell_data = {});

}  // namespace gridshell::io
