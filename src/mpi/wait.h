// Waiting for an MPI event without holding a core: poll, yield a little, then sleep longer and longer.
#pragma once

#include <mpi.h>

#include <functional>
#include <vector>

namespace gdp::mpi {

// Calls `ready()` until it returns true. Open MPI's blocking calls (MPI_Wait, MPI_Mprobe,
// MPI_Mrecv of a large message, collectives) spin on the progress engine at 100 % of a core for
// as long as they wait (with mpi_yield_when_idle, in a loop of sched_yield calls, which takes a
// core all the same whenever no other thread wants it); on a machine with fewer cores than busy
// threads that core is taken from the rank's own workers and I/O threads. Here the first 8 polls
// yield the core (low latency when the message is about to arrive), then the thread sleeps 20 us,
// doubling up to 640 us, between polls (the sleep resets to 20 us on the next call): fewer
// context switches than 64 yields and sleeps up to 320 us, at the same CPU and wall within this
// machine's noise (docs/how-bands-work.md). `between`, when given, runs every 16th poll (the MPI
// hub reaps completed sends there).
void wait_until(const std::function<bool()>& ready, const std::function<void()>& between = {});

// MPI_Wait without spinning: MPI_Test under wait_until.
void wait_request(MPI_Request& request, const std::function<void()>& between = {});

// The next message from `source` with `tag` on `comm`, whole, into `data` (resized to it):
// MPI_Improbe under wait_until, then MPI_Imrecv completed by wait_request (a large message
// arrives in pieces, which MPI_Mrecv would wait for spinning).
void receive_message(int source, int tag, MPI_Comm comm, std::vector<unsigned char>& data,
                     const std::function<void()>& between = {});

}  // namespace gdp::mpi
