// The MPI transport: band workers spread over MPI ranks, a fixed number of worker threads per rank.
#pragma once

#include <memory>
#include <string>

#include "bands/transport.h"

namespace gdp::bands {

// This rank's share of `local * ranks` workers: worker w runs on rank w / local. Messages between
// workers of one rank go through a ThreadHub; the others through MPI on a duplicate of
// MPI_COMM_WORLD: MPI_Isend (the bytes are kept until the send completes) and a receive that
// waits for the matching (source rank, tag) with MPI_Improbe + MPI_Mrecv, MPI tag
// (tag * local + from % local) * local + to % local. abort() ends every rank (mpi::abort_ranks).
// Needs MPI initialised with MPI_THREAD_MULTIPLE (gdp::MpiRun); constructing is collective (a rank
// that comes first waits without holding a core).
class MpiHub {
 public:
  explicit MpiHub(int local);
  ~MpiHub();  // waits for this rank's sends to complete
  int first() const;  // the first worker on this rank
  Transport& endpoint(int worker);  // worker in [first(), first() + local)

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gdp::bands
