#include "gridshell/pipeline/frame_output.h"

#include <algorithm>
#include <array>
#include <string>

#include <fmt/format.h>

#include "gridshell/io/files.h"
#include "gridshell/io/frame_model_json.h"
#include "gridshell/io/mesh_io.h"

namespace gridshell {

namespace {
std::string fmt_num(double x) {
  return io::format_number(x);
}
/// A name as one CSV cell: separators and quotes (possible in a MODEL.json's names) as spaces.
std::string csv_name(std::string name) {
  for (char& c : name)
    if (c == ',' || c == '"' || c == '\n' || c == '\r') c = ' ';
  return name;
}
}  // namespace

void write_frame_outputs(const std::filesystem::path& dir, const fem::FrameModel& model,
                         const std::vector<int>& supports, const analysis::FrameResult& r,
                         BeamsCsv beams) {
  std::vector<char> is_support(model.num_nodes(), 0);
  for (int v : supports)
    if (v >= 0 && v < model.num_nodes()) is_support[v] = 1;
  {
    std::string s = "node,x,y,z,ux,uy,uz,support\n";
    for (int v = 0; v < model.num_nodes(); ++v)
      s += fmt::format("{},{},{},{},{},{},{},{}\n", v, fmt_num(model.nodes(v, 0)),
                       fmt_num(model.nodes(v, 1)), fmt_num(model.nodes(v, 2)),
                       fmt_num(r.displacement(v, 0)), fmt_num(r.displacement(v, 1)),
                       fmt_num(r.displacement(v, 2)), int(is_support[v]));
    io::write_file_atomic(dir / "nodes.csv", s);
  }
  if (beams == BeamsCsv::Write) {
    std::string s =
        "beam,node_i,node_j,length,axial_force,utilisation,buckling_utilisation,section,"
        "governing\n";
    for (size_t m = 0; m < model.members.size(); ++m) {
      const checks::MemberCheck& c = r.checks.members[m];
      s += fmt::format("{},{},{},{},{},{},{},{},{}\n", m, model.members[m].i, model.members[m].j,
                       fmt_num(fem::member_length(model, static_cast<int>(m))),
                       fmt_num(r.axial_force[m]), fmt_num(c.section), fmt_num(c.buckling),
                       csv_name(model.sections[model.members[m].section].name),
                       c.buckling > c.section ? c.buckling_governing : c.section_governing);
    }
    io::write_file_atomic(dir / "beams.csv", s);
  }
  {
    std::string s = "lambda,displacement\n";
    for (const auto& p : r.path)
      s += fmt::format("{},{}\n", fmt_num(p.lambda), fmt_num(p.displacement));
    io::write_file_atomic(dir / "path.csv", s);
  }
  write_buckling_modes(dir, r);
  if (r.nonlinear_displacement) {
    const Points& U = *r.nonlinear_displacement;
    const Points& R = *r.nonlinear_rotation;
    std::string s = "node,x,y,z,ux,uy,uz,support,rx,ry,rz\n";
    for (int v = 0; v < model.num_nodes(); ++v)
      s += fmt::format("{},{},{},{},{},{},{},{},{},{},{}\n", v, fmt_num(model.nodes(v, 0)),
                       fmt_num(model.nodes(v, 1)), fmt_num(model.nodes(v, 2)), fmt_num(U(v, 0)),
                       fmt_num(U(v, 1)), fmt_num(U(v, 2)), int(is_support[v]), fmt_num(R(v, 0)),
                       fmt_num(R(v, 1)), fmt_num(R(v, 2)));
    io::write_file_atomic(dir / "nodes_nonlinear.csv", s);
  }
  {
    std::vector<std::array<int, 2>> lines;
    Eigen::MatrixXd axial(model.members.size(), 1);
    for (size_t m = 0; m < model.members.size(); ++m) {
      lines.push_back({model.members[m].i, model.members[m].j});
      axial(m, 0) = r.axial_force[m];
    }
    Eigen::MatrixXd disp = r.displacement;
    Eigen::MatrixXd sup(model.num_nodes(), 1);
    for (int v = 0; v < model.num_nodes(); ++v) sup(v, 0) = is_support[v];
    io::write_vtp_lines(dir / "frame.vtp", model.nodes, lines,
                        {{"displacement", disp}, {"support", sup}}, {{"axial_force", axial}});
  }
}

void write_buckling_modes(const std::filesystem::path& dir, const analysis::FrameResult& r,
                          int count) {
  if (r.buckling_modes.empty()) return;
  std::string s = "mode,lambda,joint,ux,uy,uz\n";
  const int n = std::min(count, static_cast<int>(r.buckling_modes.size()));
  for (int k = 0; k < n; ++k) {
    const Points& shape = r.buckling_modes[k];
    for (int v = 0; v < static_cast<int>(shape.rows()); ++v)
      s += fmt::format("{},{},{},{},{},{}\n", k + 1, fmt_num(r.buckling_lambdas[k]), v,
                       fmt_num(shape(v, 0)), fmt_num(shape(v, 1)), fmt_num(shape(v, 2)));
  }
  io::write_file_atomic(dir / "modes.csv", s);
}

void write_frame_json(const std::filesystem::path& dir, const fem::FrameModel& model,
                      const analysis::GridshellFrameOptions& frame,
                      const analysis::FrameAnalysisOptions& options,
                      analysis::AnalysisLevel level) {
  fem::FrameModel m = model;
  for (fem::FrameMaterial& mat : m.materials)
    if (!(mat.fy > 0)) mat.fy = options.checks.fy;
  std::vector<io::NodalLoadCase> cases;
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, double>>>> combinations;
  if (frame.loads == analysis::LoadModel::eurocode) {
    const PolyMesh mesh{model.nodes, model.faces};
    const std::vector<analysis::LoadCase> lc =
        analysis::eurocode_cases(mesh, analysis::bar_weights_per_m(model, frame), frame);
    for (const analysis::LoadCase& c : lc) {
      io::NodalLoadCase out{c.name, c.permanent, {}};
      for (int v = 0; v < static_cast<int>(c.F.size()); ++v)
        if (c.F[v].squaredNorm() > 0) out.loads.push_back({v, c.F[v], Vec3::Zero()});
      cases.push_back(std::move(out));
    }
    for (const analysis::LoadCombination& c : analysis::eurocode_combinations(lc))
      combinations.emplace_back(c.name, c.factors);
  }
  nlohmann::json j = io::frame_model_to_json(m, cases, combinations);
  nlohmann::json a;
  a["linear"] = level != analysis::AnalysisLevel::none;
  a["buckling"] = level == analysis::AnalysisLevel::buckling ||
                  level == analysis::AnalysisLevel::nonlinear;
  a["nonlinear"] = level == analysis::AnalysisLevel::nonlinear;
  if (model.num_nodes() > 0) {
    const Eigen::RowVector3d lo = model.nodes.colwise().minCoeff(),
                             hi = model.nodes.colwise().maxCoeff();
    const double span = std::max(hi(0) - lo(0), hi(1) - lo(1));
    a["stop_displacement"] = options.arc.max_displacement > 0 ? options.arc.max_displacement
                             : options.path_reach > 0 || !(span > 0)
                                 ? (hi - lo).maxCoeff() * std::max(options.path_reach, 1.0)
                                 : span / 5;
  }
  a["max_steps"] = options.arc.max_steps;
  j["analysis"] = a;
  io::write_file_atomic(dir / "frame.json", j.dump() + "\n");
}

}  // namespace gridshell
