// --max-pixels and the default bound on image sizes: what the scratch and memory a size needs allow.
#pragma once

#include "cli_common.h"

namespace gdp::cli {

// Installs the size check (gdp/size_check.h) for the images this command opens: with --max-pixels
// N, at most N pixels; otherwise what fits the free space of the scratch directory and the
// available memory, by estimates of what a solve (`solver`; nullptr: a command that streams rows
// through without solving, or resamples in memory when `in_memory`) needs per sample.
void guard_sizes(const CommonOptions& o, const SolverOptions* solver, bool in_memory = false);

// An image size derived from options (`what`, e.g. "--pq-height 100000": its PQ grid), checked
// like a file's header (gdp/size_check.h); UsageError naming `what`. Sides are given as long
// long so that a product computed from an option cannot have overflowed already.
void check_derived_size(const std::string& what, long long width, long long height, int channels);

}  // namespace gdp::cli
