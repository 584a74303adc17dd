// The scratch an application (the CLI, the Python module) asks for: its precision from the flags, and its stores' halo.
#pragma once

#include <cstddef>
#include <string>

#include "gdp/solver.h"

namespace gdp {

// `scratch` is --scratch ("float", "narrow" or empty), `half_scratch` --half-scratch (the same as
// narrow), `double_precision` --double. Applications writing images default to narrow; double
// precision to float (docs/how-streaming-works.md). UsageError naming the flags that conflict.
ScratchPrecision app_scratch_precision(const std::string& scratch, bool half_scratch, bool double_precision);

// A scratch budget the application names (--memory, memory=): `bytes` of scratch rows in memory,
// every store there while it fits and O_DIRECT files only past it (direct_scratch_from SIZE_MAX).
void app_scratch_memory(SolverOptions& options, std::size_t bytes);

// The most columns of each neighbour's that a band of the band schedule keeps, for `sweeps`
// (the larger of SolverOptions::sweeps and post_sweeps): under mpirun a rank's row stores span its columns and these either side.
int band_halo_columns(int sweeps);

// Row stores of at least this many bytes go to O_DIRECT files whatever --memory leaves them
// (options.direct_scratch_from, or GDP_DIRECT_SCRATCH where set; SIZE_MAX when none is): the disk
// the size check must count.
std::size_t direct_scratch_from(const SolverOptions& options);

}  // namespace gdp
