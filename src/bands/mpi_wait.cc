// Polls with a growing sleep: the MPI waits of the band transport and the column gather.
#include "bands/mpi_wait.h"

#include <algorithm>
#include <chrono>
#include <thread>

namespace gdp::bands {

void wait_until(const std::function<bool()>& ready, const std::function<void()>& between) {
  constexpr int kYields = 64;
  constexpr auto kFirstSleep = std::chrono::microseconds(20), kLongestSleep = std::chrono::microseconds(320);
  auto sleep = kFirstSleep;
  for (int polls = 0; !ready(); ++polls) {
    if (between && polls % 16 == 15) between();
    if (polls < kYields) {
      std::this_thread::yield();
    } else {
      std::this_thread::sleep_for(sleep);
      sleep = std::min(sleep * 2, kLongestSleep);
    }
  }
}

}  // namespace gdp::bands
