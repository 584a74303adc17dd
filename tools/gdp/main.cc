// gdp command line entry point: parses a subcommand, runs it, maps errors to exit codes.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "blend_args.h"
#include "commands.h"
#include "gdp/cleanup.h"
#include "gdp/errors.h"
#include "gdp/mpi_run.h"

int main(int argc, char** argv) {
  const gdp::MpiRun mpi(argc, argv);  // under mpirun: MPI for the whole run (docs/how-bands-work.md)
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
  commands.push_back(gdp::cli::make_blend(root));
  try {
    // gdp-blend runs `gdp blend`; blend's arguments may be enblend's (Hugin's makefiles).
    std::vector<std::string> args = gdp::cli::command_line(argc, argv);
    std::reverse(args.begin(), args.end());
    root.parse(args);
  } catch (const CLI::CallForHelp& e) {
    return root.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return root.exit(e);
  } catch (const gdp::UsageError& e) {  // an unreadable @listfile
    std::fprintf(stderr, "gdp: %s\n", e.what());
    return 2;
  } catch (const CLI::ParseError& e) {
    if (gdp::MpiRun::size() > 1) gdp::MpiRun::abort(e.what());
    std::fprintf(stderr, "gdp: %s\nRun 'gdp --help' or 'gdp SUBCOMMAND --help' for usage.\n", e.what());
    return 2;
  }
  gdp::cleanup::install_signal_handlers();
  try {
    for (auto& c : commands) {
      if (!c->app->parsed()) continue;
      const std::string name = c->app->get_name();
      if (gdp::MpiRun::size() > 1 && !c->runs_under_mpi())
        throw gdp::UsageError("under mpirun, only stitch, sharpen, smooth and clone run (with --bands), not " + name);
      return c->run();
    }
  } catch (const gdp::Error& e) {
    // Under mpirun a rank that fails alone ends them all (the others may be waiting for it);
    // an error every rank saw in the collective check is printed once, by rank 0.
    if (gdp::MpiRun::size() > 1 && !gdp::MpiRun::failed_together()) gdp::MpiRun::abort(e.what());
    if (gdp::MpiRun::rank() == 0) std::fprintf(stderr, "gdp: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    if (gdp::MpiRun::size() > 1) gdp::MpiRun::abort(std::string("internal error: ") + e.what());
    std::fprintf(stderr, "gdp: internal error: %s\n", e.what());
    return 1;
  }
  return 2;
}
