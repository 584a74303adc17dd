// Workers on threads: each runs, an exception reaches the caller (no terminate), steps run in order on kept workers;
// marks wake every waiter whose wait is met (however many at once), and only those.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "schedule/parallel.h"
#include "util/workers.h"

namespace gdp::schedule {
namespace {

using util::run_steps;
using util::run_workers;
using util::Stopped;

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

// Twelve threads wait on one mark (more than set() wakes after unlocking: the rest under the lock),
// each for its own value; raising it step by step releases them in order, none early.
TEST(Marks, EveryWaiterWakesOnceItsWaitIsMetAndNotBefore) {
  Marks marks;
  const int m = marks.add(1), count = 12;
  std::atomic<int> woken{0};
  std::vector<int> seen(count, -1);
  std::vector<std::thread> threads;
  for (int t = 0; t < count; ++t)
    threads.emplace_back([&, t] {
      marks.wait(m, t / 2);  // until the mark is above t / 2
      seen[t] = woken.fetch_add(1);
    });
  for (int v = 1; v <= count / 2; ++v) {
    marks.set(m, v);
    // Waiters of values below v go (a lost wake-up hangs here); the others must not have gone.
    while (woken.load() < 2 * v) std::this_thread::yield();
    EXPECT_EQ(woken.load(), 2 * v) << "mark " << v;
  }
  for (std::thread& th : threads) th.join();
  EXPECT_EQ(woken.load(), count);
}

// Two threads hand a count back and forth 20000 times through two marks (waiters coming and going,
// their wake-ups reused): no hand-off is lost (a lost one hangs) and each sees the other's value.
TEST(Marks, HandOffsBackAndForthAreNeverLost) {
  Marks marks;
  const int ping = marks.add(1), pong = marks.add(1), rounds = 20000;
  std::thread other([&] {
    for (int i = 1; i <= rounds; ++i) {
      marks.wait(ping, i - 1);
      marks.set(pong, i);
    }
  });
  for (int i = 1; i <= rounds; ++i) {
    marks.set(ping, i);
    marks.wait(pong, i - 1);
  }
  other.join();
  SUCCEED();
}

TEST(Marks, StopEndsEveryWaitWithStopped) {
  Marks marks;
  const int m = marks.add(1);
  std::atomic<int> stopped{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 10; ++t)
    threads.emplace_back([&] {
      try {
        marks.wait(m, 5);
      } catch (const Stopped&) {
        ++stopped;
      }
    });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  marks.stop();
  for (std::thread& th : threads) th.join();
  EXPECT_EQ(stopped.load(), 10);
  EXPECT_THROW(marks.wait(m, 5), Stopped);
}

}  // namespace
}  // namespace gdp::schedule
