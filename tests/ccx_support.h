#pragma once
// CalculiX (ccx) as the tests' independent frame solver: the deck of a frame, running it, and
// reading its node displacements. Header-only: the ccx test programs include it.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "gridshell/fem/frame_element.h"
#include "gridshell/fem/frame_model.h"
#include "test_support.h"

namespace gridshell::test {

inline bool have_ccx() { return std::system("command -v ccx > /dev/null 2>&1") == 0; }

/// The CalculiX deck of a frame: per member 4 quadratic beam elements (B32R, mid-nodes added),
/// one ELSET and one section card (local y as our element frame's) each; steel E = 210 GPa,
/// ν = 0.3; the supports' translations fixed; `step` (from `*STEP` to
/// the procedure's data lines, e.g. "*STEP\n*STATIC") with the model's loads × `load_factor`;
/// the node displacements printed.
/// `card(k)` gives member k's section as CalculiX writes it after SECTION= (the type, a newline,
/// its dimensions), e.g. "RECT\n0.03,0.03" or "PIPE\n0.044,0.004" (outer radius, wall).
inline std::string ccx_frame_deck(const fem::FrameModel& m, const std::vector<int>& supports,
                                  const std::function<std::string(std::size_t)>& card,
                                  const std::string& step, double load_factor = 1) {
  std::ostringstream inp, elems, sections;
  inp << "*NODE, NSET=NALL\n";
  const int n = m.num_nodes();
  for (int v = 0; v < n; ++v)
    inp << fmt::format("{},{:.12g},{:.12g},{:.12g}\n", v + 1, m.nodes(v, 0), m.nodes(v, 1),
                       m.nodes(v, 2));
  int next = n + 1, eid = 1;
  for (std::size_t k = 0; k < m.members.size(); ++k) {
    const auto& mb = m.members[k];
    const Vec3 a = m.nodes.row(mb.i).transpose(), c = m.nodes.row(mb.j).transpose();
    constexpr int kNe = 4;
    int ids[2 * kNe + 1];
    ids[0] = mb.i + 1;
    ids[2 * kNe] = mb.j + 1;
    for (int q = 1; q < 2 * kNe; ++q) {
      const Vec3 p = a + (c - a) * (q / (2.0 * kNe));
      ids[q] = next++;
      inp << fmt::format("{},{:.12g},{:.12g},{:.12g}\n", ids[q], p.x(), p.y(), p.z());
    }
    elems << fmt::format("*ELEMENT, TYPE=B32R, ELSET=M{}\n", k);
    for (int e = 0; e < kNe; ++e)
      elems << fmt::format("{},{},{},{}\n", eid++, ids[2 * e], ids[2 * e + 1], ids[2 * e + 2]);
    const fem::Mat3 R = fem::element_frame(a, c, Vec3::Zero());
    sections << fmt::format(
        "*BEAM SECTION, ELSET=M{}, MATERIAL=STEEL, SECTION={}\n{:.12g},{:.12g},{:.12g}\n", k,
        card(k), R(0, 1), R(1, 1), R(2, 1));
  }
  inp << elems.str() << sections.str();
  inp << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11,0.3\n*BOUNDARY\n";
  for (int v : supports) inp << fmt::format("{},1,3\n", v + 1);
  inp << step << "\n*CLOAD\n";
  for (const auto& l : m.loads)
    for (int c = 0; c < 3; ++c)
      if (l.force(c) != 0)
        inp << fmt::format("{},{},{:.12g}\n", l.node + 1, c + 1, load_factor * l.force(c));
  inp << "*NODE PRINT, NSET=NALL\nU\n*END STEP\n";
  return inp.str();
}

/// The deck with every member a solid square of side `side`.
inline std::string ccx_frame_deck(const fem::FrameModel& m, const std::vector<int>& supports,
                                  double side, const std::string& step,
                                  double load_factor = 1) {
  return ccx_frame_deck(
      m, supports, [&](std::size_t) { return fmt::format("RECT\n{},{}", side, side); }, step,
      load_factor);
}

/// Runs ccx on `deck` in a fresh folder `name`; the folder (its .dat is job.dat), and whether ccx
/// succeeded.
struct CcxRun {
  std::filesystem::path dir;
  bool ok = false;
};
inline CcxRun run_ccx(const std::string& name, const std::string& deck) {
  CcxRun run{temp_dir(name)};
  std::ofstream(run.dir / "job.inp") << deck;
  const std::string cmd =
      fmt::format("cd '{}' && OMP_NUM_THREADS=2 ccx -i job > ccx.log 2>&1", run.dir.string());
  run.ok = std::system(cmd.c_str()) == 0;
  return run;
}

/// Displacements per node id (1-based) from a ccx .dat file; a non-linear step prints a block per
/// increment, and the last one wins.
inline std::map<int, Vec3> read_ccx_displacements(const std::filesystem::path& dat) {
  std::ifstream in(dat);
  std::map<int, Vec3> u;
  std::string line;
  bool block = false;
  while (std::getline(in, line)) {
    if (line.find("displacements") != std::string::npos) {
      block = true;
      continue;
    }
    std::istringstream ss(line);
    int id;
    double x, y, z;
    if (block && ss >> id >> x >> y >> z) u[id] = Vec3(x, y, z);
  }
  return u;
}

}  // namespace gridshell::test
