#include "gridshell/core/timings.h"

#include <algorithm>

#include <nlohmann/json.hpp>

namespace gridshell {

double& Timings::operator[](const std::string& stage) {
  const auto it = std::find_if(entries_.begin(), entries_.end(),
                               [&](const Entry& e) { return e.first == stage; });
  if (it != entries_.end()) return it->second;
  entries_.emplace_back(stage, 0.0);
  return entries_.back().second;
}

double Timings::get(const std::string& stage) const {
  for (const auto& [name, seconds] : entries_)
    if (name == stage) return seconds;
  return 0.0;
}

bool Timings::contains(const std::string& stage) const {
  return std::any_of(entries_.begin(), entries_.end(),
                     [&](const Entry& e) { return e.first == stage; });
}

double Timings::sum() const {
  double s = 0;
  for (const auto& [name, seconds] : entries_) s += seconds;
  return s;
}

void to_json(nlohmann::json& j, const Timings& t) {
  j = nlohmann::json::object();
  for (const auto& [stage, seconds] : t) j[stage] = seconds;
}

}  // namespace gridshell
