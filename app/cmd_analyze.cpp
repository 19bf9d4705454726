// gridshell analyze: not implemented yet (issue 5).

#include <iostream>

#include "common.h"

namespace gridshell::app {

void register_analyze(CLI::App& app, Action& action) {
  CLI::App* sub = app.add_subcommand("analyze", "(not implemented yet)");
  sub->allow_extras();
  sub->callback([&action] {
    action = [] {
      std::cerr << "gridshell: error: analyze: not implemented yet (issue 5)\n";
      return 2;
    };
  });
}

}  // namespace gridshell::app
