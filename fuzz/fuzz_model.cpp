// libFuzzer harness: MODEL.json through both readers, io::read_frame_model (`analyze`) and
// io::read_shell_model (`stress`). The whole input is the file.

#include <cmath>
#include <cstdint>

#include "fuzz_support.h"
#include "gridshell/core/error.h"
#include "gridshell/fem/frame_model.h"
#include "gridshell/io/frame_model_json.h"
#include "gridshell/io/shell_model_json.h"

using namespace gridshell;

namespace {

void check_frame(const io::FrameModelFile& f) {
  try {
    fem::validate(f.model, "fuzz");
  } catch (const Error&) {
    fuzz::require(false, "read_frame_model returns a model that validates");
  }
  for (const auto& face : f.model.faces)
    for (int v : face)
      fuzz::require(v >= 0 && v < f.model.num_nodes(), "frame faces refer to nodes");
}

void check_shell(const fem::ShellModel& m) {
  const int n = m.mesh.num_vertices();
  fuzz::require(n > 0 && m.mesh.num_faces() > 0, "shell: nodes and triangles");
  fuzz::require(m.mesh.V.allFinite(), "shell: finite nodes");
  for (int f = 0; f < m.mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      fuzz::require(m.mesh.F(f, k) >= 0 && m.mesh.F(f, k) < n, "shell: triangles refer to nodes");
  fuzz::require(static_cast<int>(m.fixed.size()) == n, "shell: one support flag set per node");
  fuzz::require(m.thickness > 0 && std::isfinite(m.thickness), "shell: thickness > 0");
  fuzz::require(m.material.E > 0 && std::isfinite(m.material.E), "shell: E > 0");
  for (const auto& l : m.loads) {
    fuzz::require(l.kind != fem::ShellLoad::Kind::kNode || (l.node >= 0 && l.node < n),
                  "shell: nodal loads refer to nodes");
    fuzz::require(l.force.allFinite() && l.moment.allFinite() && l.q.allFinite() &&
                      std::isfinite(l.p) && std::isfinite(l.g),
                  "shell: finite loads");
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::quiet_logging();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = fuzz::write_input("model.json", data, size);
  try {
    check_frame(io::read_frame_model(path));
  } catch (const Error&) {
  }
  try {
    check_shell(io::read_shell_model(path));
  } catch (const Error&) {
  }
  return 0;
}
