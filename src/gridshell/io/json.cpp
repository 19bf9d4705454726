#include "gridshell/io/json.h"

#include <fmt/format.h>

#include "gridshell/core/error.h"

namespace gridshell::io {

nlohmann::json parse_json(const std::string& text, const std::string& subject) {
  // The callback sees the depth of each object or array as it opens (depth 0 = the top level).
  const nlohmann::json::parser_callback_t limit =
      [&subject](int depth, nlohmann::json::parse_event_t event, nlohmann::json&) {
        if ((event == nlohmann::json::parse_event_t::object_start ||
             event == nlohmann::json::parse_event_t::array_start) &&
            depth >= kMaxJsonDepth)
          throw Error(subject, fmt::format("JSON nested deeper than {} levels", kMaxJsonDepth));
        return true;
      };
  return nlohmann::json::parse(text, limit);
}

}  // namespace gridshell::io
