// Items handed back between threads for reuse, so that large buffers are allocated once, not per use.
#pragma once

#include <mutex>
#include <vector>

namespace gdp::util {

// A thread-safe free list: give() what a consumer is done with, take() it back (or a new, empty
// item) where the next one is filled. Vectors inside keep their capacity: a solve allocates a few
// buffers once instead of one per band or batch (large buffers allocated and freed in an inner
// loop cost a page fault per page every time: docs/how-streaming-works.md).
template <class Item>
class RecyclePool {
 public:
  void give(Item&& item) {
    const std::lock_guard lock(mutex_);
    free_.push_back(std::move(item));
  }
  Item take() {
    const std::lock_guard lock(mutex_);
    if (free_.empty()) return {};
    Item item = std::move(free_.back());
    free_.pop_back();
    return item;
  }

 private:
  std::mutex mutex_;
  std::vector<Item> free_;
};

}  // namespace gdp::util
