#pragma once
/// \file progress.h
/// How far a long computation has come, for whoever shows it. The library only calls the
/// function it is given; the command line draws a bar (or, when stderr is not a terminal, a line
/// per quarter) for stages that run longer than a second and stays silent with `--quiet`. An
/// empty Progress reports nothing — the default in every options struct, so library users and
/// tests pay nothing. Calls may come from several threads at once: the receiver serialises them.

#include <exception>
#include <functional>
#include <string_view>

namespace gridshell {

/// `stage`: what runs (e.g. "objective search"); `fraction` in [0, 1], 1 when the stage is done;
/// `detail`: a short counter such as "7/16 designs".
using Progress =
    std::function<void(std::string_view stage, double fraction, std::string_view detail)>;

inline void report_progress(const Progress& progress, std::string_view stage, double fraction,
                            std::string_view detail = {}) {
  if (progress) progress(stage, fraction, detail);
}

/// Asked by a long computation that can be stopped, between its units of work (never inside a
/// parallel loop's body, so nothing is left half done); true asks it to stop. May be called from
/// several threads. An empty one never stops anything — the default everywhere.
using StopRequest = std::function<bool()>;

/// Thrown by a computation that stopped because its StopRequest said so; nothing it would have
/// returned exists.
struct Stopped : std::exception {
  const char* what() const noexcept override { return "stopped on request"; }
};

inline bool stop_requested(const StopRequest& stop) { return stop && stop(); }

}  // namespace gridshell
