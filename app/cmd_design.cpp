// gridshell design: not implemented yet (issue 3).

#include <iostream>

#include "common.h"

namespace gridshell::app {

void register_design(CLI::App& app, Action& action) {
  CLI::App* sub = app.add_subcommand("design", "(not implemented yet)");
  sub->allow_extras();
  sub->callback([&action] {
    action = [] {
      std::cerr << "gridshell: error: design: not implemented yet (issue 3)\n";
      return 2;
    };
  });
}

}  // namespace gridshell::app
