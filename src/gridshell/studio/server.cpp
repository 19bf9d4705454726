#include "gridshell/studio/server.h"

#include <sys/random.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>

#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <set>
#include <optional>
#include <thread>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "gridshell/core/error.h"
#include "gridshell/io/files.h"
#include "gridshell/studio/assets.h"
#include "gridshell/studio/request.h"
#include "gridshell/studio/zip.h"
#include "gridshell/surfaces/builtin.h"

// Last: it includes <resolv.h>, whose macro `_res` breaks Eigen headers included after it.
#include <httplib.h>

namespace gridshell::studio {

namespace {

/// A loaded surface and what the user called it (the positional argument of config.json).
struct NamedSurface {
  std::string name;
  Surface surface;
};

/// Answered 503: the server is busy with what this request would need.
struct Busy {
  std::string what;
};
/// Answered 409: a newer design request came in.
struct Superseded {};

/// The CLI's line for an Error.
std::string error_line(const Error& e) {
  return "gridshell: error: " + e.message() + "\n";
}

void answer_text(httplib::Response& res, int status, const std::string& text) {
  res.status = status;
  res.set_content(text, "text/plain; charset=utf-8");
}

Params query_params(const httplib::Request& req) {
  Params p;
  for (const auto& [name, value] : req.params) p.emplace_back(name, value);
  return p;
}

/// A fresh private folder (mode 0700, an unpredictable name) under the temporary folder.
std::filesystem::path scratch_folder() {
  std::string t = (std::filesystem::temp_directory_path() / "gridshell-studio-XXXXXX").string();
  if (::mkdtemp(t.data()) == nullptr)
    throw Error("studio", "cannot make a scratch folder in " +
                              std::filesystem::temp_directory_path().string());
  return t;
}

/// 32 hex digits from the kernel's random source.
std::string random_token() {
  unsigned char bytes[16];
  std::size_t got = 0;
  while (got < sizeof bytes) {
    const ssize_t n = ::getrandom(bytes + got, sizeof bytes - got, 0);
    if (n <= 0) throw Error("studio", "no random bytes for the token");
    got += static_cast<std::size_t>(n);
  }
  std::string hex;
  for (unsigned char b : bytes) hex += fmt::format("{:02x}", b);
  return hex;
}

/// Equal strings, in a time that does not depend on where they differ.
bool same_secret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

/// The name an upload is shown by: its last path component, printable characters only, at most
/// 100 bytes; its extension picks the reader (.ply, .obj, .off, .stl).
std::pair<std::string, std::string> upload_name(const std::string& given) {
  std::string name = given.substr(given.find_last_of("/\\") == std::string::npos
                                      ? 0
                                      : given.find_last_of("/\\") + 1);
  std::string clean;
  for (char c : name)
    if (static_cast<unsigned char>(c) >= 0x20 && c != 0x7f) clean += c;
  if (clean.size() > 100) clean.erase(0, clean.size() - 100);
  const auto dot = clean.rfind('.');
  std::string ext = dot == std::string::npos ? "" : clean.substr(dot);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (clean.empty()) throw Error("upload", "no file name given (?name=FILE.ply)");
  if (ext != ".ply" && ext != ".obj" && ext != ".off" && ext != ".stl")
    throw Error("upload", "'" + clean + "': the name must end in .ply, .obj, .off or .stl");
  return {clean, ext};
}

}  // namespace

struct Server::State {
  ServerOptions options;
  httplib::Server http;
  std::thread thread;
  int port = -1;
  std::string token = random_token();
  std::vector<std::string> hosts, origins;  // what Host and Origin may say (after bind)

  /// The surface cache (server.h "Memory"): least recently used first out.
  struct Cached {
    std::shared_ptr<const NamedSurface> surface;
    std::uint64_t used = 0;
    bool pinned = false;
  };
  std::mutex surfaces_mutex;  // guards surfaces, uploads, clock (held for map access only)
  std::map<std::string, Cached> surfaces;
  std::uint64_t uploads = 0, clock = 0;
  std::string initial;
  std::mutex load_mutex;  // one surface loads at a time

  std::mutex design_mutex;  // one design at a time; guards `last` and `shared`
  std::atomic<std::uint64_t> latest{0};
  std::optional<StudioDesign> last;
  std::string last_query;
  /// What the designs of one surface and design_cache_key share (request.h): the analysis
  /// surface and stress, per (D, A) the field and M′. One at a time, dropped when the surface or
  /// the key changes or when it holds kMaxCachedFields fields (its memory stays bounded).
  struct SharedDesignWork {
    std::string surface, key;
    std::set<std::pair<double, double>> fields;
    std::unique_ptr<DesignCache> cache;
  } shared;

  void hook(std::string_view point) const {
    if (options.pause_hook) options.pause_hook(point);
  }

  std::shared_ptr<const NamedSurface> cached(const std::string& id) {
    std::lock_guard lock(surfaces_mutex);
    const auto it = surfaces.find(id);
    if (it == surfaces.end()) return nullptr;
    it->second.used = ++clock;
    return it->second.surface;
  }

  void keep(const std::string& id, std::shared_ptr<const NamedSurface> s, bool pinned) {
    std::lock_guard lock(surfaces_mutex);
    surfaces[id] = Cached{std::move(s), ++clock, pinned};
    for (;;) {
      int count = 0;
      long vertices = 0;
      auto oldest = surfaces.end();
      for (auto it = surfaces.begin(); it != surfaces.end(); ++it) {
        vertices += it->second.surface->surface.mesh.num_vertices();
        if (it->second.pinned) continue;
        ++count;
        if (it->first != id && (oldest == surfaces.end() || it->second.used < oldest->second.used))
          oldest = it;
      }
      if ((count <= kMaxCachedSurfaces && vertices <= kMaxCachedVertices) ||
          oldest == surfaces.end())
        break;
      surfaces.erase(oldest);
    }
  }

  std::shared_ptr<const NamedSurface> surface(const std::string& id) {
    if (auto s = cached(id)) return s;
    if (id.rfind("builtin:", 0) != 0)
      throw Error("surface", "unknown surface '" + id +
                                 "' (builtin:NAME, or a file dropped on the page; the studio "
                                 "keeps the last few)");
    std::lock_guard load(load_mutex);
    if (auto s = cached(id)) return s;  // loaded while this one waited
    auto s = std::make_shared<const NamedSurface>(NamedSurface{id, load_surface(id)});
    keep(id, s, false);
    return s;
  }

  std::pair<std::string, std::shared_ptr<const NamedSurface>> add_upload(
      const std::string& given_name, const std::string& bytes) {
    const auto [name, ext] = upload_name(given_name);
    std::unique_lock load(load_mutex, std::try_to_lock);
    if (!load.owns_lock()) throw Busy{"another surface is loading; try again when it is done"};
    const std::filesystem::path dir = scratch_folder();
    const std::filesystem::path path = dir / ("upload" + ext);
    std::shared_ptr<NamedSurface> s;
    try {
      io::write_file_atomic(path, bytes);
      s = std::make_shared<NamedSurface>(
          NamedSurface{name, load_surface(path.string(), options.surface_options)});
    } catch (const Error& e) {
      // The message names the file as the user did, not our scratch copy.
      std::filesystem::remove_all(dir);
      std::string message = e.message();
      for (std::size_t at; (at = message.find(path.string())) != std::string::npos;)
        message.replace(at, path.string().size(), name);
      throw Error("", message);
    } catch (...) {
      std::filesystem::remove_all(dir);
      throw;
    }
    std::filesystem::remove_all(dir);
    std::string id;
    {
      std::lock_guard lock(surfaces_mutex);
      id = "upload:" + std::to_string(uploads++);
    }
    keep(id, s, false);
    return {id, s};
  }

  /// Designs `request` into `last` (nothing when `last` is that request) unless a newer design
  /// request than `generation` comes in (Superseded). Call with design_mutex held.
  void designed(const StudioRequest& request, const NamedSurface& surface,
                std::uint64_t generation) {
    const std::string query = request_query(request);
    if (last && last_query == query) return;
    last.reset();
    // A newer request stops the design at its next step or candidate (request.h).
    try {
      last = design_request(
          surface.surface, request,
          [this, generation] {
            hook("check");
            return generation != latest;
          },
          shared_work(request));
    } catch (const Stopped&) {
      throw Superseded{};
    }
    last_query = query;
  }

  /// The DesignCache a request's design may use (null with an objective). Call with
  /// design_mutex held.
  DesignCache* shared_work(const StudioRequest& request) {
    if (request.objective) return nullptr;
    const std::string key = design_cache_key(request);
    const std::pair<double, double> field{request.D, request.A};
    if (!shared.cache || shared.surface != request.surface || shared.key != key ||
        (!shared.fields.count(field) && shared.fields.size() >= kMaxCachedFields)) {
      shared.cache.reset();  // before the new one: never two caches' memory at once
      shared = SharedDesignWork{request.surface, key, {}, std::make_unique<DesignCache>()};
    }
    shared.fields.insert(field);
    return shared.cache.get();
  }

  nlohmann::json design(const StudioRequest& request, const NamedSurface& surface,
                        std::uint64_t generation) {
    std::lock_guard lock(design_mutex);
    if (generation != latest) throw Superseded{};
    designed(request, surface, generation);
    if (generation != latest) throw Superseded{};
    return design_answer(*last, surface.name);
  }

  std::string export_zip(const StudioRequest& request, const NamedSurface& surface) {
    std::unique_lock lock(design_mutex, std::try_to_lock);
    if (!lock.owns_lock()) throw Busy{"a design is running; export when it is done"};
    designed(request, surface, latest);  // a newer design request stops it
    const std::filesystem::path dir = scratch_folder();
    try {
      write_design_folder(dir / "design", *last, surface.surface, surface.name);
      std::string zip = zip_stored(zip_entries_of(dir / "design"));
      std::filesystem::remove_all(dir);
      return zip;
    } catch (...) {
      std::filesystem::remove_all(dir);
      throw;
    }
  }

  /// Whether a request may be answered at all (server.h "Who may ask"); else answers 403/404/413.
  bool admit(const httplib::Request& req, httplib::Response& res) const;
  void add_routes();
};

bool Server::State::admit(const httplib::Request& req, httplib::Response& res) const {
  const auto listed = [](const std::vector<std::string>& list, const std::string& x) {
    return std::find(list.begin(), list.end(), x) != list.end();
  };
  const bool api = req.path.rfind("/api/", 0) == 0;
  std::string refused;
  if (!listed(hosts, req.get_header_value("Host"))) {
    refused = "this server answers only to its own address";
  } else if (req.has_header("Origin") && !listed(origins, req.get_header_value("Origin"))) {
    refused = "requests from other pages are refused";
  } else if (req.has_header("Sec-Fetch-Site") &&
             req.get_header_value("Sec-Fetch-Site") != "same-origin" &&
             (api || req.get_header_value("Sec-Fetch-Site") != "none")) {
    // The page only when the user opened it (none) or it reloads itself: a page of another
    // origin that opens the studio's page (whose link can preset a design) is refused too.
    refused = "requests from other pages are refused";
  } else if (api && !same_secret(req.get_header_value("X-Gridshell-Token"), token)) {
    refused = "missing or wrong X-Gridshell-Token (reload the page)";
  }
  if (!refused.empty()) {
    answer_text(res, 403, "gridshell: error: studio: " + refused + "\n");
    return false;
  }
  const bool upload = req.method == "POST" && req.path == "/api/surface";
  const bool has_body = req.has_header("Transfer-Encoding") ||
                        (req.has_header("Content-Length") &&
                         req.get_header_value("Content-Length") != "0");
  if (!upload && (req.method != "GET" || has_body)) {
    answer_text(res, req.method == "GET" ? 413 : 405, "gridshell: error: studio: no such request\n");
    return false;
  }
  if (upload && req.has_header("Content-Length")) {
    const std::string n = req.get_header_value("Content-Length");
    if (n.size() > 12 || n.find_first_not_of("0123456789") != std::string::npos ||
        std::stoull(n) > 2 * kMaxUploadBytes) {  // up to twice: read and dropped (413)
      answer_text(res, 413,
                  fmt::format("gridshell: error: upload: larger than {} MiB\n", kMaxUploadBytes >> 20));
      return false;
    }
  }
  return true;
}

Server::Server(const ServerOptions& options) : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.options = options;
  if (options.surface.rfind("builtin:", 0) == 0) {
    s.initial = "builtin:" + canonical_builtin(options.surface.substr(8));
    s.keep(s.initial,
           std::make_shared<const NamedSurface>(NamedSurface{s.initial, load_surface(s.initial)}),
           true);
  } else {
    s.keep("upload:0",
           std::make_shared<const NamedSurface>(
               NamedSurface{std::filesystem::path(options.surface).filename().string(),
                            load_surface(options.surface, options.surface_options)}),
           true);
    s.uploads = 1;
    s.initial = "upload:0";
  }
  httplib::Server& http = s.http;
  http.set_payload_max_length(kMaxUploadBytes);
  // One request per connection: a refused request's unread body is never taken for the next.
  http.set_keep_alive_max_count(1);
  // SO_REUSEADDR only: the library's default adds SO_REUSEPORT, with which a second studio on
  // the same port would start and share the requests instead of failing.
  http.set_socket_options([](int sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    if (state_->admit(req, res)) return httplib::Server::HandlerResponse::Unhandled;
    spdlog::info("studio: {} {} → {} (refused)", req.method, req.path, res.status);
    return httplib::Server::HandlerResponse::Handled;
  });
  s.add_routes();
}

namespace {

/// Runs a handler: Error → 400 with the CLI's line, Busy → 503, Superseded → 409, anything
/// else → 500.
template <typename Body>
void answering(const httplib::Request& req, httplib::Response& res, const Body& body) {
  try {
    body();
  } catch (const Error& e) {
    answer_text(res, 400, error_line(e));
  } catch (const Busy& b) {
    answer_text(res, 503, "gridshell: busy: " + b.what + "\n");
  } catch (const Superseded&) {
    answer_text(res, 409, "superseded by a newer request\n");
  } catch (const std::bad_alloc&) {
    answer_text(res, 500, "gridshell: error: out of memory\n");
  } catch (const std::exception& e) {
    answer_text(res, 500, std::string("gridshell: internal error: ") + e.what() + "\n");
  }
  spdlog::info("studio: {} {} → {}", req.method, req.path, res.status < 0 ? 200 : res.status);
}

}  // namespace

void Server::State::add_routes() {
  using httplib::Request;
  using httplib::Response;
  http.Get("/", [this](const Request& req, Response& res) {
    answering(req, res, [&] {
      res.set_header("Cache-Control", "no-store");
      res.set_header("X-Frame-Options", "DENY");
      res.set_header("Content-Security-Policy", "frame-ancestors 'none'");
      res.set_header("Referrer-Policy", "no-referrer");
      res.set_content(studio_page(token), "text/html; charset=utf-8");
    });
  });
  http.Get("/api/surfaces", [this](const Request& req, Response& res) {
    answering(req, res, [&] {
      nlohmann::json list = nlohmann::json::array();
      for (const std::string& name : builtin_names())
        list.push_back({{"id", "builtin:" + name}, {"name", name}});
      {
        std::lock_guard lock(surfaces_mutex);
        for (const auto& [id, cached] : surfaces)
          if (id.rfind("upload:", 0) == 0)
            list.push_back({{"id", id}, {"name", cached.surface->name}});
      }
      res.set_content(nlohmann::json{{"surfaces", list}, {"initial", initial}}.dump(),
                      "application/json");
    });
  });
  http.Post("/api/surface", [this](const Request& req, Response& res,
                                   const httplib::ContentReader& reader) {
    answering(req, res, [&] {
      // Counted as decoded: a chunked or compressed body is held to the same cap.
      // Past the cap the rest is read and dropped, up to twice the cap, so that the client
      // gets its 413 on a connection that is still sound; beyond that the reading stops.
      std::string body;
      bool over = false;
      std::size_t received = 0;
      const bool read = reader([&](const char* data, std::size_t n) {
        received += n;
        if (received > kMaxUploadBytes) {
          over = true;
          body.clear();
          body.shrink_to_fit();
          return received <= 2 * kMaxUploadBytes;
        }
        body.append(data, n);
        return true;
      });
      if (over || res.status == 413) {
        answer_text(res, 413,
                    fmt::format("gridshell: error: upload: larger than {} MiB\n",
                                kMaxUploadBytes >> 20));
        return;
      }
      if (!read) throw Error("upload", "the file did not arrive whole");
      const auto [id, loaded] = add_upload(req.get_param_value("name"), body);
      res.set_content(nlohmann::json{{"surface", id},
                                     {"name", loaded->name},
                                     {"vertices", loaded->surface.mesh.num_vertices()},
                                     {"triangles", loaded->surface.mesh.num_faces()},
                                     {"supports", loaded->surface.supports.size()}}
                          .dump(),
                      "application/json");
    });
  });
  http.Get("/api/design", [this](const Request& req, Response& res) {
    answering(req, res, [&] {
      // Checked whole (parameters, surface, size) before it takes a number: a bad request
      // never stops the running design.
      const StudioRequest request = parse_request(query_params(req));
      const auto named = surface(request.surface);
      check_request_size(request, named->surface);
      const std::uint64_t generation = ++latest;
      hook("queued");
      const auto start = std::chrono::steady_clock::now();
      nlohmann::json answer = design(request, *named, generation);
      answer["generation"] = generation;
      answer["seconds"] =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      res.set_content(answer.dump(), "application/json");
    });
  });
  http.Get("/api/config.json", [this](const Request& req, Response& res) {
    answering(req, res, [&] {
      const StudioRequest request = parse_request(query_params(req));
      const auto named = surface(request.surface);
      check_request_size(request, named->surface);  // the same refusal as its design's
      res.set_header("Content-Disposition", "attachment; filename=\"config.json\"");
      res.set_content(request_config(request, named->name).dump(2) + "\n", "application/json");
    });
  });
  http.Get("/api/export.zip", [this](const Request& req, Response& res) {
    answering(req, res, [&] {
      const StudioRequest request = parse_request(query_params(req));
      const auto named = surface(request.surface);
      check_request_size(request, named->surface);
      res.set_header("Content-Disposition", "attachment; filename=\"gridshell_design.zip\"");
      res.set_content(export_zip(request, *named), "application/zip");
    });
  });
}

Server::~Server() {
  stop();
}

int Server::bind() {
  State& s = *state_;
  if (s.options.port == 0) {
    s.port = s.http.bind_to_any_port(s.options.host);
  } else {
    s.port = s.http.bind_to_port(s.options.host, s.options.port) ? s.options.port : -1;
  }
  if (s.port <= 0)
    throw Error("--port", "cannot listen on " + s.options.host + ":" +
                              std::to_string(s.options.port) + " (in use?)");
  const std::string port = ":" + std::to_string(s.port);
  s.hosts = {s.options.host + port};
  if (s.options.host == "127.0.0.1") s.hosts.push_back("localhost" + port);
  s.origins.clear();
  for (const std::string& h : s.hosts) s.origins.push_back("http://" + h);
  return s.port;
}

void Server::run() {
  state_->http.listen_after_bind();
}

int Server::start() {
  const int p = bind();
  state_->thread = std::thread([this] { run(); });
  for (int i = 0; i < 5000 && !state_->http.is_running(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return p;
}

void Server::stop() {
  state_->http.stop();
  if (state_->thread.joinable()) state_->thread.join();
}

int Server::port() const {
  return state_->port;
}

const std::string& Server::token() const {
  return state_->token;
}

int Server::cached_surfaces() const {
  std::lock_guard lock(state_->surfaces_mutex);
  return static_cast<int>(state_->surfaces.size());
}

std::string studio_page(const std::string& token) {
  std::string page(studio_template());
  const std::string key = "@STUDIO@", token_key = "@TOKEN@";
  const std::size_t t = page.find(token_key);  // in the head, before the script
  if (t != std::string::npos) page.replace(t, token_key.size(), token);
  const std::size_t at = page.find(key);
  if (at != std::string::npos) page.replace(at, key.size(), studio_script());
  return page;
}

}  // namespace gridshell::studio
