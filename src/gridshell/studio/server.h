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
/// Who may ask (docs/studio.md, "What the studio protects"): a request whose Host is not the
/// server's own `127.0.0.1:PORT` (or `localhost:PORT`), whose Origin, when sent, is not its own
/// page, or whose Sec-Fetch-Site, when sent, is not same-origin (or none: the user opened the
/// page itself; not for /api), is answered 403
/// without work; every /api request must carry the per-run token (`X-Gridshell-Token`, random,
/// written into the page at GET /) or gets 403. Uploads are capped at kMaxUploadBytes however
/// they are sent (chunked, compressed: counted as read, 413); other requests have no body.
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
/// path at its next step, an objective search before its next candidate (request.h). Only a
/// valid request (parsed, its surface loaded) takes a number: a bad one never stops a design.
/// The last design is kept, so that an export of it costs only the files; an export while a
/// design or another export runs is answered 503 (busy), and an export that has to design is
/// stopped (409) by a newer design request like a design is.
///
/// Memory: loaded surfaces are kept in a least-recently-used cache of at most
/// kMaxCachedSurfaces built-ins and uploads and kMaxCachedVertices vertices (the page's first
/// surface is always kept); built-in specs are cached under their canonical text
/// (canonical_builtin: `span=20` and `span=20.0` are one entry). Surfaces load one at a time
/// outside the lock that guards the cache; an upload while another loads is answered 503.
/// Designs (without an objective) of the same surface, cells or length, symmetry, panels and
/// analysis share one DesignCache (pipeline/design.h): the analysis surface and its shell
/// stress once, the field and the deformed surface M′ once per (D, A), for at most
/// kMaxCachedFields pairs; another surface or setting starts a new one. A new seed, or a
/// slider moved back, then costs the tessellation and the analysis only; the design is the
/// same as without the cache.

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "gridshell/surfaces/load.h"

namespace gridshell::studio {

inline constexpr std::size_t kMaxUploadBytes = 64u << 20;  ///< an uploaded file, after decoding
inline constexpr int kMaxCachedSurfaces = 8;               ///< besides the page's first surface
inline constexpr long kMaxCachedVertices = 4'000'000;
/// Fields (D, A pairs) whose field and M′ the designs of one surface keep (server.h "Memory").
inline constexpr std::size_t kMaxCachedFields = 8;

struct ServerOptions {
  std::string surface = kDefaultSurface;  ///< what the page opens with (builtin:NAME or a file)
  SurfaceOptions surface_options;         ///< for that file and for uploads
  std::string host = "127.0.0.1";
  int port = 8080;  ///< 0: any free port (port() tells which)
  /// Tests only: called at named points of a design request, on the request's thread —
  /// "queued" (a valid /api/design request took its number) and "check" (a running design asks
  /// whether a newer request came in: before each candidate of an objective search, at each step
  /// of a non-linear path). A hook that blocks holds the server there, so a test can order
  /// events without watching the clock.
  std::function<void(std::string_view point)> pause_hook;
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
  /// The per-run token the page sends in `X-Gridshell-Token` (32 hex digits from getrandom).
  const std::string& token() const;
  /// Surfaces in the cache now (the page's first one included).
  int cached_surfaces() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// The page with its script inlined and `token` written into it.
std::string studio_page(const std::string& token = "");

}  // namespace gridshell::studio
