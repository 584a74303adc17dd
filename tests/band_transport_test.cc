// The thread transport (order per sender and tag, stop wakes every waiter) and failures in a band solve.
#include <gtest/gtest.h>

#include <thread>

#include "bands/transport.h"
#include "gdp/errors.h"
#include "gdp/solver.h"
#include "test_util.h"

namespace gdp::bands {
namespace {

TEST(ThreadTransport, MessagesArriveInOrderPerSenderAndTag) {
  ThreadHub hub(3);
  std::thread a([&] {
    for (unsigned char i = 0; i < 50; ++i) hub.endpoint(0).send(2, 7, Bytes{i});
  });
  std::thread b([&] {
    for (unsigned char i = 0; i < 50; ++i) hub.endpoint(1).send(2, 7, Bytes{static_cast<unsigned char>(100 + i)});
    hub.endpoint(1).send(2, 8, Bytes{1, 2, 3});
  });
  Transport& me = hub.endpoint(2);
  EXPECT_EQ(me.receive(1, 8), (Bytes{1, 2, 3}));  // another tag may overtake
  for (unsigned char i = 0; i < 50; ++i) {
    EXPECT_EQ(me.receive(0, 7), Bytes{i});
    EXPECT_EQ(me.receive(1, 7), Bytes{static_cast<unsigned char>(100 + i)});
  }
  a.join();
  b.join();
}

TEST(ThreadTransport, AbortWakesEveryWaiterWithTheReason) {
  ThreadHub hub(3);
  std::vector<std::string> seen(2);
  std::vector<std::thread> waiters;
  for (int w = 0; w < 2; ++w)
    waiters.emplace_back([&, w] {
      try {
        hub.endpoint(w).receive(2, 0);
      } catch (const util::Stopped& e) {
        seen[w] = e.what();
      }
    });
  hub.stop("band 2 stopped: disk full");
  for (auto& t : waiters) t.join();
  EXPECT_EQ(seen[0], "band 2 stopped: disk full");
  EXPECT_EQ(seen[1], "band 2 stopped: disk full");
  EXPECT_THROW(hub.endpoint(0).send(1, 0, {}), util::Stopped);
}

// A token passed round four workers, 2000 times, each send waking only the worker it is for:
// every message arrives (a lost wake-up hangs), and a worker's receive from one sender is not
// taken by a message from another.
TEST(ThreadTransport, ATokenGoesRoundEveryWorkerWithoutALostWakeUp) {
  const int n = 4, rounds = 2000;
  ThreadHub hub(n);
  std::vector<int> last(n, -1);
  std::vector<std::thread> workers;
  for (int w = 0; w < n; ++w)
    workers.emplace_back([&, w] {
      Transport& me = hub.endpoint(w);
      for (int r = 0; r < rounds; ++r) {
        if (w != 0 || r > 0) {
          const Bytes got = me.receive((w + n - 1) % n, 3);
          last[w] = got[0] + 256 * got[1];
        }
        const int token = r * n + w;
        me.send((w + 1) % n, 3,
                Bytes{static_cast<unsigned char>(token % 256), static_cast<unsigned char>(token / 256)});
        me.send((w + 2) % n, 4, Bytes{1});  // noise on another tag, received at the end
      }
    });
  for (auto& t : workers) t.join();
  EXPECT_EQ(hub.endpoint(0).receive(n - 1, 3), (Bytes{static_cast<unsigned char>((rounds * n - 1) % 256),
                                                      static_cast<unsigned char>((rounds * n - 1) / 256)}));
  for (int w = 0; w < n; ++w) {
    EXPECT_EQ(last[w], (rounds - 1) * n + w - 1) << "worker " << w;
    for (int r = 0; r < rounds; ++r) ASSERT_EQ(hub.endpoint(w).receive((w + n - 2) % n, 4), Bytes{1});
  }
}

// Guidance that fails part-way through, like a truncated input file.
class FailingSource : public test::ExactGradients {
 public:
  using ExactGradients::ExactGradients;
  void read_row(int j, GuidanceRow& out) override {
    if (j == 150) throw InputError("input.tif: row 150 is truncated");
    ExactGradients::read_row(j, out);
  }
};

TEST(BandSolve, AnInputErrorStopsEveryBandWithItsMessage) {
  const Image img = test::random_image(400, 200, 1, 2);
  FailingSource src(img, Domain::Planar);
  SolverOptions o;
  o.schedule = Schedule::Bands;
  o.bands = 3;
  o.incore_bytes = 4096;
  try {
    solve(src, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "input.tif: row 150 is truncated");
  }
}

}  // namespace
}  // namespace gdp::bands
