// gridshell sweep: not implemented yet (issue 8).

#include <iostream>

#include "common.h"

namespace gridshell::app {

void register_sweep(CLI::App& app, Action& action) {
  CLI::App* sub = app.add_subcommand("sweep", "(not implemented yet)");
  sub->allow_extras();
  sub->callback([&action] {
    action = [] {
      std::cerr << "gridshell: error: sweep: not implemented yet (issue 8)\n";
      return 2;
    };
  });
}

}  // namespace gridshell::app
