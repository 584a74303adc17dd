// Doorbells of the ranks on one node: a word each in memory they share; a sender rings, a waiter sleeps on a futex.
#pragma once

#include <chrono>
#include <cstdint>

namespace gdp::mpi {

// Opens the doorbells of the ranks that share this rank's node (collective on MPI_COMM_WORLD,
// called by gdp::MpiRun right after MPI_Init, when the ranks arrive together: its blocking calls
// spin only briefly): a 64-byte slot per rank in an MPI_Win_allocate_shared window of
// MPI_Comm_split_type(MPI_COMM_TYPE_SHARED). Ranks on other nodes have none (rings() false): their
// waits keep the sleeping polls (mpi/wait.h). close_doorbells() is collective too (at the end).
void open_doorbells();
void close_doorbells();

// Whether world rank `rank` shares this rank's node, so that ring(rank) wakes its waits.
bool rings(int rank);
// Whether every rank shares this node.
bool all_ring();
// Counts one event for `rank` (a message sent to it, one of its sends received) and wakes its
// threads sleeping in wait_bell(); a no-op for a rank with no doorbell. The wake is a system call
// only when one of them sleeps.
void ring(int rank);
void ring_all();
// This rank's count of events, to read BEFORE polling MPI for what is awaited.
std::uint32_t bell_count();
// Sleeps until this rank's count differs from `seen` (at once if it already does) or `timeout`
// passes: never longer, so a wake-up that does not come (a message the sender's MPI queued for
// its next progress call, a collective's later rounds) costs at most the timeout.
void wait_bell(std::uint32_t seen, std::chrono::microseconds timeout);

}  // namespace gdp::mpi
