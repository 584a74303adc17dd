// Workers on threads: each runs, an exception reaches the caller (no terminate), steps run in order on kept workers.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

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

// Steps of 3, 0, 5 and 40 tasks on 4 kept workers: each task runs once, after every task of the
// step before (it sees their writes), and next() never runs beside a task or another next().
TEST(RunSteps, EachStepsTasksRunOnceAfterTheStepBefore) {
  const std::vector<int> sizes = {3, 0, 5, 40};
  std::vector<std::vector<int>> runs;  // per step, per task: times run (written only by its task)
  std::atomic<int> busy{0}, bad{0};
  int step = -1;
  run_steps(
      4,
      [&] {
        bad += busy.load() != 0;
        if (++step == static_cast<int>(sizes.size())) return -1;
        runs.emplace_back(sizes[step], 0);
        return sizes[step];
      },
      [&](int, int i) {
        ++busy;
        if (step > 0)
          for (const int r : runs[step - 1]) bad += r != 1;
        ++runs[step][i];
        --busy;
      });
  EXPECT_EQ(bad.load(), 0);
  ASSERT_EQ(runs.size(), sizes.size());
  for (std::size_t s = 0; s < sizes.size(); ++s)
    EXPECT_EQ(runs[s], std::vector<int>(sizes[s], 1)) << "step " << s;
}

// A task's or next()'s exception stops the run (no later step starts) and reaches the caller.
TEST(RunSteps, AnExceptionStopsTheRunAndReachesTheCaller) {
  for (const bool in_next : {false, true}) {
    int steps = 0;
    try {
      run_steps(
          3,
          [&] {
            if (in_next && steps == 2) throw std::runtime_error("next failed");
            return ++steps <= 5 ? 10 : -1;
          },
          [&](int, int i) {
            if (!in_next && steps == 2 && i == 4) throw std::runtime_error("task failed");
          });
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), in_next ? "next failed" : "task failed");
    }
    EXPECT_EQ(steps, 2);
  }
}

}  // namespace
}  // namespace gdp::schedule
