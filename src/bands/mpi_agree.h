// The collective check before a distributed band solve (mpi_run.cc): all ranks go on, or all stop with one message.
#pragma once

#include <string>
#include <vector>

namespace gdp::bands {

// Every rank calls this at the same point with its own setup error ("" when it has none) and a
// fingerprint of what it is about to solve (image size, options). Returns when every rank is fine
// and the fingerprints agree; otherwise throws on every rank the same UsageError: the error of
// the lowest failing rank ("rank R: ...") or that the ranks disagree on the problem.
void agree_before_solving(const std::string& error, const std::vector<long long>& fingerprint);

}  // namespace gdp::bands
