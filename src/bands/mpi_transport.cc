// MPI point-to-point for band workers on different ranks; workers of one rank share the ThreadHub's mailboxes.
#include "bands/mpi_transport.h"

#include <exception>

#include "gdp/mpi_run.h"
#include "mpi/ranks.h"
#include "mpi/wait.h"

namespace gdp::bands {

MpiHub::MpiHub(int local) : ThreadHub(local, MpiRun::rank() * local, MpiRun::size() * local) {
  MPI_Request request;  // a rank that comes early waits without holding a core
  MPI_Comm_idup(MPI_COMM_WORLD, &comm_, &request);
  mpi::wait_request(request);
}

MpiHub::~MpiHub() {
  {
    const std::lock_guard<std::mutex> lock(sending_);
    const bool failed = std::uncaught_exceptions() > 0;  // MPI_Abort follows: not waited for
    for (auto& p : sends_)
      if (failed) MPI_Request_free(&p.request);
      else mpi::wait_request(p.request);
    sends_.clear();
  }
  MPI_Comm_free(&comm_);
}

void MpiHub::reap() {
  while (!sends_.empty()) {
    int done = 0;
    MPI_Test(&sends_.front().request, &done, MPI_STATUS_IGNORE);
    if (!done) return;
    keep(std::move(sends_.front().data));
    sends_.pop_front();
  }
}

void MpiHub::keep(Bytes used) {
  if (spares_.size() < kSpares && used.capacity() > 0) spares_.push_back(std::move(used));
}

Bytes MpiHub::spare() {
  const std::lock_guard<std::mutex> lock(sending_);
  reap();
  if (spares_.empty()) return {};
  Bytes b = std::move(spares_.back());
  spares_.pop_back();
  return b;
}

void MpiHub::recycle(Bytes used) {
  const std::lock_guard<std::mutex> lock(sending_);
  keep(std::move(used));
}

void MpiHub::send_away(int from, int to, int tag, Bytes data) {
  const std::lock_guard<std::mutex> lock(sending_);
  reap();
  Pending& p = sends_.emplace_back();
  p.data = std::move(data);
  MPI_Isend(p.data.data(), static_cast<int>(p.data.size()), MPI_BYTE, to / local_, mpi_tag(tag, from, to), comm_,
            &p.request);
}

Bytes MpiHub::receive_away(int from, int to, int tag) {
  Bytes data = spare();
  mpi::receive_message(from / local_, mpi_tag(tag, from, to), comm_, data, [&] {
    const std::lock_guard<std::mutex> lock(sending_);
    reap();
  });
  return data;
}

std::optional<Bytes> MpiHub::poll(int from, int to, int tag) {
  int found = 0;
  MPI_Message message;
  MPI_Status status;
  MPI_Improbe(from / local_, mpi_tag(tag, from, to), comm_, &found, &message, &status);
  if (!found) return std::nullopt;
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  Bytes data = spare();
  data.resize(static_cast<std::size_t>(count));
  MPI_Request request;  // a large message arrives in pieces: completed without spinning
  MPI_Imrecv(data.data(), count, MPI_BYTE, &message, &request);
  mpi::wait_request(request);
  return data;
}

void MpiHub::stop(const std::string& why) { mpi::abort_ranks(why); }

}  // namespace gdp::bands
