// --checkpoint / --resume plumbing shared by the solving subcommands.
#include "cli_checkpoint.h"

#include <set>

#include <fmt/format.h>

#include "gdp/checkpoint.h"
#include "gdp/errors.h"
#include "gdp/mpi_run.h"

namespace gdp::cli {
namespace {

std::filesystem::path& finished_dir() {
  static std::filesystem::path dir;
  return dir;
}

// Options that change neither the result nor the checkpoint's shape (a resumed run keeps the
// checkpoint's lanes whatever --threads says; its scratch lives in the checkpoint).
bool ignored(const std::string& name) {
  static const std::set<std::string> names = {"--threads", "--quiet", "--verbose", "--residuals", "--stats", "--temp",
                                              "--checkpoint", "--resume", "--max-pixels", "--help"};
  return names.count(name) > 0;
}

CheckpointIdentity run_identity(const CLI::App& cmd, const std::string& command) {
  CheckpointIdentity id;
  id["command"] = command;
  for (const CLI::Option* opt : cmd.get_options()) {
    const std::string name = opt->get_name();
    if (opt->count() == 0 || ignored(name)) continue;
    std::string value;
    for (const std::string& r : opt->results()) value += (value.empty() ? "" : " ") + r;
    id["option " + name] = value;
    if (name == "--output") continue;  // may exist from an earlier run; it is replaced at the end
    for (const std::string& r : opt->results()) {
      const std::string file = file_identity(r);
      if (!file.empty()) id["input " + r] = file;
    }
  }
  return id;
}

}  // namespace

void add_checkpoint_options(CLI::App& cmd, std::string& checkpoint, std::string& resume) {
  cmd.add_option("--checkpoint", checkpoint,
                 "keep the scratch and the solver's state in this directory at every completed unit of work, so "
                 "that --resume DIR continues after a crash; removed after success (docs/resume.md)");
  cmd.add_option("--resume", resume,
                 "continue the run checkpointed in this directory (same inputs and options; bit-identical result), "
                 "checkpointing there again");
}

void apply_checkpoint_options(const CLI::App& cmd, const std::string& command, const std::string& checkpoint,
                              const std::string& resume, SolverOptions& solver) {
  if (checkpoint.empty() && resume.empty()) return;
  if (!checkpoint.empty() && !resume.empty() && std::filesystem::path(checkpoint) != std::filesystem::path(resume))
    throw UsageError(fmt::format("--checkpoint {} and --resume {}: one directory (--resume keeps checkpointing there)",
                                 checkpoint, resume));
  solver.checkpoint_dir = resume.empty() ? checkpoint : resume;
  solver.resume = !resume.empty();
  solver.checkpoint_identity = run_identity(cmd, command);
  if (solver.resume) check_resume(solver.checkpoint_dir, solver.checkpoint_identity);
  finished_dir() = solver.checkpoint_dir;
}

void finish_checkpoint() {
  if (!finished_dir().empty()) remove_checkpoint(finished_dir());
}

}  // namespace gdp::cli
