// gridshell stress: not implemented yet (issue 4).

#include <iostream>

#include "common.h"

namespace gridshell::app {

void register_stress(CLI::App& app, Action& action) {
  CLI::App* sub = app.add_subcommand("stress", "(not implemented yet)");
  sub->allow_extras();
  sub->callback([&action] {
    action = [] {
      std::cerr << "gridshell: error: stress: not implemented yet (issue 4)\n";
      return 2;
    };
  });
}

}  // namespace gridshell::app
