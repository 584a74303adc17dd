// What every rank of an mpirun does together (mpi_run.cc): agree before a solve, or all end at once.
#pragma once

#include <string>
#include <vector>

namespace gdp::mpi {

// Every rank calls this at the same point with its own setup error ("" when it has none) and a
// fingerprint of what it is about to solve (image size, options). Returns when every rank is fine
// and the fingerprints agree; otherwise throws on every rank the same UsageError: the error of
// the lowest failing rank ("rank R: ...") or that the ranks disagree on the problem.
void agree_before_solving(const std::string& error, const std::vector<long long>& fingerprint);

// Prints "gdp: rank R: why" on stderr and calls MPI_Abort(MPI_COMM_WORLD, 2): every rank ends with
// a non-zero status instead of waiting for messages that will never come. The only place the
// library ends the process; used by the band transport's abort() and gdp::MpiRun::abort(). Tracked
// files (the temporary output) are removed first (gdp/cleanup.h): MPI_Abort runs no destructor.
[[noreturn]] void abort_ranks(const std::string& why);

}  // namespace gdp::mpi
