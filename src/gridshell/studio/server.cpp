#include "gridshell/studio/server.h"

#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

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

/// The CLI's line for an Error.
std::string error_line(const Error& e) {
  return "gridshell: error: " + e.message() + "\n";
}

Params query_params(const httplib::Request& req) {
  Params p;
  for (const auto& [name, value] : req.params) p.emplace_back(name, value);
  return p;
}

/// A fresh private folder under the system's temporary folder.
std::filesystem::path scratch_folder(const std::string& what, std::uint64_t n) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("gridshell-studio-" + std::to_string(::getpid()) + "-" + what + "-" + std::to_string(n));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace

struct Server::State {
  ServerOptions options;
  httplib::Server http;
  std::thread thread;
  int port = -1;

  std::mutex surfaces_mutex;  // guards surfaces and uploads
  std::map<std::string, std::shared_ptr<const NamedSurface>> surfaces;
  std::uint64_t uploads = 0;
  std::string initial;

  std::mutex design_mutex;  // one design at a time; guards `last`
  std::atomic<std::uint64_t> latest{0};
  std::optional<StudioDesign> last;
  std::string last_query;
  std::atomic<std::uint64_t> scratch{0};

  std::shared_ptr<const NamedSurface> surface(const std::string& id) {
    std::lock_guard lock(surfaces_mutex);
    const auto it = surfaces.find(id);
    if (it != surfaces.end()) return it->second;
    if (id.rfind("builtin:", 0) != 0)
      throw Error("surface", "unknown surface '" + id +
                                 "' (builtin:NAME, or a file dropped on "
                                 "the page)");
    auto s = std::make_shared<NamedSurface>(NamedSurface{id, load_surface(id)});
    surfaces[id] = s;
    return s;
  }

  std::string add_upload(const std::string& name, const std::string& bytes) {
    const std::filesystem::path file_name = std::filesystem::path(name).filename();
    if (file_name.empty()) throw Error("upload", "no file name given (?name=FILE.ply)");
    const std::filesystem::path dir = scratch_folder("upload", ++scratch);
    const std::filesystem::path path = dir / file_name;
    io::write_file_atomic(path, bytes);
    std::shared_ptr<NamedSurface> s;
    try {
      s = std::make_shared<NamedSurface>(
          NamedSurface{file_name.string(), load_surface(path.string(), options.surface_options)});
    } catch (const Error& e) {
      // The message names the file as the user did, not our scratch copy.
      std::filesystem::remove_all(dir);
      std::string message = e.message();
      for (std::size_t at; (at = message.find(path.string())) != std::string::npos;)
        message.replace(at, path.string().size(), file_name.string());
      throw Error("", message);
    } catch (...) {
      std::filesystem::remove_all(dir);
      throw;
    }
    std::filesystem::remove_all(dir);
    std::lock_guard lock(surfaces_mutex);
    const std::string id = "upload:" + std::to_string(uploads++);
    surfaces[id] = std::move(s);
    return id;
  }

  /// Designs `request` unless a newer design request came in (nullopt: superseded).
  std::optional<nlohmann::json> design(const StudioRequest& request, std::uint64_t generation) {
    const auto surface_ptr = surface(request.surface);
    std::lock_guard lock(design_mutex);
    if (generation != latest) return std::nullopt;
    const std::string query = request_query(request);
    if (!last || last_query != query) {
      last.reset();
      // A newer request stops the design at its next step or candidate (request.h).
      try {
        last = design_request(surface_ptr->surface, request,
                              [this, generation] { return generation != latest; });
      } catch (const Stopped&) {
        return std::nullopt;
      }
      last_query = query;
    }
    if (generation != latest) return std::nullopt;
    return design_answer(*last, surface_ptr->name);
  }

  std::string export_zip(const StudioRequest& request) {
    const auto surface_ptr = surface(request.surface);
    std::lock_guard lock(design_mutex);
    const std::string query = request_query(request);
    if (!last || last_query != query) {
      last.reset();
      last = design_request(surface_ptr->surface, request);
      last_query = query;
    }
    const std::filesystem::path dir = scratch_folder("export", ++scratch);
    try {
      write_design_folder(dir, *last, surface_ptr->surface, surface_ptr->name);
      std::string zip = zip_stored(zip_entries_of(dir));
      std::filesystem::remove_all(dir);
      return zip;
    } catch (...) {
      std::filesystem::remove_all(dir);
      throw;
    }
  }
};

Server::Server(const ServerOptions& options) : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.options = options;
  if (options.surface.rfind("builtin:", 0) == 0) {
    (void)s.surface(options.surface);
    s.initial = options.surface;
  } else {
    auto named = std::make_shared<NamedSurface>(
        NamedSurface{std::filesystem::path(options.surface).filename().string(),
                     load_surface(options.surface, options.surface_options)});
    s.surfaces["upload:0"] = std::move(named);
    s.uploads = 1;
    s.initial = "upload:0";
  }
  httplib::Server& http = s.http;
  http.set_payload_max_length(256u << 20);
  // SO_REUSEADDR only: the library's default adds SO_REUSEPORT, with which a second studio on
  // the same port would start and share the requests instead of failing.
  http.set_socket_options([](int sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });

  // Every handler answers Error with 400 and the CLI's line; anything else with 500.
  auto guarded = [this](auto body) {
    return [this, body](const httplib::Request& req, httplib::Response& res) {
      try {
        body(req, res);
      } catch (const Error& e) {
        res.status = 400;
        res.set_content(error_line(e), "text/plain; charset=utf-8");
      } catch (const std::bad_alloc&) {
        res.status = 500;
        res.set_content("gridshell: error: out of memory\n", "text/plain; charset=utf-8");
      } catch (const std::exception& e) {
        res.status = 500;
        res.set_content(std::string("gridshell: internal error: ") + e.what() + "\n",
                        "text/plain; charset=utf-8");
      }
      spdlog::info("studio: {} {} → {}", req.method, req.path, res.status < 0 ? 200 : res.status);
    };
  };

  http.Get("/", guarded([](const httplib::Request&, httplib::Response& res) {
             res.set_content(studio_page(), "text/html; charset=utf-8");
           }));
  http.Get("/api/surfaces", guarded([this](const httplib::Request&, httplib::Response& res) {
             State& st = *state_;
             nlohmann::json list = nlohmann::json::array();
             for (const std::string& name : builtin_names())
               list.push_back({{"id", "builtin:" + name}, {"name", name}});
             {
               std::lock_guard lock(st.surfaces_mutex);
               for (const auto& [id, surface] : st.surfaces)
                 if (id.rfind("upload:", 0) == 0)
                   list.push_back({{"id", id}, {"name", surface->name}});
             }
             res.set_content(nlohmann::json{{"surfaces", list}, {"initial", st.initial}}.dump(),
                             "application/json");
           }));
  http.Post("/api/surface", guarded([this](const httplib::Request& req, httplib::Response& res) {
              const std::string name = req.get_param_value("name");
              const std::string id = state_->add_upload(name, req.body);
              const auto loaded = state_->surface(id);
              res.set_content(nlohmann::json{{"surface", id},
                                             {"name", loaded->name},
                                             {"vertices", loaded->surface.mesh.num_vertices()},
                                             {"triangles", loaded->surface.mesh.num_faces()},
                                             {"supports", loaded->surface.supports.size()}}
                                  .dump(),
                              "application/json");
            }));
  http.Get("/api/design", guarded([this](const httplib::Request& req, httplib::Response& res) {
             State& st = *state_;
             const std::uint64_t generation = ++st.latest;
             const StudioRequest request = parse_request(query_params(req));
             const auto start = std::chrono::steady_clock::now();
             std::optional<nlohmann::json> answer = st.design(request, generation);
             if (!answer) {
               res.status = 409;
               res.set_content("superseded by a newer request\n", "text/plain; charset=utf-8");
               return;
             }
             (*answer)["generation"] = generation;
             (*answer)["seconds"] =
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
             res.set_content(answer->dump(), "application/json");
           }));
  http.Get("/api/config.json", guarded([this](const httplib::Request& req, httplib::Response& res) {
             const StudioRequest request = parse_request(query_params(req));
             const auto loaded = state_->surface(request.surface);
             res.set_header("Content-Disposition", "attachment; filename=\"config.json\"");
             res.set_content(request_config(request, loaded->name).dump(2) + "\n",
                             "application/json");
           }));
  http.Get("/api/export.zip", guarded([this](const httplib::Request& req, httplib::Response& res) {
             const StudioRequest request = parse_request(query_params(req));
             res.set_header("Content-Disposition", "attachment; filename=\"gridshell_design.zip\"");
             res.set_content(state_->export_zip(request), "application/zip");
           }));
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

std::string studio_page() {
  std::string page(studio_template());
  const std::string key = "@STUDIO@";
  const std::size_t at = page.find(key);
  if (at != std::string::npos) page.replace(at, key.size(), studio_script());
  return page;
}

}  // namespace gridshell::studio
