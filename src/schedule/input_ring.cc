// The input ring: one decoding thread, readers computing their columns, waits on one condition.
#include "schedule/input_ring.h"

#include <algorithm>
#include <climits>

#include "schedule/parallel.h"

namespace gdp::schedule {

// Reader r's view of the source: its rows' columns computed from the ring's slots.
class InputRing::View final : public GuidanceSource {
 public:
  View(InputRing& ring, int reader, std::vector<Range> windows)
      : ring_(ring), src_(ring.source_), reader_(reader), windows_(std::move(windows)) {}
  int width() const override { return src_.width(); }
  int height() const override { return src_.height(); }
  int channels() const override { return src_.channels(); }
  double alpha() const override { return src_.alpha(); }
  bool has_weights() const override { return src_.has_weights(); }
  bool has_initial() const override { return src_.has_initial(); }
  bool start_from_initial() const override { return src_.start_from_initial(); }
  void read_row(int j, GuidanceRow& out) override {
    if (!ring_.split_) return src_.read_row(j, out);
    ring_.wait_decoded(std::min(j + 1, height() - 1));
    for (const auto& [begin, end] : windows_) src_.compute(j, out, begin, end);
    ring_.release(reader_, j + 1);
  }

 private:
  InputRing& ring_;
  GuidanceSource& src_;
  const int reader_;
  const std::vector<Range> windows_;
};

InputRing::InputRing(GuidanceSource& source, int readers, int slots)
    : source_(source), split_(source.splits()), slots_(slots), height_(source.height()), released_(readers, 0) {
  if (split_) source.set_slots(slots);
}

std::unique_ptr<GuidanceSource> InputRing::view(int reader, std::vector<Range> windows) {
  return std::make_unique<View>(*this, reader, std::move(windows));
}

// A thread that must wait asks for a few rows more than it needs (kBatch), so that threads are
// woken about once every kBatch rows; whoever changes what it waits for wakes it (the *_wants_).
void InputRing::decode_all() {
  const auto released = [&] { return *std::min_element(released_.begin(), released_.end()); };
  for (int y = 0; split_ && y <= height_; ++y) {
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
