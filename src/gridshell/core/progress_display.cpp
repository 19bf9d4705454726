#include "gridshell/core/progress_display.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <spdlog/sinks/base_sink.h>

namespace gridshell {

namespace {

constexpr int kBarWidth = 30;

/// spdlog lines through the display, so that a bar on a terminal stays below them.
class DisplaySink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  explicit DisplaySink(std::shared_ptr<ProgressDisplay> display) : display_(std::move(display)) {}

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    spdlog::memory_buf_t text;
    formatter_->format(msg, text);
    display_->log(std::string_view(text.data(), text.size()));
  }
  void flush_() override {}

 private:
  std::shared_ptr<ProgressDisplay> display_;
};

}  // namespace

ProgressDisplay::ProgressDisplay(std::FILE* out, bool terminal, double show_after)
    : out_(out), terminal_(terminal), show_after_(show_after) {}

Progress ProgressDisplay::callback(const std::shared_ptr<ProgressDisplay>& display) {
  return [display](std::string_view stage, double fraction, std::string_view detail) {
    display->report(stage, fraction, detail);
  };
}

std::shared_ptr<spdlog::sinks::sink> log_sink(const std::shared_ptr<ProgressDisplay>& display) {
  return std::make_shared<DisplaySink>(display);
}

void ProgressDisplay::report(std::string_view stage, double fraction, std::string_view detail) {
  const std::lock_guard lock(mutex_);
  const Clock::time_point now = Clock::now();
  auto it = stages_.find(stage);
  if (it == stages_.end()) it = stages_.emplace(std::string(stage), Stage{now}).first;
  fraction = std::isfinite(fraction) ? std::clamp(fraction, 0.0, 1.0) : 0.0;
  const double seconds = std::chrono::duration<double>(now - it->second.start).count();
  const bool done = fraction >= 1.0;
  if (seconds >= show_after_) {
    if (terminal_) {
      if (done || now - last_draw_ >= std::chrono::milliseconds(100))
        draw_bar(stage, fraction, detail, seconds);
      if (done) {
        std::fputs("\n", out_);
        bar_.clear();
      }
    } else {
      const int quarter = static_cast<int>(std::floor(fraction * 4));
      if (quarter > it->second.quarter) {
        std::fputs(fmt::format("[{}] {:3.0f}% {} ({:.1f} s)\n", stage, 100 * fraction, detail,
                               seconds)
                       .c_str(),
                   out_);
        it->second.quarter = quarter;
      }
    }
    std::fflush(out_);
  }
  if (done) stages_.erase(it);
}

void ProgressDisplay::log(std::string_view line) {
  const std::lock_guard lock(mutex_);
  clear_bar();
  std::fwrite(line.data(), 1, line.size(), out_);
  if (!bar_.empty()) std::fputs(bar_.c_str(), out_);
  std::fflush(out_);
}

void ProgressDisplay::draw_bar(std::string_view stage, double fraction, std::string_view detail,
                               double seconds) {
  const int filled = static_cast<int>(std::lround(fraction * kBarWidth));
  std::string bar;
  for (int k = 0; k < kBarWidth; ++k) bar += k < filled ? "█" : "░";
  clear_bar();
  bar_ = fmt::format("[{}] {} {:3.0f}% {} ({:.0f} s)", stage, bar, 100 * fraction, detail, seconds);
  std::fputs(bar_.c_str(), out_);
  last_draw_ = Clock::now();
}

void ProgressDisplay::clear_bar() {
  if (terminal_ && !bar_.empty()) std::fputs("\r\033[K", out_);
}

}  // namespace gridshell
