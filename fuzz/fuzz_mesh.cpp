// libFuzzer harness: surface files (PLY ascii/binary, OBJ, OFF, STL ascii/binary) through
// io::read_mesh and load_surface. The first input byte picks the extension (byte % 4: 0 = .ply,
// 1 = .obj, 2 = .off, 3 = .stl; the seed corpus starts its files with '0' … '3'), the rest is
// the file.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "fuzz_support.h"
#include "gridshell/core/error.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/mesh/topology.h"
#include "gridshell/surfaces/load.h"

using namespace gridshell;

namespace {

void check_mesh_file(const io::MeshFile& f) {
  const PolyMesh& m = f.mesh;
  fuzz::require(m.num_vertices() > 0 && m.num_faces() > 0, "read_mesh: vertices and faces");
  fuzz::require(m.V.allFinite(), "read_mesh: finite coordinates");
  for (const auto& face : m.faces) {
    fuzz::require(face.size() >= 3, "read_mesh: faces of at least 3 corners");
    for (int v : face) fuzz::require(v >= 0 && v < m.num_vertices(), "read_mesh: indices in range");
  }
  fuzz::require(f.vertex_colors.empty() ||
                    f.vertex_colors.size() == static_cast<std::size_t>(m.num_vertices()),
                "read_mesh: one colour per vertex or none");
}

void check_surface(const Surface& s) {
  const TriMesh& m = s.mesh;
  fuzz::require(m.V.allFinite(), "load_surface: finite coordinates");
  for (int f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      fuzz::require(m.F(f, k) >= 0 && m.F(f, k) < m.num_vertices(),
                    "load_surface: indices in range");
  fuzz::require(std::is_sorted(s.supports.begin(), s.supports.end()) &&
                    std::adjacent_find(s.supports.begin(), s.supports.end()) == s.supports.end(),
                "load_surface: supports sorted and unique");
  for (int v : s.supports)
    fuzz::require(v >= 0 && v < m.num_vertices(), "load_surface: supports in range");
  // The repair's promises (mesh/repair.h): every vertex used, no two at the same position, no
  // triangle that uses a vertex twice.
  std::vector<char> used(m.num_vertices(), 0);
  for (int f = 0; f < m.num_faces(); ++f) {
    const auto t = m.F.row(f);
    fuzz::require(t(0) != t(1) && t(1) != t(2) && t(0) != t(2), "load_surface: distinct corners");
    for (int k = 0; k < 3; ++k) used[t(k)] = 1;
  }
  fuzz::require(std::count(used.begin(), used.end(), 0) == 0, "load_surface: no unused vertex");
  PolyMesh p;
  p.V = m.V;
  fuzz::require(check_mesh(p).duplicate_vertices == 0, "load_surface: no duplicate vertices");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kNames[4] = {"input.ply", "input.obj", "input.off", "input.stl"};
  const auto path = fuzz::write_input(kNames[data[0] % 4], data + 1, size - 1);
  try {
    check_mesh_file(io::read_mesh(path));
  } catch (const Error&) {
    return 0;  // the file is refused: fine, as long as it is refused this way
  }
  try {
    check_surface(load_surface(path.string()));
  } catch (const Error&) {
  }
  return 0;
}
