// Marks that threads wait on (each waiter on a util::Bell of its own) and rings of rows made by their readers.
#include "schedule/parallel.h"

#include <algorithm>
#include <array>
#include <mutex>
#include <vector>

#include "util/seconds.h"

namespace gdp::schedule {

int Marks::add(int count) {
  const std::lock_guard lock(mutex_);
  marks_.insert(marks_.end(), count, 0);
  return static_cast<int>(marks_.size()) - count;
}

void Marks::set(int m, int value) {
  std::array<util::Bell*, 8> rung;  // rung after unlocking (more at once: under the lock)
  std::size_t n = 0;
  {
    const std::lock_guard lock(mutex_);
    marks_[m] = value;
    for (Waiter* w : waiters_)
      if (!w->done && (w->done = w->ready(marks_))) {
        if (n < rung.size()) rung[n++] = w->bell;
        else w->bell->ring();
      }
  }
  for (std::size_t i = 0; i < n; ++i) rung[i]->ring();
}

void Marks::wait(const Ready& ready) {
  std::unique_lock lock(mutex_);
  Waiter me{ready, !stopped_ && ready(marks_)};
  if (!me.done && !stopped_) {
    me.bell = spare_.empty() ? &bells_.emplace_back() : spare_.back();
    if (!spare_.empty()) spare_.pop_back();
    waiters_.push_back(&me);
    while (!stopped_ && !me.done) {
      me.bell->arm();  // (under the lock: set() rings it only after marking it done)
      lock.unlock();
      me.bell->sleep();
      lock.lock();
    }
    std::erase(waiters_, &me);
    spare_.push_back(me.bell);
  }
  if (stopped_) throw util::Stopped("stopped");
}

void Marks::wait(int a, int b, int after, int until) {
  int bar = after;  // then `until`, once it waits
  wait([&](std::vector<int>& m) {
    const bool above = *std::min_element(m.begin() + a, m.begin() + b) > bar;
    bar = std::max(after, until);
    return above;
  });
}

void Marks::stop() {
  const std::lock_guard lock(mutex_);
  stopped_ = true;
  for (Waiter* w : waiters_) w->bell->ring();
}

RowRing::RowRing(Marks& marks, int readers, int slots, int rows, std::function<void(int)> make)
    : marks_(marks), readers_(marks.add(readers)), count_(readers), made_(marks.add(1)), busy_(marks.add(1)),
      slots_(slots), rows_(rows), make_(std::move(make)) {}

void RowRing::need(int r, int from, int to) {
  marks_.set(readers_ + r, from);
  for (;;) {
    int next = -1;  // row `to` not made and no one making rows: make rows from `next` on here
    // Waiting for another reader's makes: until kSlack rows more are made (woken once every few
    // rows, not once a row) or it stops making, but never past a row whose slot this reader holds.
    int bar = to;
    marks_.wait([&](std::vector<int>& m) {
      if (m[made_] > bar) return true;
      if (m[busy_]) return bar = std::max(to, std::min(to + kSlack, from + slots_ - 1)), false;
      if (m[made_] > to) return true;
      m[busy_] = 1;
      next = m[made_];
      return true;
    });
    if (next < 0) return;
    // Row `to`, then up to kAhead more while their slots are free: the other readers' next rows,
    // made before they ask (they wait less, and for no maker that lost its core).
    const double t = util::thread_cpu_seconds();
    for (int y = next; y < rows_ && y <= to + kAhead; ++y) {
      bool free = y <= to;
      if (!free)
        marks_.wait([&](std::vector<int>& m) {
          return free = *std::min_element(m.begin() + readers_, m.begin() + readers_ + count_) > y - slots_, true;
        });
      if (!free) break;
      marks_.wait(readers_, readers_ + count_, y - slots_, y - slots_ + kSlack);
      make_(y);
      marks_.set(made_, y + 1);
    }
    cpu += util::thread_cpu_seconds() - t;
    marks_.set(busy_, 0);
  }
}

}  // namespace gdp::schedule
