// The MPI transport: band workers spread over MPI ranks, a fixed number of worker threads per rank.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>

#include <mpi.h>

#include "bands/transport.h"

namespace gdp::bands {

// This rank's share of `local * ranks` workers: worker w runs on rank w / local. Messages between
// workers of one rank go through the ThreadHub's mailboxes; the others through MPI on a duplicate
// of MPI_COMM_WORLD: MPI_Isend (the bytes are kept until the send completes) and a receive that
// waits for the matching (source rank, tag) with MPI_Improbe + MPI_Mrecv, MPI tag
// (tag * local + from % local) * local + to % local. Sends are not bounded: each keeps its bytes
// until it completes, then up to kSpares of them are kept (reaped at the next send or receive) and
// receives fill those: no fresh pages per message (docs/how-bands-work.md, "mpirun's extra CPU, where it goes").
// abort() ends every rank (mpi::abort_ranks). Needs MPI initialised
// with MPI_THREAD_MULTIPLE (gdp::MpiRun); constructing is collective (a rank that comes first
// waits without holding a core).
class MpiHub final : public ThreadHub {
 public:
  explicit MpiHub(int local);
  // Waits for this rank's sends, unless an exception unwinds: their receiver may be the rank that
  // failed, and MPI_Abort follows (gdp's main).
  ~MpiHub() override;
  // The next message from worker `from` (on another rank) to `to` with `tag` if it has arrived,
  // else none: it never waits for one to be sent (the column gather's rank 0, docs/how-bands-work.md).
  std::optional<Bytes> poll(int from, int to, int tag);
  // A buffer to fill (a completed send's or a recycled one, its size kept: resizing it down and up
  // again writes no page twice), else an empty one; recycle() hands back one done with.
  Bytes spare();
  void recycle(Bytes used);

 private:
  void send_away(int from, int to, int tag, Bytes data) override;
  Bytes receive_away(int from, int to, int tag) override;
  void stop(const std::string& why) override;
  int mpi_tag(int tag, int from, int to) const { return (tag * local_ + from % local_) * local_ + to % local_; }
  void reap();  // keeps the bytes of the sends that have completed (the oldest first); with `sending_` held
  void keep(Bytes used);  // with `sending_` held

  MPI_Comm comm_ = MPI_COMM_NULL;
  std::mutex sending_;  // guards sends_ and spares_
  struct Pending {
    Bytes data;
    MPI_Request request = MPI_REQUEST_NULL;
  };
  std::deque<Pending> sends_;  // in the order started
  std::vector<Bytes> spares_;  // at most kSpares
  static constexpr std::size_t kSpares = 8;
};

}  // namespace gdp::bands
