// A bounded blocking queue between threads, closable to stop every side.
#pragma once

#include <algorithm>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>
#include <utility>

#include "util/bells.h"

namespace gdp::util {

// Waiters sleep on bells (util/bells.h), rung after the lock is released and only where a thread
// waits: a hand-off costs a waiting side one futex call to sleep and the other one to wake it.
// A push that finds the queue full waits until `refill` places are free (1 to capacity): a
// producer faster than its consumer then sleeps once per `refill` items, not once an item. The
// queue may be destroyed by a thread that push() or pop() has just woken (say, right after its
// last pop) while the waking call still returns.
template <class Item>
class BoundedQueue {
 public:
  explicit BoundedQueue(std::size_t capacity, std::size_t refill = 1)
      : capacity_(capacity), refill_(std::clamp<std::size_t>(refill, 1, capacity)) {}
  // Blocks while full; false when the queue was closed (the item is dropped).
  bool push(Item item) {
    Bell* wake = nullptr;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      std::size_t free = 1;  // places it needs free: then `refill_`, once it waits
      bells_.wait(lock, pushers_, [&] { return closed_ || items_.size() + std::exchange(free, refill_) <= capacity_; });
      if (closed_) return false;
      items_.push_back(std::move(item));
      wake = bells_.call(poppers_);
    }
    bells_.ring(wake);
    return true;
  }
  // Blocks while empty; nothing once the queue is closed, or finished and empty.
  std::optional<Item> pop() {
    Bell* wake = nullptr;
    std::optional<Item> item;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      bells_.wait(lock, poppers_, [&] { return closed_ || finished_ || !items_.empty(); });
      if (closed_ || items_.empty()) return std::nullopt;
      item.emplace(std::move(items_.front()));
      items_.pop_front();
      if (items_.size() + refill_ <= capacity_) wake = bells_.call(pushers_);
    }
    bells_.ring(wake);
    return item;
  }
  // No more items: pop() drains what is queued, then returns nothing.
  void finish() {
    const std::lock_guard<std::mutex> lock(mutex_);
    finished_ = true;
    bells_.ring_all(poppers_);
  }
  // Wakes and fails every waiting and later push() and pop(); queued items are dropped.
  void close() {
    const std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
    bells_.ring_all(pushers_);
    bells_.ring_all(poppers_);
  }

 private:
  std::size_t capacity_, refill_;
  std::mutex mutex_;
  Bells bells_;
  Bells::Line pushers_, poppers_;  // threads waiting for room, for an item
  std::deque<Item> items_;
  bool closed_ = false, finished_ = false;
};

}  // namespace gdp::util
