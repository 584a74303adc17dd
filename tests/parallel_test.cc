// Workers on threads: every one runs, and an exception reaches the caller instead of terminating.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>

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

}  // namespace
}  // namespace gdp::schedule
