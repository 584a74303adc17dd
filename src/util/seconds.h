// Seconds on the steady clock since a point in time, and the calling thread's CPU seconds.
#pragma once

#include <chrono>
#include <ctime>

namespace gdp::util {

using SteadyClock = std::chrono::steady_clock;

inline double seconds_since(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

// CPU seconds (user + system) of the calling thread so far (the phase CPU of summaries, benches).
inline double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

}  // namespace gdp::util
