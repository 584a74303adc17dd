// Waiting threads asleep on futex words of their own, rung by another thread after it unlocks: one system call a side.
#pragma once

#include <algorithm>
#include <atomic>
#include <deque>
#include <mutex>
#include <vector>

namespace gdp::util {

// A waiter's futex word: arm() under the owner's lock, sleep() after releasing it; ring() wakes
// the sleeper, if it sleeps yet (a ring between arm() and sleep() makes sleep() return at once).
class Bell {
 public:
  void arm() { word_.store(0); }
  void sleep();  // returns once rung (or spuriously: the caller looks again under its lock)
  void ring();

 private:
  std::atomic<int> word_{0};  // 0 armed, 1 rung, 2 asleep
};

// Threads that wait under one mutex, in lines (one a condition), each asleep on a bell lent by
// these Bells. A state change takes a line's first waiter out of it under the lock (call()) and
// rings it once the lock is released (ring()): a condition variable notified under the lock costs
// three futex calls and a second switch (the woken thread sleeps again at once on the held lock),
// and its woken waiter relocks the mutex as contended (its next unlock another futex call), dear
// on a guest where every wake-up is. Bells stay at their addresses, lent again and again: a late
// ring of a bell since lent to another waiter is only a spurious wake-up. The destructor waits for
// rings begun by call() and not yet done, so the owner may be destroyed by the thread it woke.
class Bells {
 public:
  using Line = std::vector<Bell*>;  // the waiters of one condition, first come first
  Bells() = default;
  Bells(const Bells&) = delete;
  Bells& operator=(const Bells&) = delete;
  ~Bells();

  // Under `lock` (held, on the owner's mutex): returns once ready() holds (asked under the lock,
  // now and after each wake-up), waiting in `line` meanwhile.
  template <class Ready>
  void wait(std::unique_lock<std::mutex>& lock, Line& line, Ready ready) {
    if (ready()) return;
    Bell* bell = take();
    do {
      bell->arm();
      line.push_back(bell);
      lock.unlock();
      bell->sleep();
      lock.lock();
      std::erase(line, bell);  // (still in line after a spurious wake-up)
    } while (!ready());
    spare_.push_back(bell);
  }
  // Under the lock: the first waiter of `line`, out of it, for ring() after unlocking (nullptr:
  // no one waits).
  Bell* call(Line& line);
  // After unlocking: wakes the waiter call() returned (nothing for nullptr).
  void ring(Bell* bell);
  // Under the lock: wakes every waiter of `line` (for a close or a stop: rare).
  void ring_all(Line& line);

 private:
  Bell* take();
  std::deque<Bell> bells_;
  std::vector<Bell*> spare_;
  std::atomic<int> ringing_{0};  // calls not yet rung
};

}  // namespace gdp::util
