// The band solve schedule (Schedule::Bands): bands of columns solved by workers in lockstep.
#pragma once

#include "gdp/guidance.h"
#include "gdp/solver.h"

namespace gdp::bands {

// options.bands workers, one thread each, in this process; under mpirun (gdp::MpiRun) options.bands
// workers on every rank. Then every rank tells `source` the columns it needs
// (GuidanceSource::set_columns: its bands' columns plus margins, whole rows where they would
// wrap around a periodic domain) and `out` the columns it writes (RowWriter::set_columns): the
// rows it writes hold its bands' columns only, and `out` must put them together
// (gdp::MpiRun::gather_writer). Levels too small to band are solved whole on every rank, which
// then writes whole rows without calling set_columns.
template <class T>
void solve_streamed(GuidanceSource& source, const SolverOptions& options, RowWriter& out, SolveSummary& summary);

}  // namespace gdp::bands
