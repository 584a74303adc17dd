// The band solve schedule (Schedule::Bands): bands of columns solved by workers in lockstep.
#pragma once

#include "gdp/guidance.h"
#include "gdp/solver.h"
#include "multigrid/incore_vcycle.h"
#include "schedule/solve_parts.h"

namespace gdp::bands {

// options.bands workers, one thread each, in this process; under mpirun (gdp::MpiRun) options.bands
// workers on every rank, rank 0 writing the whole result to `out` (other ranks write nothing).
template <class T>
void solve_bands(GuidanceSource& source, const SolverOptions& options, RowWriter& out, SolveSummary& summary);

// The first level (>= 1) whose planes, u and b for every channel, fit in `bytes`.
template <class T>
int first_whole_level(const multigrid::Operators<T>& ops, int channels, std::size_t bytes);

}  // namespace gdp::bands
