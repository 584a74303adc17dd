// Mailboxes guarded by one mutex: posting never waits, taking waits for its message or a stop.
#include "bands/transport.h"

#include <stdexcept>

#include <fmt/format.h>

namespace gdp::bands {

void Transport::send(int to, int tag, Bytes data) { hub_->send(rank_ * stride_, to * stride_, tag + tags_, std::move(data)); }
Bytes Transport::receive(int from, int tag) { return hub_->receive(from * stride_, rank_ * stride_, tag + tags_); }

ThreadHub::ThreadHub(int local, int first, int size) : local_(local), first_(first) {
  for (int b = first; b < first + local; ++b) endpoints_.emplace_back(*this, b, size);
}

Transport& ThreadHub::endpoint(int worker) {
  if (!here(worker)) throw std::logic_error(fmt::format("worker {} does not run in this process", worker));
  return endpoints_[worker - first_];
}

void ThreadHub::send_away(int, int to, int, Bytes) { throw std::logic_error(fmt::format("no worker {}", to)); }
Bytes ThreadHub::receive_away(int from, int, int) { throw std::logic_error(fmt::format("no worker {}", from)); }

void ThreadHub::send(int from, int to, int tag, Bytes data) {
  if (!here(to)) return send_away(from, to, tag, std::move(data));
  util::Bell* wake = nullptr;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (stopped_) throw util::Stopped(*stopped_);
    Box& box = boxes_[{from, to, tag}];
    box.messages.push_back(std::move(data));
    wake = bells_.call(box.waiting);
  }
  bells_.ring(wake);
}

Bytes ThreadHub::receive(int from, int to, int tag) {
  if (!here(from)) return receive_away(from, to, tag);
  std::unique_lock<std::mutex> lock(mutex_);
  Box& box = boxes_[{from, to, tag}];
  bells_.wait(lock, box.waiting, [&] { return stopped_ || !box.messages.empty(); });
  if (stopped_) throw util::Stopped(*stopped_);
  Bytes data = std::move(box.messages.front());
  box.messages.pop_front();
  return data;
}

void ThreadHub::stop(const std::string& why) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!stopped_) stopped_ = why;
  for (auto& [key, box] : boxes_) bells_.ring_all(box.waiting);
}

}  // namespace gdp::bands
