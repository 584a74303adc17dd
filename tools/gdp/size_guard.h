// --max-pixels and the default bound on image sizes: what the scratch and memory a size needs allow.
#pragma once

#include "cli_common.h"

namespace gdp::cli {

// Installs the size check (gdp/size_check.h) for the images this command opens: with --max-pixels
// N, at most N pixels; otherwise what fits the free space of the scratch directory and the
// available memory, by estimates of what a solve (`solver`; nullptr: a command that streams rows
// through without solving, or resamples in memory when `in_memory`) needs per sample.
void guard_sizes(const CommonOptions& o, const SolverOptions* solver, bool in_memory = false);

}  // namespace gdp::cli
