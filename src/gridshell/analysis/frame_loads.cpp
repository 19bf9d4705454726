#include "gridshell/analysis/frame_loads.h"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "gridshell/analysis/frame_records.h"
#include "gridshell/core/error.h"
#include "gridshell/fem/linear_cases.h"

namespace gridshell::analysis {

using namespace gridshell::fem;

std::vector<FrameResult> analyze_frame_loads(const FrameModel& model,
                                             const std::vector<FrameLoad>& loads,
                                             const FrameAnalysisOptions& o) {
  Stopwatch total, t;
  const FrameMesh mesh = discretize(model, o.subject);
  std::vector<Eigen::VectorXd> full;
  for (const FrameLoad& l : loads) {
    full.push_back(load_vector(mesh, l.loads, o.subject));
    if (full.back().norm() == 0) throw Error(o.subject, "no loads: nothing to analyse");
  }
  const FrameAssembler assembler(mesh);
  const double setup = t.seconds();
  t = Stopwatch();
  const std::vector<LinearResult> lin = linear_static_cases(mesh, assembler, full, o.subject);
  const double linear = t.seconds() / std::max<std::size_t>(loads.size(), 1);
  std::vector<FrameResult> out(loads.size());
  // Each load's figures read only the mesh, the assembler and its own solution.
  tbb::parallel_for(std::size_t{0}, loads.size(), [&](std::size_t k) {
    FrameResult& res = out[k];
    res.num_elements = static_cast<int>(mesh.elements.size());
    res.num_dofs = mesh.num_dofs;
    res.mass_kg = total_mass(model);
    res.total_length_m = total_length(model);
    res.nodes = model.nodes;
    res.timings["setup"] = setup;
    res.timings["linear"] = linear;
    detail::record_linear(mesh, assembler, lin[k], full[k], res);
    detail::record_checks(model, mesh, assembler, lin[k], o, res);
  });
  // The LBAs share K's factor (its solves keep workspaces): one after another.
  std::vector<BucklingResult> lba(loads.size());
  BucklingOptions bo;
  bo.modes = std::max(1, o.buckling_modes);
  for (std::size_t k = 0; k < loads.size(); ++k) {
    if (!loads[k].buckling) continue;
    t = Stopwatch();
    lba[k] = linear_buckling(mesh, assembler, lin[k], bo);
    out[k].timings["buckling"] = t.seconds();
  }
  tbb::parallel_for(std::size_t{0}, loads.size(), [&](std::size_t k) {
    if (loads[k].buckling) detail::record_buckling(mesh, assembler, lba[k], out[k]);
  });
  const double seconds = total.seconds() / std::max<std::size_t>(loads.size(), 1);
  for (FrameResult& r : out) r.timings["total"] = seconds;
  return out;
}

}  // namespace gridshell::analysis
