// Waiting for an MPI event without holding a core: poll, then sleep longer and longer between polls.
#pragma once

#include <mpi.h>

#include <functional>
#include <vector>

namespace gdp::mpi {

// Calls `ready()` until it returns true. Open MPI's blocking calls (MPI_Wait, MPI_Mprobe,
// MPI_Mrecv of a large message, collectives) spin on the progress engine at 100 % of a core for
// as long as they wait; on a machine with fewer cores than busy threads that core is taken from
// the rank's own workers and I/O threads. Here the thread sleeps 20 us, doubling up to 640 us,
// between polls (the sleep resets to 20 us on the next call). It never calls sched_yield (nor
// lets Open MPI do it, gdp::MpiRun): on a core shared with busy threads (mpirun binds each rank
// to one core) every yield gives each of them a full time slice before the thread runs again,
// ~4 ms a yield with two busy loops on the core against ~0.2 ms for a 20 us sleep, which made
// band solves under load 5-50x slower, minutes for 2 s of work (docs/how-bands-work.md, "No
// spin-waits"). `between`, when given, runs every 16th poll (the MPI hub reaps completed sends there).
void wait_until(const std::function<bool()>& ready, const std::function<void()>& between = {});

// MPI_Wait without spinning: MPI_Test under wait_until.
void wait_request(MPI_Request& request, const std::function<void()>& between = {});

// The next message from `source` with `tag` on `comm`, whole, into `data` (resized to it):
// MPI_Improbe under wait_until, then MPI_Imrecv completed by wait_request (a large message
// arrives in pieces, which MPI_Mrecv would wait for spinning).
void receive_message(int source, int tag, MPI_Comm comm, std::vector<unsigned char>& data,
                     const std::function<void()>& between = {});

}  // namespace gdp::mpi
