#include "gridshell/report/design_folder.h"

#include <algorithm>
#include <future>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "gridshell/analysis/gridshell_frame.h"
#include "gridshell/core/error.h"
#include "gridshell/field/field.h"
#include "gridshell/io/files.h"
#include "gridshell/io/mesh_io.h"
#include "gridshell/pipeline/design_report.h"
#include "gridshell/pipeline/frame_output.h"
#include "gridshell/pipeline/gridshell_output.h"
#include "gridshell/pipeline/structure.h"

namespace gridshell::report {

namespace {

/// report.json's analysed keys beyond design_report's (add_analysed_report: steel, loads, the
/// combinations and the governing ones, mass, sizing) with frame.json, and modes.csv. Returns
/// the seconds of the combinations' analyses (those other than the primary).
double add_structure_files(const std::filesystem::path& dir, const DesignFolderInput& in,
                           const analysis::GridshellFrameOptions& frame, nlohmann::json& report) {
  const DesignResult& r = *in.result;
  const DesignOptions& options = *in.options;
  AnalysedGridshell analysed;
  analysed.mesh = &r.mesh;
  analysed.supports = &r.supports;
  analysed.frame = &frame;
  analysed.options = &options.frame_analysis;
  analysed.level = options.analyze;
  analysed.structure = &*r.structure;
  analysed.sized = r.sizing ? &*r.sizing : nullptr;
  analysed.sizing_options = &options.sizing_options;
  analysed.steel = in.steel;
  analysed.sections = in.sections;
  analysed.carbon_factor = in.carbon_factor;
  const double combinations_s = add_analysed_report(dir, analysed, report);
  write_buckling_modes(dir, *r.structure);
  return combinations_s;
}

}  // namespace

nlohmann::json write_design_folder(const std::filesystem::path& dir, const DesignFolderInput& in) {
  if (!in.surface || !in.options || !in.result)
    throw Error("design folder", "no surface, options or design given");
  const DesignResult& r = *in.result;
  const DesignOptions& options = *in.options;
  const analysis::FrameResult* structure = r.structure ? &*r.structure : nullptr;
  Stopwatch folder;
  io::ensure_directory(dir);
  const GridShellOutput out = design_output(r);
  const analysis::GridshellFrameOptions frame = analysed_frame(options, r);
  const std::optional<fabrication::BeamResults> envelope =
      r.sizing ? std::optional(member_envelope(*r.sizing)) : std::nullopt;
  // The figures read only the finished design: they are drawn and written on a second thread
  // while the other files are written (the same bytes; docs/performance.md, "The design
  // folder's figures beside its files"). A failure there is rethrown below.
  // The field figure draws the field where it was computed: on a coarsened analysis surface
  // its triangles, not every input triangle (2 M of them took 5–8 s to draw).
  const bool coarse = r.analysis_field.size() > 0;
  std::future<std::vector<std::string>> figures_job = std::async(std::launch::async, [&] {
    return figures::write_figures(dir,
                                  {.title = in.title,
                                   .gridshell = &r.mesh,
                                   .supports = r.supports,
                                   .structure = structure,
                                   .surface = coarse ? &r.analysis_mesh : &in.surface->mesh,
                                   .field = coarse ? &r.analysis_field : &r.field},
                                  in.figures);
  });
  write_gridshell_files(dir, out);
  Stopwatch fabrication_watch;
  const nlohmann::json bom = fabrication_report(dir, r.mesh, r.supports, structure, frame,
                                                in.sheet, envelope ? &*envelope : nullptr);
  const double fabrication_s = fabrication_watch.seconds();
  io::write_vtp(dir / "field.vtp", in.surface->mesh, {}, field_attributes(r.field),
                io::VtpEncoding::binary);
  nlohmann::json report = design_report(r, options);
  double combinations_s = 0;
  report["surface"] = in.surface_name;
  report["fabrication"] = bom;
  if (structure) combinations_s = add_structure_files(dir, in, frame, report);
  if (in.search) report["objective"] = in.search->report();
  Stopwatch figures_wait;
  report["figures"] = figures_job.get();
  // The stages still add up to the run's wall time: `figures` is what the figures took beyond
  // the other files (the wait for their thread).
  const double figures_s = figures_wait.seconds();
  Timings extra = in.timings_before;
  extra.add("write", folder.seconds() - fabrication_s - figures_s - combinations_s);
  extra.add("fabrication", fabrication_s);
  extra.add("figures", figures_s);
  if (combinations_s > 0) extra.add("combinations", combinations_s);
  // The search's other candidates (the chosen design's own stages are in r.timings).
  if (in.search) extra.add("objective_search", std::max(0.0, in.search->seconds - r.timings.sum()));
  report["timings_s"] = timings_block(r.timings, extra, in.seconds_before + folder.seconds());
  io::write_file_atomic(dir / "config.json", in.config.dump(2) + "\n");
  io::write_file_atomic(dir / "report.json", report.dump(2) + "\n");
  ReportInput page = gridshell_report_input(r.mesh, r.supports, structure);
  page.density = out.d_target;
  if (structure) page.beam_sections = member_designations(frame);  // sized: one per beam
  if (envelope) {  // sized: the envelope over the ULS combinations, as beams.csv has it
    page.utilisation = envelope->utilisation;
    page.buckling_utilisation = envelope->buckling_utilisation;
  }
  write_report_page(dir, std::move(page), report, in.config);
  return report;
}

ReportWritten write_report_page(const std::filesystem::path& dir, ReportInput page,
                                const nlohmann::json& report, const nlohmann::json& config) {
  page.config = config;
  page.report = report;
  std::string title = fmt::format("gridshell {}", config.value("command", std::string("design")));
  const nlohmann::json positional = config.value("positional", nlohmann::json::array());
  for (const auto& p : positional) title += fmt::format(" {}", p.get<std::string>());
  if (positional.empty() && report.contains("surface"))
    title += fmt::format(" {}", report["surface"].get<std::string>());
  page.title = std::move(title);
  ReportWritten w = write_report_html(dir, page);
  spdlog::info("[report] report.html: {:.1f} MB, {} figures, {:.3f} s", w.bytes / 1e6, w.figures,
               w.seconds);
  return w;
}

}  // namespace gridshell::report
