// --max-pixels and the default bound on image sizes: what the scratch and memory a size needs allow.
#pragma once

#include <string>

#include "cli_common.h"

namespace gdp::cli {

// Installs the size check (gdp/size_check.h) for the images this command opens: with --max-pixels
// N, at most N pixels; otherwise what fits the free space of the scratch directory and the
// available memory, by estimates of what a solve (`solver`; nullptr: a command that streams rows
// through without solving, or resamples in memory when `in_memory`) needs per sample.
void guard_sizes(const CommonOptions& o, const SolverOptions* solver, bool in_memory = false);

// The same bounds for an image the command makes itself (no file header passes the check above: gdp
// blend's canvas), with `extra_disk_per_pixel` bytes of the command's own scratch beside the solver's;
// UsageError naming `what`.
void check_canvas_size(const std::string& what, const CommonOptions& o, const SolverOptions& solver, long long width,
                       long long height, int channels, double extra_disk_per_pixel);

}  // namespace gdp::cli
