// libFuzzer harness: stress-field files (`--field FILE`) through read_field_file against a small
// fixed triangle mesh (a 3 × 3 vertex patch of a gentle dome, 8 triangles). The first input byte
// picks the format (byte % 2: 0 = .blk, 1 = .csv; the seed corpus starts its files with '0' or
// '1'), the rest is the file.

#include <cmath>
#include <cstdint>

#include "fuzz_support.h"
#include "gridshell/core/error.h"
#include "gridshell/field/field.h"
#include "gridshell/field/field_io.h"

using namespace gridshell;

namespace {

TriMesh patch() {
  TriMesh m;
  m.V.resize(9, 3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) m.V.row(3 * j + i) << i - 1.0, j - 1.0, (i == 1 && j == 1) ? 0.3 : 0;
  m.F.resize(8, 3);
  int f = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = 3 * j + i;
      m.F.row(f++) << a, a + 1, a + 4;
      m.F.row(f++) << a, a + 4, a + 3;
    }
  return m;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const TriMesh mesh = patch();
  static const FaceFrames frames = face_frames(mesh);
  const auto path = fuzz::write_input(data[0] % 2 ? "field.csv" : "field.blk", data + 1, size - 1);
  StressField field;
  try {
    field = read_field_file(path.string(), mesh);
  } catch (const Error&) {
    return 0;
  }
  fuzz::require(static_cast<int>(field.size()) == mesh.num_faces(), "one stress per triangle");
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const PrincipalStress& p = field[f];
    fuzz::require(std::isfinite(p.s1) && std::isfinite(p.s2), "finite stresses");
    fuzz::require(p.s1 >= p.s2, "s1 >= s2");
    fuzz::require(std::abs(p.d1.norm() - 1) < 1e-6 && std::abs(p.d2.norm() - 1) < 1e-6,
                  "unit directions");
    fuzz::require(std::abs(p.d1.dot(frames.n[f])) < 1e-6, "d1 tangent to its triangle");
  }
  return 0;
}
