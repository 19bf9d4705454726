// gridshell studio [SURFACE] [--port P]: a local web server with one page that designs the
// grid-shell live while the user moves sliders (src/gridshell/studio/server.h, docs/studio.md).

#include <csignal>
#include <iostream>

#include <spdlog/spdlog.h>

#include "common.h"
#include "gridshell/studio/server.h"

namespace gridshell::app {

namespace {

struct StudioArgs {
  std::string surface = kDefaultSurface;
  SurfaceOptions surface_options;
  int port = 8080;
  int threads = 0;
  bool quiet = false;
};

int run_studio_cmd(const StudioArgs& a) {
  RunOptions run;
  run.threads = a.threads;
  run.quiet = a.quiet;
  const auto guard = apply_run_options(run);
  studio::ServerOptions options;
  options.surface = a.surface;
  options.surface_options = a.surface_options;
  options.port = a.port;
  // A browser that closes a connection while an answer is being sent must not end the server.
  std::signal(SIGPIPE, SIG_IGN);
  studio::Server server(options);
  const int port = server.bind();
  // The URL on stderr, flushed: scripts and tests read the port from it (--port 0).
  std::cerr << "studio: http://127.0.0.1:" << port << "/" << std::endl;
  server.run();
  return 0;
}

}  // namespace

void register_studio(CLI::App& app, Action& action) {
  auto a = std::make_shared<StudioArgs>();
  CLI::App* sub = app.add_subcommand(
      "studio",
      "A local web page (127.0.0.1 only) that re-designs and re-analyses the grid-shell while "
      "you move sliders for D, A, cells, objective and symmetry");
  sub->add_option("surface", a->surface,
                  "the surface the page opens with: PLY/OBJ/OFF file or builtin:NAME (default "
                  "builtin:funicular); other files can be dropped on the page")
      ->default_str(kDefaultSurface);
  sub->add_option("--port", a->port, "TCP port on 127.0.0.1 (0 = any free port)")
      ->default_str("8080")
      ->check(CLI::Range(0, 65535));
  sub->add_option("--threads", a->threads, "worker threads (0 = all cores)")->default_str("0");
  sub->add_flag("--quiet", a->quiet, "no log lines per stage and request");
  add_surface_options(sub, a->surface_options);
  sub->footer(
      "Prints `studio: http://127.0.0.1:PORT/` on stderr and serves until stopped (Ctrl-C).\n"
      "API: GET /api/design?surface=builtin:funicular&D=2&A=2&cells=300 (docs/studio.md).");
  sub->callback([a, &action] { action = [a] { return run_studio_cmd(*a); }; });
}

}  // namespace gridshell::app
