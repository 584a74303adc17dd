// Rows handed between a solve's threads: marks they raise and wait on, rings of rows made by their readers; one stop ends every wait.
#pragma once

#include <climits>
#include <deque>
#include <functional>
#include <mutex>
#include <vector>

#include "util/bells.h"
#include "util/workers.h"

namespace gdp::schedule {

// Counts (rows done) that threads raise and wait on. stop() ends every wait, now and later, with
// util::Stopped: a solve's one stop for every hand-off between its threads.
class Marks {
 public:
  using Ready = std::function<bool(std::vector<int>& marks)>;
  // `count` more marks, each 0 (before any thread uses them); returns the first one's number.
  int add(int count);
  void set(int m, int value);
  // Returns once `ready` holds. It is asked under the marks' lock, now and after each set() while
  // it waits, until it first says yes, and may set marks then (a claim).
  void wait(const Ready& ready);
  // Until every mark in [a, b) is above `after`; one that must wait first waits until they are
  // above `until` (>= after: asking a few rows more wakes threads once every few rows).
  void wait(int a, int b, int after, int until);
  void wait(int m, int after) { wait(m, m + 1, after, after); }
  void stop();

 private:
  // A waiter sleeps on a bell of the marks' own (`bells_`, taken from `spare_` while it waits):
  // set() rings it after unlocking, one futex call on each side (util/bells.h says why). A late
  // ring of a bell since handed to another waiter is a spurious wake-up: the waiter looks again
  // under the lock. (Not util::Bells' lines: a waiter here is woken by its own condition.)
  struct Waiter {
    const Ready& ready;
    bool done = false;
    util::Bell* bell = nullptr;
  };
  std::mutex mutex_;
  std::vector<int> marks_;
  std::vector<Waiter*> waiters_;
  std::deque<util::Bell> bells_;
  std::vector<util::Bell*> spare_;
  bool stopped_ = false;
};

// Rows made in order by the threads that read them: a reader that needs a row no one has made
// makes it, if no other reader is making one (make(y)), in slot y % slots once every reader is past
// row y - slots.
class RowRing {
 public:
  RowRing(Marks& marks, int readers, int slots, int rows, std::function<void(int)> make);
  // Reader r is done with rows < `from` and needs rows up to `to`.
  void need(int r, int from, int to);
  // Reader r reads no more; returns once every row is made (made here while no other reader does).
  void done(int r) { need(r, INT_MAX, rows_ - 1); }
  double cpu = 0.0;  // CPU seconds of the makes
  // A maker makes up to kAhead rows past the one asked for while their slots are free; a maker
  // waiting for a slot is woken once kSlack more are free, a reader waiting for another's makes once
  // kSlack more rows are made or it stops making (woken once every few rows).
  static constexpr int kAhead = 4, kSlack = 4;

 private:
  Marks& marks_;
  const int readers_, count_, made_, busy_, slots_, rows_;  // marks: readers' `from`, rows made, making
  std::function<void(int)> make_;
};

}  // namespace gdp::schedule
