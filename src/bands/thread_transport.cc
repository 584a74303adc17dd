// Mailboxes guarded by one mutex: posting never waits, taking waits for its message or a stop.
#include "bands/thread_transport.h"

#include <fmt/format.h>

namespace gdp::bands {

class ThreadHub::Endpoint final : public Transport {
 public:
  Endpoint(ThreadHub& hub, int rank) : hub_(hub), rank_(rank) {}
  int rank() const override { return rank_; }
  int size() const override { return hub_.size_; }
  void send(int to, int tag, Bytes data) override {
    if (hub_.here(to)) return hub_.post(rank_, to, tag, std::move(data));
    hub_.send_away(rank_, to, tag, std::move(data));
  }
  Bytes receive(int from, int tag) override {
    return hub_.here(from) ? hub_.take(from, rank_, tag) : hub_.receive_away(from, rank_, tag);
  }
  void abort(const std::string& why) override { hub_.stop(why); }

 private:
  ThreadHub& hub_;
  int rank_;
};

ThreadHub::ThreadHub(int local, int first, int size) : local_(local), first_(first), size_(size) {
  for (int b = first; b < first + local; ++b) endpoints_.push_back(std::make_unique<Endpoint>(*this, b));
}

ThreadHub::~ThreadHub() = default;

Transport& ThreadHub::endpoint(int worker) {
  if (!here(worker)) throw std::logic_error(fmt::format("worker {} does not run in this process", worker));
  return *endpoints_[worker - first_];
}

void ThreadHub::send_away(int, int to, int, Bytes) { throw std::logic_error(fmt::format("no worker {}", to)); }
Bytes ThreadHub::receive_away(int from, int, int) { throw std::logic_error(fmt::format("no worker {}", from)); }

void ThreadHub::post(int from, int to, int tag, Bytes data) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (stopped_) throw TransportStopped(*stopped_);
    boxes_[{from, to, tag}].push_back(std::move(data));
  }
  arrived_.notify_all();
}

Bytes ThreadHub::take(int from, int to, int tag) {
  std::unique_lock<std::mutex> lock(mutex_);
  auto& box = boxes_[{from, to, tag}];
  arrived_.wait(lock, [&] { return stopped_ || !box.empty(); });
  if (stopped_) throw TransportStopped(*stopped_);
  Bytes data = std::move(box.front());
  box.pop_front();
  return data;
}

void ThreadHub::stop(const std::string& why) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!stopped_) stopped_ = why;
  }
  arrived_.notify_all();
}

}  // namespace gdp::bands
