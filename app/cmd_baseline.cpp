// gridshell baseline: not implemented yet (issue 8).

#include <iostream>

#include "common.h"

namespace gridshell::app {

void register_baseline(CLI::App& app, Action& action) {
  CLI::App* sub = app.add_subcommand("baseline", "(not implemented yet)");
  sub->allow_extras();
  sub->callback([&action] {
    action = [] {
      std::cerr << "gridshell: error: baseline: not implemented yet (issue 8)\n";
      return 2;
    };
  });
}

}  // namespace gridshell::app
