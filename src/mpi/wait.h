// Waiting for an MPI event without holding a core: poll, then sleep longer and longer between polls.
#pragma once

#include <mpi.h>

#include <functional>
#include <vector>

namespace gdp::mpi {

// MPI_Wait without spinning: MPI_Test, with a sleep of 20 us doubling up to 640 us between polls
// (wait.cc says why). `between`, when given, runs every 16th poll (the MPI hub reaps its sends there).
void wait_request(MPI_Request& request, const std::function<void()>& between = {});

// The next message from `source` with `tag` on `comm`, whole, into `data` (resized to it, its
// capacity reused): MPI_Improbe polled alike, then MPI_Imrecv completed by wait_request (a large
// message arrives in pieces, which MPI_Mrecv would wait for spinning).
void receive_message(int source, int tag, MPI_Comm comm, std::vector<unsigned char>& data,
                     const std::function<void()>& between = {});

}  // namespace gdp::mpi
