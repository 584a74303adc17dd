// Seconds on the steady clock since a point in time (the phase timings of summaries and reports).
#pragma once

#include <chrono>

namespace gdp::util {

using SteadyClock = std::chrono::steady_clock;

inline double seconds_since(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

}  // namespace gdp::util
