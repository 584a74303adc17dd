// Workers on threads: every one runs, and an exception reaches the caller instead of terminating.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>

#include "schedule/parallel.h"

namespace gdp::schedule {
namespace {

TEST(RunWorkers, EveryWorkerRunsOnce) {
  std::atomic<int> mask{0};
  run_workers(5, [&](int t) { mask |= 1 << t; });
  EXPECT_EQ(mask.load(), 0b11111);
}

TEST(RunWorkers, AWorkersExceptionIsRethrownAfterAllFinish) {
  std::atomic<int> finished{0};
  EXPECT_THROW(run_workers(3,
                           [&](int t) {
                             ++finished;
                             if (t == 2) throw std::runtime_error("worker 2");
                           }),
               std::runtime_error);
  EXPECT_EQ(finished.load(), 3);
}

// The stop policy of the streamed solve: a failure stops the others, and the error that explains
// (not the "stopped" of a worker that was stopped) reaches the caller, even when it came later.
TEST(RunWorkers, AFailureStopsTheOthersAndTheRealErrorWins) {
  std::atomic<int> stopped_by{-1};
  try {
    run_workers(
        3,
        [&](int t) {
          if (t == 1) throw Stopped("stopped");
          if (t != 2) return;
          while (stopped_by.load() < 0) std::this_thread::yield();
          throw std::runtime_error("worker 2 failed");
        },
        [&](int t, const std::string& what) {
          if (stopped_by.load() < 0) {
            EXPECT_EQ(what, "stopped");
          }
          stopped_by = t;
        });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "worker 2 failed");
  }
  EXPECT_EQ(stopped_by.load(), 2);
}

}  // namespace
}  // namespace gdp::schedule
