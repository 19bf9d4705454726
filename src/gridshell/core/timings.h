#pragma once
/// \file timings.h
/// Wall-clock seconds per named stage, the one shape every result uses for its `timings` and
/// report.json writes as `timings_s` ({stage: seconds}); and a stopwatch to measure them.
///
///     Stopwatch clock;
///     … stage one …
///     r.timings.add("stress", clock.lap());
///
/// Timings are the one thing in a result that is not deterministic; nothing may depend on them.

#include <chrono>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace gridshell {

/// Seconds per stage, in the order the stages first ran. A stage timed again adds up.
class Timings {
 public:
  using Entry = std::pair<std::string, double>;

  Timings() = default;
  Timings(std::initializer_list<Entry> entries) {
    for (const auto& [stage, seconds] : entries) add(stage, seconds);
  }

  /// Adds `seconds` to `stage` (appended when new).
  void add(const std::string& stage, double seconds) { (*this)[stage] += seconds; }
  /// The seconds of `stage`, created at 0 when new.
  double& operator[](const std::string& stage);
  /// The seconds of `stage`; 0 when it has not run.
  double get(const std::string& stage) const;
  bool contains(const std::string& stage) const;
  /// The sum over all stages.
  double sum() const;

  bool empty() const { return entries_.empty(); }
  std::size_t size() const { return entries_.size(); }
  void clear() { entries_.clear(); }
  std::vector<Entry>::const_iterator begin() const { return entries_.begin(); }
  std::vector<Entry>::const_iterator end() const { return entries_.end(); }

 private:
  std::vector<Entry> entries_;
};

/// report.json's form: an object {stage: seconds}.
void to_json(nlohmann::json& j, const Timings& t);

/// Seconds since it was started (constructed) or since the last lap.
class Stopwatch {
 public:
  using Clock = std::chrono::steady_clock;

  Stopwatch() : start_(Clock::now()) {}
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  /// The seconds since the start or the last lap; starts the next lap.
  double lap() {
    const auto now = Clock::now();
    const double s = std::chrono::duration<double>(now - start_).count();
    start_ = now;
    return s;
  }

 private:
  Clock::time_point start_;
};

}  // namespace gridshell
