// Mesh file reading and writing: lossless round trips, every supported flavour of PLY/OBJ/OFF/STL,
// and the paper's shared surfaces with their supports.

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/surfaces/builtin.h"
#include "gridshell/surfaces/load.h"
#include "test_support.h"

using namespace gridshell;
namespace fs = std::filesystem;

namespace {

PolyMesh mixed_mesh() {
  PolyMesh m;
  m.V.resize(6, 3);
  m.V << 0, 0, 0, 1.0 / 3.0, 0, 0.1, 1, 1e-17, -2.5e10, 0, 1, std::acos(-1.0), 1, 1, 1, 2, 0.5,
      -0.125;
  m.faces = {{0, 1, 4, 3}, {1, 2, 4}, {2, 5, 4}};
  return m;
}

void write_text(const fs::path& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary);
  out << s;
}

}  // namespace

TEST(MeshIO, BinaryPlyRoundTripIsLossless) {
  PolyMesh m = mixed_mesh();
  fs::path p = test::temp_dir("ply") / "m.ply";
  io::write_ply(p, m, {1, 4}, true);
  io::MeshFile r = io::read_mesh(p);
  ASSERT_EQ(r.mesh.num_vertices(), 6);
  EXPECT_EQ((r.mesh.V - m.V).cwiseAbs().maxCoeff(), 0.0);  // bit-exact doubles
  EXPECT_EQ(r.mesh.faces, m.faces);
  ASSERT_EQ(r.vertex_colors.size(), 6u);
  EXPECT_EQ(r.vertex_colors[1][0], 255);
  EXPECT_EQ(r.vertex_colors[1][1], 0);
  EXPECT_EQ(r.vertex_colors[0][1], 192);
  // Supports come back through the default rule (pure red vertices).
  PolySurface s = load_poly_surface(p.string());
  EXPECT_EQ(s.supports, (std::vector<int>{1, 4}));
}

TEST(MeshIO, AsciiPlyRoundTripIsLossless) {
  PolyMesh m = mixed_mesh();
  fs::path p = test::temp_dir("ply") / "m.ply";
  io::write_ply(p, m, {0}, false);
  io::MeshFile r = io::read_mesh(p);
  EXPECT_EQ((r.mesh.V - m.V).cwiseAbs().maxCoeff(), 0.0);  // shortest round-trip decimals
  EXPECT_EQ(r.mesh.faces, m.faces);
}

TEST(MeshIO, ObjRoundTripIsLossless) {
  PolyMesh m = mixed_mesh();
  fs::path p = test::temp_dir("obj") / "m.obj";
  io::write_obj(p, m, {2});
  io::MeshFile r = io::read_mesh(p);
  EXPECT_EQ((r.mesh.V - m.V).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(r.mesh.faces, m.faces);
}

TEST(MeshIO, BigEndianPlyWithExtraPropertiesAndElements) {
  // Two triangles; float x y z plus an extra per-vertex 'quality' double; a face 'flags' int;
  // an extra element 'material' between vertices and faces.
  std::string s =
      "ply\nformat binary_big_endian 1.0\ncomment written by hand\nelement vertex 4\n"
      "property float x\nproperty float y\nproperty float z\nproperty double quality\n"
      "element material 1\nproperty uchar kind\n"
      "element face 2\nproperty list uchar int vertex_indices\nproperty int flags\nend_header\n";
  auto be = [&s](const void* p, std::size_t n) {
    const char* c = static_cast<const char*>(p);
    for (std::size_t i = 0; i < n; ++i) s.push_back(c[n - 1 - i]);
  };
  const float xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5f}, {0, 1, 0.25f}};
  for (auto& v : xyz) {
    for (float c : v) be(&c, 4);
    double q = 7.5;
    be(&q, 8);
  }
  s.push_back(3);  // material kind
  const int faces[2][3] = {{0, 1, 2}, {0, 2, 3}};
  for (auto& f : faces) {
    s.push_back(3);
    for (int v : f) be(&v, 4);
    int flags = 42;
    be(&flags, 4);
  }
  fs::path p = test::temp_dir("be") / "be.ply";
  write_text(p, s);
  io::MeshFile r = io::read_mesh(p);
  ASSERT_EQ(r.mesh.num_vertices(), 4);
  ASSERT_EQ(r.mesh.num_faces(), 2);
  EXPECT_DOUBLE_EQ(r.mesh.V(2, 2), 0.5);
  EXPECT_DOUBLE_EQ(r.mesh.V(3, 2), 0.25);
  EXPECT_EQ(r.mesh.faces[1], (std::vector<int>{0, 2, 3}));
}

TEST(MeshIO, PlyIntegerCoordinatesAndOtherColourTypes) {
  // Coordinates may be any numeric type (CGAL's reader crashed on a `short` one, found by
  // fuzz/fuzz_mesh); float colours are 0–1, and some exporters write diffuse_red ….
  fs::path d = test::temp_dir("plytypes");
  write_text(d / "short.ply",
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty short x\nproperty int y\n"
             "property uchar z\nproperty float red\nproperty float green\nproperty float blue\n"
             "element face 1\nproperty list uchar uint vertex_index\nend_header\n"
             "-2 0 0 1 0 0\n5 0 0 0.5 0.5 0.5\n0 7 3 2 -1 0\n3 0 1 2\n");
  io::MeshFile r = io::read_mesh(d / "short.ply");
  ASSERT_EQ(r.mesh.num_vertices(), 3);
  EXPECT_EQ(r.mesh.V.row(2), Eigen::RowVector3d(0, 7, 3));
  EXPECT_EQ(r.mesh.V(0, 0), -2.0);
  EXPECT_EQ(r.mesh.faces, (std::vector<std::vector<int>>{{0, 1, 2}}));
  ASSERT_EQ(r.vertex_colors.size(), 3u);
  EXPECT_EQ(r.vertex_colors[0], (std::array<std::uint8_t, 3>{255, 0, 0}));
  EXPECT_EQ(r.vertex_colors[1], (std::array<std::uint8_t, 3>{128, 128, 128}));
  EXPECT_EQ(r.vertex_colors[2], (std::array<std::uint8_t, 3>{255, 0, 0}));  // clamped
  write_text(d / "diffuse.ply",
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
             "property float z\nproperty uchar diffuse_red\nproperty uchar diffuse_green\n"
             "property uchar diffuse_blue\nelement face 1\nproperty list uchar int "
             "vertex_indices\nend_header\n0 0 0 255 0 0\n1 0 0 9 9 9\n0 1 0 9 9 9\n3 0 1 2\n");
  EXPECT_EQ(load_surface((d / "diffuse.ply").string()).supports, (std::vector<int>{0}));
}

TEST(MeshIO, ObjPolygonsAndNegativeIndices) {
  fs::path p = test::temp_dir("obj") / "neg.obj";
  write_text(p,
             "# a quad and a triangle, relative indices\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
             "vt 0 0\nvn 0 0 1\nf -4/1/1 -3/1/1 -2/1/1 -1/1/1\nv 2 0.5 0\nf 2 5 3\n");
  io::MeshFile r = io::read_mesh(p);
  ASSERT_EQ(r.mesh.num_faces(), 2);
  EXPECT_EQ(r.mesh.faces[0], (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(r.mesh.faces[1], (std::vector<int>{1, 4, 2}));
  Surface s = load_surface(p.string());
  EXPECT_EQ(s.mesh.num_faces(), 3);  // the quad fan-triangulated
  EXPECT_EQ(s.supports.size(), 5u);  // no colours: the whole boundary
}

TEST(MeshIO, OffFile) {
  fs::path p = test::temp_dir("off") / "t.off";
  write_text(p, "OFF\n# comment\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
  io::MeshFile r = io::read_mesh(p);
  EXPECT_EQ(r.mesh.num_vertices(), 4);
  EXPECT_EQ(r.mesh.faces[1], (std::vector<int>{0, 2, 3}));
}

TEST(MeshIO, OffVariants) {
  fs::path d = test::temp_dir("off");
  // Counts on the header line, CRLF line ends, comments, colours after the coordinates and after
  // the face's corners (COFF), normals (NOFF).
  write_text(d / "c.off",
             "COFF 4 2 0\r\n0 0 0 255 0 0 255\r\n1 0 0 0.5 0.5 0.5 1\r\n1 1 0 1 1 1 1 # c\r\n"
             "0 1 0 1 1 1 1\r\n3 0 1 2 255 0 0\r\n3 0 2 3\r\n");
  write_text(d / "n.off",
             "NOFF\n4 1 4\n0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n4 0 1 2 3\n");
  io::MeshFile c = io::read_mesh(d / "c.off");
  EXPECT_EQ(c.mesh.num_vertices(), 4);
  EXPECT_EQ(c.mesh.faces, (std::vector<std::vector<int>>{{0, 1, 2}, {0, 2, 3}}));
  EXPECT_DOUBLE_EQ(c.mesh.V(2, 1), 1.0);
  io::MeshFile n = io::read_mesh(d / "n.off");
  EXPECT_EQ(n.mesh.faces, (std::vector<std::vector<int>>{{0, 1, 2, 3}}));
  // 4D OFF has a fourth coordinate: refused rather than misread.
  write_text(d / "4.off", "4OFF\n3 1 0\n0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2\n");
  EXPECT_THROW(io::read_mesh(d / "4.off"), Error);
}

namespace {

/// A binary STL of `triangles` (corners as coordinates), with `header` in its 80-byte header and
/// `count` facets declared (-1: as many as given).
std::string binary_stl(const std::vector<std::array<Vec3, 3>>& triangles, const std::string& header,
                       long count = -1) {
  std::string out = header;
  out.resize(80, ' ');
  const std::uint32_t n = count < 0 ? static_cast<std::uint32_t>(triangles.size())
                                    : static_cast<std::uint32_t>(count);
  out.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : triangles) {
    const float normal[3] = {0, 0, 1};
    out.append(reinterpret_cast<const char*>(normal), sizeof normal);
    for (const Vec3& p : t) {
      const float xyz[3] = {static_cast<float>(p.x()), static_cast<float>(p.y()),
                            static_cast<float>(p.z())};
      out.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
    }
    out.append(2, '\0');
  }
  return out;
}

}  // namespace

TEST(MeshIO, StlAsciiAndBinary) {
  // The unit square as two facets, each with its own copy of the corners (as STL stores them):
  // read back as 4 shared vertices, whichever of the two encodings.
  const std::vector<std::array<Vec3, 3>> square = {
      {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0.5)},
      {Vec3(0, 0, 0), Vec3(1, 1, 0.5), Vec3(0, 1, 0)}};
  const fs::path d = test::temp_dir("stl");
  std::string ascii = "solid square\n";
  for (const auto& t : square) {
    ascii += "  facet normal 0 0 1\n    outer loop\n";
    for (const Vec3& p : t) ascii += fmt::format("      vertex {} {} {}\n", p.x(), p.y(), p.z());
    ascii += "    endloop\n  endfacet\n";
  }
  ascii += "endsolid square\n";
  write_text(d / "a.stl", ascii);
  write_text(d / "b.stl", binary_stl(square, "binary"));
  // Some exporters begin a binary file's header with "solid" too; and no extension at all.
  write_text(d / "c.stl", binary_stl(square, "solid exported by a CAD tool"));
  write_text(d / "ascii_without_extension", ascii);
  for (const char* name : {"a.stl", "b.stl", "c.stl", "ascii_without_extension"}) {
    const io::MeshFile r = io::read_mesh(d / name);
    EXPECT_EQ(r.mesh.num_vertices(), 4) << name;
    ASSERT_EQ(r.mesh.num_faces(), 2) << name;
    EXPECT_EQ(r.mesh.faces[0].size(), 3u);
    EXPECT_EQ(r.mesh.faces[0][0], r.mesh.faces[1][0]) << name;  // the corner (0, 0, 0), shared
    EXPECT_DOUBLE_EQ(r.mesh.V(r.mesh.faces[0][2], 2), 0.5) << name;
    EXPECT_TRUE(r.vertex_colors.empty());
    const Surface s = load_surface((d / name).string());
    EXPECT_EQ(s.supports.size(), 4u) << name;  // no colours: the boundary
  }
  // A binary file that declares more facets than it holds is refused.
  write_text(d / "short.stl", binary_stl(square, "binary", 5));
  EXPECT_THROW(io::read_mesh(d / "short.stl"), Error);
}

TEST(MeshIO, UpAxisAndScale) {
  fs::path p = test::temp_dir("up") / "t.off";
  write_text(p, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 2 0\n3 0 1 2\n");
  SurfaceOptions o;
  o.up = "y";
  o.scale = 3;
  Surface s = load_surface(p.string(), o);
  EXPECT_DOUBLE_EQ(s.mesh.V(2, 2), 6.0);  // +y became +z, times 3
  EXPECT_DOUBLE_EQ(s.mesh.V(2, 1), 0.0);
  o.up = "-y";
  s = load_surface(p.string(), o);
  EXPECT_DOUBLE_EQ(s.mesh.V(2, 2), -6.0);
}

TEST(MeshIO, SupportsFromJson) {
  fs::path d = test::temp_dir("sup");
  write_text(d / "t.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
  write_text(d / "s.json", "[3, 1, 1]");
  SurfaceOptions o;
  o.supports = (d / "s.json").string();
  EXPECT_EQ(load_surface((d / "t.off").string(), o).supports, (std::vector<int>{1, 3}));
}

TEST(MeshIO, VtpIsWellFormed) {
  PolyMesh m = mixed_mesh();
  fs::path p = test::temp_dir("vtp") / "m.vtp";
  io::Attributes point, cell;
  point["height"] = m.V.col(2);
  cell["sides"] = Eigen::Vector3d(4, 3, 3);
  io::write_vtp(p, m, point, cell);
  std::string s = io::read_file(p);
  EXPECT_NE(s.find("NumberOfPoints=\"6\" NumberOfPolys=\"3\""), std::string::npos);
  EXPECT_NE(s.find("Name=\"height\""), std::string::npos);
  EXPECT_NE(s.find("Name=\"sides\""), std::string::npos);
  EXPECT_NE(s.find("</VTKFile>"), std::string::npos);
}

namespace {
/// A paraboloid of res × res squares with a point array `height` (z) and a two-component cell
/// array `face` (f / 7, −f): the fine-input VTP tests' data.
struct VtpCase {
  Surface s;
  io::Attributes point, cell;
};
VtpCase vtp_case(int res) {
  BuiltinOptions bo;
  bo.res = res;
  VtpCase c{make_builtin("paraboloid", bo), {}, {}};
  c.point["height"] = c.s.mesh.V.col(2);
  Eigen::MatrixXd faces(c.s.mesh.num_faces(), 2);
  for (int f = 0; f < c.s.mesh.num_faces(); ++f) faces.row(f) << f / 7.0, -f;
  c.cell["face"] = faces;
  return c;
}
}  // namespace

// field.vtp of a fine input: the triangle-mesh writer gives the bytes of the polygon-mesh one,
// across the writer's batches of rows (16 blocks of 4096, formatted on several threads and
// written in order); a non-finite value late in the file leaves no file and no temp file.
TEST(MeshIO, TriangleVtpEqualsPolygonVtp) {
  // 80 000 triangles, 40 401 vertices: more than one batch of rows.
  auto [s, point, cell] = vtp_case(200);
  const fs::path d = test::temp_dir("trivtp");
  io::write_vtp(d / "tri.vtp", s.mesh, point, cell);
  io::write_vtp(d / "poly.vtp", to_poly(s.mesh), point, cell);
  const std::string tri = io::read_file(d / "tri.vtp");
  EXPECT_EQ(tri, io::read_file(d / "poly.vtp"));
  // Rows in order: the first triangle's row, the last offset, the last value of `face`.
  EXPECT_NE(tri.find(fmt::format("connectivity\" format=\"ascii\">\n{} {} {} \n", s.mesh.F(0, 0),
                                 s.mesh.F(0, 1), s.mesh.F(0, 2))),
            std::string::npos);
  EXPECT_NE(tri.find("\n240000\n</DataArray>\n</Polys>"), std::string::npos);
  EXPECT_NE(tri.find(fmt::format("{} -79999 \n</DataArray>", 79999 / 7.0)), std::string::npos);
  cell["face"](79990, 1) = std::nan("");
  EXPECT_THROW(io::write_vtp(d / "bad.vtp", s.mesh, point, cell), Error);
  int files = 0;
  for (const auto& e : fs::directory_iterator(d)) files += e.is_regular_file();
  EXPECT_EQ(files, 2);  // tri.vtp and poly.vtp: nothing half-written, no temp file
}

// The binary encoding of field.vtp (VTK's appended raw data): every array decoded from its
// offset — a UInt64 byte count, then little-endian values — equals what was written, bit for bit;
// a non-finite value leaves no file.
TEST(MeshIO, BinaryVtpHoldsTheSameValues) {
  auto [s, point, cell] = vtp_case(150);  // 45 000 triangles: more than one block of values
  const fs::path d = test::temp_dir("binvtp");
  io::write_vtp(d / "b.vtp", s.mesh, point, cell, io::VtpEncoding::binary);
  const std::string b = io::read_file(d / "b.vtp");
  EXPECT_NE(b.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_NE(b.find(fmt::format("NumberOfPoints=\"{}\" NumberOfPolys=\"{}\"", s.mesh.num_vertices(),
                               s.mesh.num_faces())),
            std::string::npos);
  const std::size_t data = b.find("<AppendedData encoding=\"raw\">\n_");
  ASSERT_NE(data, std::string::npos);
  const std::size_t base = b.find('_', data) + 1;
  // The values of the array whose element contains `name` (a DataArray in document order).
  auto values = [&](const std::string& name) {
    const std::size_t at = b.find(name);
    EXPECT_LT(at, data) << name;
    const std::size_t o = b.find("offset=\"", at) + 8;
    const std::size_t offset = std::stoull(b.substr(o, b.find('"', o) - o));
    std::uint64_t bytes = 0;
    std::memcpy(&bytes, b.data() + base + offset, sizeof(bytes));
    return std::string_view(b).substr(base + offset + sizeof(bytes), bytes);
  };
  auto doubles = [](std::string_view raw) {
    std::vector<double> v(raw.size() / sizeof(double));
    std::memcpy(v.data(), raw.data(), raw.size());
    return v;
  };
  auto longs = [](std::string_view raw) {
    std::vector<std::int64_t> v(raw.size() / sizeof(std::int64_t));
    std::memcpy(v.data(), raw.data(), raw.size());
    return v;
  };
  const std::vector<double> xyz = doubles(values("<Points>"));
  ASSERT_EQ(xyz.size(), 3u * s.mesh.num_vertices());
  for (int v = 0; v < s.mesh.num_vertices(); ++v)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(xyz[3 * v + c], s.mesh.V(v, c));
  const std::vector<std::int64_t> conn = longs(values("\"connectivity\"")),
                                  offsets = longs(values("\"offsets\""));
  ASSERT_EQ(conn.size(), 3u * s.mesh.num_faces());
  ASSERT_EQ(offsets.size(), static_cast<std::size_t>(s.mesh.num_faces()));
  for (int f = 0; f < s.mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) ASSERT_EQ(conn[3 * f + k], s.mesh.F(f, k));
    ASSERT_EQ(offsets[f], 3 * (f + 1));
  }
  const std::vector<double> height = doubles(values("\"height\"")),
                            face = doubles(values("\"face\""));
  ASSERT_EQ(height.size(), static_cast<std::size_t>(s.mesh.num_vertices()));
  for (int v = 0; v < s.mesh.num_vertices(); ++v) ASSERT_EQ(height[v], s.mesh.V(v, 2));
  ASSERT_EQ(face.size(), 2u * s.mesh.num_faces());
  for (int f = 0; f < s.mesh.num_faces(); ++f) {
    ASSERT_EQ(face[2 * f], f / 7.0);
    ASSERT_EQ(face[2 * f + 1], -f);
  }
  EXPECT_EQ(b.substr(b.size() - 28), "\n</AppendedData>\n</VTKFile>\n");
  cell["face"](44990, 0) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(io::write_vtp(d / "bad.vtp", s.mesh, point, cell, io::VtpEncoding::binary), Error);
  EXPECT_FALSE(fs::exists(d / "bad.vtp"));
}

TEST(MeshIO, RefusesToWriteNaN) {
  PolyMesh m = mixed_mesh();
  m.V(0, 0) = std::nan("");
  fs::path d = test::temp_dir("nan");
  EXPECT_THROW(io::write_obj(d / "m.obj", m), Error);
  EXPECT_FALSE(fs::exists(d / "m.obj"));  // nothing half-written
}

TEST(MeshIO, AFailedWriteKeepsThePreviousFile) {
  // Every writer builds the whole text first and hands it to write_file_atomic (temp file +
  // rename), or writes it in pieces through AtomicFileWriter (VTP): a writer that fails part-way
  // leaves the previous file as it was, and no temp file.
  fs::path d = test::temp_dir("atomic");
  PolyMesh m = mixed_mesh();
  io::write_obj(d / "m.obj", m);
  io::write_ply(d / "m.ply", m);
  const std::string obj = io::read_file(d / "m.obj"), ply = io::read_file(d / "m.ply");
  PolyMesh bad = m;
  bad.V(5, 2) = std::numeric_limits<double>::infinity();  // the last vertex: found late
  EXPECT_THROW(io::write_obj(d / "m.obj", bad), Error);
  EXPECT_THROW(io::write_ply(d / "m.ply", bad, {}, false), Error);
  EXPECT_THROW(io::write_ply(d / "m.ply", m, {0, 6}), Error);  // a support beyond the mesh
  EXPECT_THROW(io::write_vtp(d / "m.vtp", bad), Error);
  EXPECT_EQ(io::read_file(d / "m.obj"), obj);
  EXPECT_EQ(io::read_file(d / "m.ply"), ply);
  EXPECT_FALSE(fs::exists(d / "m.vtp"));
  // A target that cannot be replaced (a folder): Error, the folder untouched, no temp file.
  fs::create_directory(d / "dir.obj");
  EXPECT_THROW(io::write_file_atomic(d / "dir.obj", "v 0 0 0\n"), Error);
  EXPECT_TRUE(fs::is_directory(d / "dir.obj"));
  int files = 0;
  for (const auto& e : fs::directory_iterator(d)) files += e.is_regular_file();
  EXPECT_EQ(files, 2);  // m.obj and m.ply only
}

struct SharedSurface {
  const char* file;
  int vertices, faces, loops, supports;
};

TEST(MeshIO, SharedSurfacesLoadWithTheirSupports) {
  SKIP_WITHOUT_SHARED_DATA();
  const SharedSurface cases[] = {{"surfaces/Shell.ply", 441, 800, 1, 80},
                                 {"surfaces/Botanic.ply", 1121, 2152, 1, 88},
                                 {"surfaces/Neumunster.ply", 1209, 2232, 1, 184},
                                 {"surfaces/aquadom_Vouga.ply", 4005, 7742, 3, 252},
                                 {"surfaces/liliumVouga.ply", 2554, 4994, 1, 113},
                                 {"surfaces/BritishQuadTang.ply", 1648, 3072, 2, 224}};
  for (const auto& c : cases) {
    fs::path p = test::shared_file(c.file);
    ASSERT_FALSE(p.empty()) << c.file;
    Surface s = load_surface(p.string());
    EXPECT_EQ(s.mesh.num_vertices(), c.vertices) << c.file;
    EXPECT_EQ(s.mesh.num_faces(), c.faces) << c.file;
    EXPECT_EQ(static_cast<int>(s.supports.size()), c.supports) << c.file;
    EXPECT_EQ(static_cast<int>(build_topology(s.mesh).boundary_loops.size()), c.loops) << c.file;
  }
  // The stress-field vault has normals but no colours: supports default to the boundary.
  Surface v = load_surface(test::shared_file("stress-fields/curvedVault.ply").string());
  EXPECT_EQ(v.mesh.num_vertices(), 1935);
  EXPECT_EQ(v.mesh.num_faces(), 3541);
  EXPECT_GT(v.supports.size(), 0u);
}
