// Waiting for an MPI event without holding a core: sleep on the node's doorbell, or poll with growing sleeps.
#pragma once

#include <mpi.h>

#include <functional>
#include <vector>

namespace gdp::mpi {

// A wait's `peer`: the world rank whose doing ends it (the sender of the awaited message, the
// receiver of a send), or kAnyRank (a collective: its caller rang every rank when it joined).
constexpr int kAnyRank = -1;

// MPI_Wait without spinning: MPI_Test until done. When `peer` shares this node (mpi/doorbell.h,
// every rank for kAnyRank) each poll that finds nothing sleeps on this rank's doorbell, which the
// peer rings; otherwise sleeps of 20 us doubling up to 640 us between polls (wait.cc says why).
// `between`, when given, runs every 16th poll (the MPI hub reaps its sends there).
void wait_request(MPI_Request& request, int peer, const std::function<void()>& between = {});

// The next message from `source` with `tag` on `comm` (whose ranks are the world's), whole, into
// `data` (resized to it, its capacity reused): MPI_Improbe polled alike, then MPI_Imrecv
// completed by wait_request (a large message arrives in pieces, which MPI_Mrecv would wait for
// spinning); then rings `source`'s doorbell (its send has completed, or will at its next poll).
void receive_message(int source, int tag, MPI_Comm comm, std::vector<unsigned char>& data,
                     const std::function<void()>& between = {});

}  // namespace gdp::mpi
