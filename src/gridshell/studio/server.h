#pragma once
/// \file server.h
/// `gridshell studio`: a local web server (cpp-httplib, 127.0.0.1 only) with one page that
/// designs a grid-shell live, and the JSON API behind it (docs/studio.md, CONTRACT "studio"):
///
///   GET  /                   the page (web/src/studio.html + studio.js, embedded at build time)
///   GET  /api/surfaces       {"surfaces": [{"id", "name"}...], "initial": id}
///   POST /api/surface?name=F the body is a PLY/OBJ/OFF file (F's extension says which); loaded
///                            by load_surface → {"surface": "upload:N", "name", "vertices",
///                            "triangles", "supports"}
///   GET  /api/design?…       the design of a request (studio/request.h) → JSON
///   GET  /api/config.json?…  its config.json (for `gridshell design --config`)
///   GET  /api/export.zip?…   the files `gridshell design -o` writes for it, zipped
///
/// Bad input (an unknown parameter or surface, D = 0, a malformed upload) → HTTP 400 with the
/// command line's line `gridshell: error: SUBJECT: WHAT` as text/plain; the server never stops
/// on it. Surfaces are `builtin:NAME` or `upload:N`; no path on the server's disk is read on a
/// request (the SURFACE given on the command line is loaded at start as upload:0).
///
/// One design at a time (a mutex). Each /api/design request takes a generation number; a
/// request that is no longer the newest when its turn comes, or when its design ends, is
/// answered HTTP 409 `superseded` without (further) work, so fast slider changes never build a
/// queue of stale designs; a running design stops when a newer request arrives — a non-linear
/// path at its next step, an objective search before its next candidate (request.h). The last design is kept, so that an export of it costs only the
/// files.

#include <memory>
#include <string>

#include "gridshell/surfaces/load.h"

namespace gridshell::studio {

struct ServerOptions {
  std::string surface = kDefaultSurface;  ///< what the page opens with (builtin:NAME or a file)
  SurfaceOptions surface_options;         ///< for that file and for uploads
  std::string host = "127.0.0.1";
  int port = 8080;  ///< 0: any free port (port() tells which)
};

class Server {
 public:
  /// Loads `options.surface` (throws Error for a bad one) and prepares the routes.
  explicit Server(const ServerOptions& options);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Binds the port; returns it. Throws Error("--port", …) when it is taken.
  int bind();
  /// Serves until stop() (call bind() first).
  void run();
  /// bind() and run() on a thread of its own; returns the port.
  int start();
  /// Stops serving and joins the thread of start(). Idempotent.
  void stop();
  int port() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// The page with its script inlined.
std::string studio_page();

}  // namespace gridshell::studio
