// Workers on threads with the first exception carried back to the caller.
#include "schedule/parallel.h"

#include <algorithm>
#include <atomic>
#include <barrier>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace gdp::schedule {

void run_workers(int count, const std::function<void(int)>& worker,
                 const std::function<void(int, const std::string&)>& stop) {
  std::vector<std::exception_ptr> errors;  // in the order they were thrown
  std::mutex error_mutex;
  const auto failed = [&](int t, const std::string& what) {
    {
      const std::lock_guard<std::mutex> lock(error_mutex);
      errors.push_back(std::current_exception());
    }
    if (stop) stop(t, what);
  };
  const auto guarded = [&](int t) {
    try {
      worker(t);
    } catch (const std::exception& e) {
      failed(t, e.what());
    } catch (...) {
      failed(t, "an unknown error");
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < count; ++t) pool.emplace_back(guarded, t);
  if (count > 0) guarded(0);
  for (std::thread& th : pool) th.join();
  for (const std::exception_ptr& e : errors) {
    try {
      std::rethrow_exception(e);
    } catch (const Stopped&) {
    }
  }
  if (!errors.empty()) std::rethrow_exception(errors.front());
}

void run_steps(int count, const std::function<int()>& next, const std::function<void(int, int)>& task) {
  count = std::max(count, 1);
  std::exception_ptr error;
  std::mutex error_mutex;
  std::atomic<bool> failed{false};
  const auto keep = [&] {
    const std::lock_guard<std::mutex> lock(error_mutex);
    if (!error) error = std::current_exception();
    failed.store(true);
  };
  int tasks = -1;  // the current step's (written only while every worker waits)
  std::atomic<int> taken{0};
  std::barrier sync(count, [&]() noexcept {
    tasks = -1;
    taken.store(0);
    if (failed.load()) return;
    try {
      tasks = next();
    } catch (...) {
      keep();
      tasks = -1;
    }
  });
  run_workers(count, [&](int t) {
    for (;;) {
      sync.arrive_and_wait();
      if (tasks < 0) return;
      for (int i = 0; !failed.load(std::memory_order_relaxed) && (i = taken.fetch_add(1)) < tasks;) {
        try {
          task(t, i);
        } catch (...) {
          keep();
        }
      }
    }
  });
  if (error) std::rethrow_exception(error);
}

}  // namespace gdp::schedule
