#pragma once
/// \file progress_display.h
/// The command line's progress display on stderr (CONTRACT: "progress for anything longer than about a
/// second goes to stderr; --quiet silences it"). A stage appears once it has run for a second:
/// on a terminal as one bar redrawn in place (at most 10 times a second; log lines are printed
/// above it, the bar redrawn below), otherwise as a plain line at each quarter and at the end,
/// so a log file gets a handful of lines per stage rather than a stream of carriage returns.

#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <spdlog/sinks/sink.h>

#include "gridshell/core/progress.h"

namespace gridshell {

class ProgressDisplay {
 public:
  /// `out`: where to draw (stderr); `terminal`: draw a bar in place rather than lines;
  /// `show_after`: seconds a stage runs before it is shown.
  ProgressDisplay(std::FILE* out, bool terminal, double show_after = 1.0);

  /// The callback to hand to the library's options (keeps this display alive).
  static Progress callback(const std::shared_ptr<ProgressDisplay>& display);

  void report(std::string_view stage, double fraction, std::string_view detail);
  /// Writes a log line, keeping a bar on a terminal below it.
  void log(std::string_view line);

 private:
  using Clock = std::chrono::steady_clock;
  struct Stage {
    Clock::time_point start;
    int quarter = -1;  ///< last quarter printed (lines mode)
  };
  void draw_bar(std::string_view stage, double fraction, std::string_view detail, double seconds);
  void clear_bar();

  std::FILE* out_;
  bool terminal_;
  double show_after_;
  std::mutex mutex_;
  std::map<std::string, Stage, std::less<>> stages_;
  std::string bar_;  ///< the bar as last drawn (terminal mode; empty: none shown)
  Clock::time_point last_draw_{};
};

/// A log sink that writes through `display` (used as the default logger's only sink).
std::shared_ptr<spdlog::sinks::sink> log_sink(const std::shared_ptr<ProgressDisplay>& display);

}  // namespace gridshell
