// gdp command line entry point: parses a subcommand, runs it, maps errors to exit codes.
#include <cstdio>
#include <vector>

#include "commands.h"
#include "gdp/cleanup.h"
#include "gdp/errors.h"

int main(int argc, char** argv) {
  CLI::App root{"gdp: gradient-domain processing of large planar and spherical images"};
  root.require_subcommand(1);
  std::vector<std::unique_ptr<gdp::cli::Command>> commands;
  commands.push_back(gdp::cli::make_stitch(root));
  commands.push_back(gdp::cli::make_sharpen(root, false));
  commands.push_back(gdp::cli::make_sharpen(root, true));
  commands.push_back(gdp::cli::make_reconstruct(root));
  commands.push_back(gdp::cli::make_convert(root));
  commands.push_back(gdp::cli::make_sphere(root));
  commands.push_back(gdp::cli::make_tonemap(root));
  commands.push_back(gdp::cli::make_clone(root));
  try {
    root.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return root.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return root.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "gdp: %s\nRun 'gdp --help' or 'gdp SUBCOMMAND --help' for usage.\n", e.what());
    return 2;
  }
  gdp::cleanup::install_signal_handlers();
  try {
    for (auto& c : commands)
      if (c->app->parsed()) return c->run();
  } catch (const gdp::Error& e) {
    std::fprintf(stderr, "gdp: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gdp: internal error: %s\n", e.what());
    return 1;
  }
  return 2;
}
