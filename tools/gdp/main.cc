// gdp command line entry point: parses a subcommand, runs it, maps errors to exit codes.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "blend_args.h"
#include "cli_checkpoint.h"
#include "commands.h"
#include "gdp/cleanup.h"
#include "gdp/errors.h"
#include "gdp/mpi_run.h"

namespace {

using gdp::cli::Command;

// The command line's own error ("" when none): an unknown command (CLI11 would say only "A
// subcommand is required"), a flag CLI11 refuses, or a command mpirun cannot run.
// `args`: the arguments after the program's name (gdp::cli::command_line: gdp-blend and enblend's
// syntax already translated).
std::string command_line_error(CLI::App& root, const std::vector<std::unique_ptr<Command>>& commands,
                               std::vector<std::string> args) {
  if (!args.empty() && !args[0].empty() && args[0][0] != '-') {
    std::string names;
    bool known = false;
    for (const auto& c : commands) {
      known = known || c->app->check_name(args[0]);
      names += (names.empty() ? "" : ", ") + c->app->get_name();
    }
    if (!known) return "unknown command '" + args[0] + "' (one of: " + names + ")";
  }
  try {
    std::reverse(args.begin(), args.end());  // CLI11 takes them last first
    root.parse(args);
  } catch (const CLI::ParseError& e) {
    if (dynamic_cast<const CLI::CallForHelp*>(&e) || dynamic_cast<const CLI::CallForAllHelp*>(&e)) throw;
    return e.what();
  }
  if (gdp::MpiRun::size() == 1) return "";
  for (const auto& c : commands) {
    if (!c->app->parsed()) continue;
    if (!c->runs_under_mpi())
      return "under mpirun, only stitch, sharpen, smooth, clone, blend and sky run, not " + c->app->get_name();
    const CLI::Option* in_core = c->app->get_option_no_throw("--in-core");
    if (in_core && in_core->count())  // ranks solve bands (one per rank unless --bands says more)
      return "--in-core does not run under mpirun (ranks solve bands, which stream; docs/how-bands-work.md)";
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  const gdp::MpiRun mpi(argc, argv);  // under mpirun: MPI for the whole run (docs/how-bands-work.md)
  CLI::App root{"gdp: gradient-domain processing of large planar and spherical images"};
  root.require_subcommand(1);
  std::vector<std::unique_ptr<Command>> commands;
  commands.push_back(gdp::cli::make_stitch(root));
  commands.push_back(gdp::cli::make_sharpen(root, false));
  commands.push_back(gdp::cli::make_sharpen(root, true));
  commands.push_back(gdp::cli::make_reconstruct(root));
  commands.push_back(gdp::cli::make_convert(root));
  commands.push_back(gdp::cli::make_sphere(root));
  commands.push_back(gdp::cli::make_tonemap(root));
  commands.push_back(gdp::cli::make_clone(root));
  commands.push_back(gdp::cli::make_sky(root));
  commands.push_back(gdp::cli::make_blend(root));
  try {
    // Every rank checks its own command line, then they agree: one message, from rank 0, and
    // every rank ends normally (no abort banner).
    // gdp-blend runs `gdp blend`; blend's arguments may be enblend's (Hugin's makefiles).
    gdp::MpiRun::agree(command_line_error(root, commands, gdp::cli::command_line(argc, argv)));
  } catch (const CLI::ParseError& e) {
    return root.exit(e);  // --help
  } catch (const gdp::Error& e) {
    if (gdp::MpiRun::rank() == 0)
      std::fprintf(stderr, "gdp: %s\nRun 'gdp --help' or 'gdp SUBCOMMAND --help' for usage.\n", e.what());
    return 2;
  }
  // After the agreement, so after every rank's MPI_Init (FaultCampaign.RankDeathUnderMpirun waits for them).
  gdp::cleanup::install_signal_handlers();
  try {
    for (auto& c : commands) {
      if (!c->app->parsed()) continue;
      const int code = c->run();
      if (code == 0) gdp::cli::finish_checkpoint();  // the output is committed: its checkpoint is spent
      return code;
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
