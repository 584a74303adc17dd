// --checkpoint DIR and --resume DIR on the command line: the run's identity, early refusals, removal after success.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "gdp/solver.h"

namespace gdp::cli {

// Adds --checkpoint and --resume to a solving subcommand (values into `checkpoint`, `resume`).
void add_checkpoint_options(CLI::App& cmd, std::string& checkpoint, std::string& resume);

// Puts the checkpoint directory, resume flag and the run's identity (`command`, the options given
// on `cmd` and the sizes and modification times of the files they name, but the output) into
// `solver`. Throws UsageError under mpirun, for two different directories, or when resuming
// against a checkpoint of other inputs or options (before any output is opened). Remembers the
// directory for finish_checkpoint().
void apply_checkpoint_options(const CLI::App& cmd, const std::string& command, const std::string& checkpoint,
                              const std::string& resume, SolverOptions& solver);

// After a successful run (output committed): removes the checkpoint's files (docs/resume.md).
void finish_checkpoint();

}  // namespace gdp::cli
