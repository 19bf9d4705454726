// gridshell: from a free-form roof surface to a stress-aware Voronoi steel-and-glass grid-shell.
// The front end only parses arguments and dispatches; every stage lives in src/gridshell/.

#include <iostream>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "common.h"
#include "gridshell/core/error.h"

namespace gridshell::app {
void register_kit(CLI::App& app, Action& action);  // cmd_kit.cpp
}  // namespace gridshell::app

namespace {

int run(int argc, char** argv) {
  using namespace gridshell;
  spdlog::set_default_logger(spdlog::stderr_color_st("gridshell"));
  spdlog::set_pattern("%v");
  CLI::App cli{"gridshell: stress-driven Voronoi grid-shells from free-form surfaces"};
  cli.require_subcommand(1);
  app::Action action;
  app::register_info(cli, action);
  app::register_stress(cli, action);
  app::register_design(cli, action);
  app::register_analyze(cli, action);
  app::register_sweep(cli, action);
  app::register_baseline(cli, action);
  app::register_studio(cli, action);
  app::register_kit(cli, action);

  std::vector<std::string> args(argv, argv + argc);
  try {
    args = app::expand_config(args, cli);
  } catch (const Error& e) {
    std::cerr << "gridshell: error: " << e.message() << "\n";
    return 2;
  }
  std::vector<std::string> rev(args.rbegin(), args.rend() - 1);
  try {
    cli.parse(rev);
  } catch (const CLI::CallForHelp& e) {
    return cli.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return cli.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "gridshell: error: " << e.what() << " (see gridshell --help)\n";
    return 2;
  }
  try {
    return action ? action() : 2;
  } catch (const Error& e) {
    std::cerr << "gridshell: error: " << e.message() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "gridshell: error: out of memory\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "gridshell: internal error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // What escapes run (set-up of the command line itself) is a bug: reported, never a terminate.
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "gridshell: internal error: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "gridshell: internal error\n";
  }
  return 1;
}
