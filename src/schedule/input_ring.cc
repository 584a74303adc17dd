// The input ring: one decoding thread, readers computing their columns, waits on one condition.
#include "schedule/input_ring.h"

#include <algorithm>
#include <climits>

#include "schedule/parallel.h"

namespace gdp::schedule {

InputRing::InputRing(GuidanceSource& source, int readers, int slots)
    : source_(source), split_(source.splits()), slots_(slots), height_(source.height()), released_(readers, 0) {
  if (split_) source.set_slots(slots);
}

void InputRing::read(int reader, int j, GuidanceRow& out, int begin, int end) {
  if (!split_) return source_.read_row(j, out);
  wait_decoded(std::min(j + 1, height_ - 1));
  source_.compute(j, out, begin, end);
  release(reader, j + 1);
}

// A thread that must wait asks for a few rows more than it needs (kBatch), so that threads are
// woken about once every kBatch rows; whoever changes what it waits for wakes it (the *_wants_).
void InputRing::decode_all() {
  const auto released = [&] { return *std::min_element(released_.begin(), released_.end()); };
  for (int y = split_ ? 0 : height_; y <= height_; ++y) {
    std::unique_lock lock(mutex_);
    decoded_ = y;
    if (decoded_ > reader_wants_) {
      reader_wants_ = INT_MAX;
      readers_.notify_all();
    }
    // Row y's slot is free once every reader is past row y - slots; at the end: all finished.
    const int need = y < height_ ? y - slots_ : INT_MAX - 1;
    const int target = y < height_ ? std::min(need + kBatch, height_) : need;
    if (released() <= need)
      while (!stopped_ && released() <= target) {
        decoder_wants_ = target;
        decoder_.wait(lock);
      }
    if (stopped_) throw Stopped("stopped");
    lock.unlock();
    if (y < height_) source_.decode(y);
  }
}

void InputRing::wait_decoded(int y) {
  std::unique_lock lock(mutex_);
  while (!stopped_ && decoded_ <= y) {
    reader_wants_ = std::min(reader_wants_, std::min(y + kBatch, height_ - 1));
    readers_.wait(lock);
  }
  if (stopped_) throw Stopped("stopped");
}

void InputRing::release(int reader, int rows) {
  std::unique_lock lock(mutex_);
  released_[reader] = rows;
  if (*std::min_element(released_.begin(), released_.end()) > decoder_wants_) {
    decoder_wants_ = INT_MAX;
    lock.unlock();
    decoder_.notify_one();
  }
}

void InputRing::finished(int reader) { release(reader, INT_MAX); }

void InputRing::stop() {
  {
    const std::lock_guard lock(mutex_);
    stopped_ = true;
  }
  readers_.notify_all();
  decoder_.notify_all();
}

}  // namespace gdp::schedule
