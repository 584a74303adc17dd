// Running a few workers on threads: the calling thread takes worker 0; one stop policy, one error wins;
// rows handed between them through marks and rings that the same stop ends.
#pragma once

#include <atomic>
#include <climits>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "gdp/errors.h"

namespace gdp::schedule {

// What a worker throws when it was stopped because another one failed (also bands::ThreadHub::stop).
class Stopped : public Error {
 public:
  using Error::Error;
};

// Runs worker(0) .. worker(count - 1), worker 0 on the calling thread and the others on their
// own threads, and returns when all are done. When one throws, `stop` (if given) is called with
// its number and the exception's what(), to stop the others. Once every worker has finished, the
// first exception thrown that is not Stopped (which explains more than "stopped") is rethrown
// here, else the first one (a worker exception never terminates the process).
void run_workers(int count, const std::function<void(int)>& worker,
                 const std::function<void(int, const std::string&)>& stop = {});

// Runs `count` workers, kept for the whole run, through steps one after another: before each,
// next() runs on one worker while the others wait and returns the step's number of tasks (-1:
// no more steps); then the workers take its tasks, task(worker, i) for each i in [0, tasks), each
// the next not yet taken. Everything next() and the tasks of a step write is seen by the next
// step. The first exception stops the run (no more tasks or steps) and is rethrown here.
void run_steps(int count, const std::function<int()>& next, const std::function<void(int, int)>& task);

// Counts (rows done) that threads raise and wait on. stop() ends every wait, now and later, with
// Stopped: a solve's one stop for every hand-off between its threads.
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
  // A waiter sleeps on a futex word of the marks' own (`bells_`, taken from `spare_` while it
  // waits): set() rings it after unlocking, one futex call on each side. A condition variable
  // notified under the lock costs three and a second switch (the woken thread sleeps again at once
  // on the lock), dear on a guest where each wake-up is. A late ring of a word since handed to
  // another waiter is a spurious wake-up: the waiter looks again under the lock.
  struct Waiter {
    const Ready& ready;
    bool done = false;
    std::atomic<int>* bell = nullptr;  // 0 armed, 1 rung, 2 asleep
  };
  std::mutex mutex_;
  std::vector<int> marks_;
  std::vector<Waiter*> waiters_;
  std::deque<std::atomic<int>> bells_;
  std::vector<std::atomic<int>*> spare_;
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
