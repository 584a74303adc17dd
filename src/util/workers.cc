// Workers on threads with the first exception carried back to the caller; steps of tasks on kept workers.
#include "util/workers.h"

#include <algorithm>
#include <atomic>
#include <barrier>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace gdp::util {

void run_workers(int count, const std::function<void(int)>& worker,
                 const std::function<void(int, const std::string&)>& stop) {
  std::exception_ptr first, cause;  // the first thrown, and the first that is not Stopped
  std::mutex error_mutex;
  const auto failed = [&](int t, const std::string& what, bool stopped) {
    {
      const std::lock_guard<std::mutex> lock(error_mutex);
      if (!first) first = std::current_exception();
      if (!stopped && !cause) cause = std::current_exception();
    }
    if (stop) stop(t, what);
  };
  const auto guarded = [&](int t) {
    try {
      worker(t);
    } catch (const Stopped& e) {
      failed(t, e.what(), true);
    } catch (const std::exception& e) {
      failed(t, e.what(), false);
    } catch (...) {
      failed(t, "an unknown error", false);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < count; ++t) pool.emplace_back(guarded, t);
  if (count > 0) guarded(0);
  for (std::thread& th : pool) th.join();
  if (first) std::rethrow_exception(cause ? cause : first);
}

void run_steps(int count, const std::function<int()>& next, const std::function<void(int, int)>& task) {
  count = std::max(count, 1);
  std::atomic<bool> failed{false};
  std::exception_ptr next_error;  // (the barrier's completion must not throw)
  int tasks = -1;  // the current step's (written only while every worker waits)
  std::atomic<int> taken{0};
  std::barrier sync(count, [&]() noexcept {
    tasks = -1;
    taken.store(0);
    if (failed.load()) return;
    try {
      tasks = next();
    } catch (...) {
      next_error = std::current_exception();
    }
  });
  run_workers(count, [&](int t) {
    try {
      for (;;) {
        sync.arrive_and_wait();
        if (tasks < 0) return;
        for (int i = 0; !failed.load(std::memory_order_relaxed) && (i = taken.fetch_add(1)) < tasks;) task(t, i);
      }
    } catch (...) {  // the others take no more tasks, finish the step without this worker and stop
      failed.store(true);
      sync.arrive_and_drop();
      throw;
    }
  });
  if (next_error) std::rethrow_exception(next_error);
}

}  // namespace gdp::util
