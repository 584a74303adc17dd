// Workers on threads with the first exception carried back to the caller.
#include "schedule/parallel.h"

#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace gdp::schedule {

void run_workers(int count, const std::function<void(int)>& worker) {
  std::exception_ptr error;
  std::mutex error_mutex;
  const auto guarded = [&](int t) {
    try {
      worker(t);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < count; ++t) pool.emplace_back(guarded, t);
  if (count > 0) guarded(0);
  for (std::thread& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace gdp::schedule
