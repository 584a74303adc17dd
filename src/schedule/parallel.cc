// Workers on threads with the first exception carried back to the caller.
#include "schedule/parallel.h"

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

}  // namespace gdp::schedule
