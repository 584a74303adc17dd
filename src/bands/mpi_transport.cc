// MPI point-to-point for band workers on different ranks; workers of one rank share a ThreadHub.
#include "bands/mpi_transport.h"

#include <mpi.h>

#include <deque>
#include <mutex>

#include <fmt/format.h>

#include "mpi/ranks.h"
#include "mpi/wait.h"
#include "bands/thread_transport.h"

namespace gdp::bands {

struct MpiHub::Impl {
  class Endpoint;
  int local = 1, rank = 0, ranks = 1;
  MPI_Comm comm = MPI_COMM_NULL;
  ThreadHub hub;
  std::mutex mutex;  // guards sends
  struct Pending {
    Bytes data;
    MPI_Request request = MPI_REQUEST_NULL;
  };
  std::deque<Pending> sends;  // in the order started
  std::vector<std::unique_ptr<Endpoint>> endpoints;

  explicit Impl(int local_workers) : local(local_workers), hub(local_workers) {}
  int mpi_tag(int tag, int from, int to) const { return (tag * local + from % local) * local + to % local; }

  // Forgets the sends that have completed (the oldest first). Call with `mutex` held.
  void reap() {
    while (!sends.empty()) {
      int done = 0;
      MPI_Test(&sends.front().request, &done, MPI_STATUS_IGNORE);
      if (!done) return;
      sends.pop_front();
    }
  }

  void send(int from, int to, int tag, Bytes data) {
    const std::lock_guard<std::mutex> lock(mutex);
    reap();
    Pending& p = sends.emplace_back();
    p.data = std::move(data);
    MPI_Isend(p.data.data(), static_cast<int>(p.data.size()), MPI_BYTE, to / local, mpi_tag(tag, from, to), comm,
              &p.request);
  }

  Bytes receive(int from, int to, int tag) {
    Bytes data;
    mpi::receive_message(from / local, mpi_tag(tag, from, to), comm, data, [&] {
      const std::lock_guard<std::mutex> lock(mutex);
      reap();
    });
    return data;
  }
};

class MpiHub::Impl::Endpoint final : public Transport {
 public:
  Endpoint(Impl& impl, int worker) : impl_(impl), worker_(worker) {}
  int rank() const override { return worker_; }
  int size() const override { return impl_.local * impl_.ranks; }
  void send(int to, int tag, Bytes data) override {
    if (to / impl_.local == impl_.rank)
      impl_.hub.endpoint(worker_ % impl_.local).send(to % impl_.local, tag, std::move(data));
    else
      impl_.send(worker_, to, tag, std::move(data));
  }
  Bytes receive(int from, int tag) override {
    if (from / impl_.local == impl_.rank)
      return impl_.hub.endpoint(worker_ % impl_.local).receive(from % impl_.local, tag);
    return impl_.receive(from, worker_, tag);
  }
  void abort(const std::string& why) override { mpi::abort_ranks(why); }

 private:
  Impl& impl_;
  int worker_;
};

MpiHub::MpiHub(int local) : impl_(std::make_unique<Impl>(local)) {
  MPI_Comm_rank(MPI_COMM_WORLD, &impl_->rank);
  MPI_Comm_size(MPI_COMM_WORLD, &impl_->ranks);
  MPI_Request request;  // a rank that comes early waits without holding a core
  MPI_Comm_idup(MPI_COMM_WORLD, &impl_->comm, &request);
  mpi::wait_request(request);
  for (int i = 0; i < local; ++i) impl_->endpoints.push_back(std::make_unique<Impl::Endpoint>(*impl_, first() + i));
}

MpiHub::~MpiHub() {
  {
    const std::lock_guard<std::mutex> lock(impl_->mutex);
    for (auto& p : impl_->sends) mpi::wait_request(p.request);
    impl_->sends.clear();
  }
  MPI_Comm_free(&impl_->comm);
}

int MpiHub::first() const { return impl_->rank * impl_->local; }

Transport& MpiHub::endpoint(int worker) {
  if (worker < first() || worker >= first() + impl_->local)
    throw std::logic_error(fmt::format("worker {} does not run on rank {}", worker, impl_->rank));
  return *impl_->endpoints[worker - first()];
}

}  // namespace gdp::bands
