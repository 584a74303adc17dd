// Waiting for an MPI event without holding a core: poll, yield a little, then sleep longer and longer.
#pragma once

#include <functional>

namespace gdp::bands {

// Calls `ready()` until it returns true. Open MPI's blocking calls (MPI_Wait, MPI_Mprobe) spin
// on the progress engine at 100 % of a core for as long as they wait; on a machine with fewer
// cores than busy threads that core is taken from the rank's own workers and I/O threads. Here
// the first 64 polls yield the core (low latency when the message is about to arrive), then the
// thread sleeps 20 us, doubling up to 320 us, between polls (the sleep resets to 20 us on the next
// call). `between`, when given, runs every 16th poll (the MPI hub reaps completed sends there).
void wait_until(const std::function<bool()>& ready, const std::function<void()>& between = {});

}  // namespace gdp::bands
