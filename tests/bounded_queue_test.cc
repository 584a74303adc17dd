// util::BoundedQueue and util::Bells: every item once, every waiter woken by a close, destruction by the thread just woken.
#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "util/bells.h"
#include "util/bounded_queue.h"

namespace gdp::util {
namespace {

// `producers` threads push `each` distinct numbers, `consumers` threads pop until finish(): every
// number arrives exactly once, and each producer's in the order pushed.
void every_item_once(int producers, int consumers, std::size_t capacity, int each, std::size_t refill = 1) {
  BoundedQueue<int> queue(capacity, refill);
  std::vector<std::vector<int>> got(consumers);
  std::vector<std::thread> threads;
  for (int c = 0; c < consumers; ++c)
    threads.emplace_back([&, c] {
      while (std::optional<int> v = queue.pop()) got[c].push_back(*v);
    });
  std::vector<std::thread> pushers;
  for (int p = 0; p < producers; ++p)
    pushers.emplace_back([&, p] {
      for (int i = 0; i < each; ++i) EXPECT_TRUE(queue.push(p * each + i));
    });
  for (auto& t : pushers) t.join();
  queue.finish();
  for (auto& t : threads) t.join();
  std::vector<int> seen(static_cast<std::size_t>(producers) * each, 0);
  for (const auto& g : got) {
    std::vector<int> last(producers, -1);  // per producer, in a consumer's order
    for (int v : g) {
      ++seen[v];
      EXPECT_GT(v % each, last[v / each]) << "producer " << v / each << "'s items out of order";
      last[v / each] = v % each;
    }
  }
  for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << "item " << i;
}

TEST(BoundedQueue, OneProducerOneConsumerGetsEveryItemInOrder) {
  for (std::size_t capacity : {1, 2, 5}) every_item_once(1, 1, capacity, 20000);
}

TEST(BoundedQueue, ManyProducersAndConsumersGetEveryItemOnce) {
  for (int round = 0; round < 20; ++round) every_item_once(4, 3, 1 + round % 3, 1000);
}

TEST(BoundedQueue, ProducersThatRefillGetEveryItemThroughOnce) {
  for (std::size_t capacity : {1, 2, 4}) every_item_once(1, 1, capacity, 20000, capacity);
  for (int round = 0; round < 20; ++round) every_item_once(3, 2, 2 + round % 3, 1000, 2);
}

TEST(BoundedQueue, FinishLetsConsumersDrainWhatIsQueued) {
  BoundedQueue<int> queue(3);
  queue.push(1);
  queue.push(2);
  queue.finish();
  EXPECT_EQ(queue.pop(), 1);
  EXPECT_EQ(queue.pop(), 2);
  EXPECT_EQ(queue.pop(), std::nullopt);
}

TEST(BoundedQueue, CloseWakesWaitingProducersAndConsumers) {
  for (int round = 0; round < 50; ++round) {
    BoundedQueue<int> full(1), empty(1);
    ASSERT_TRUE(full.push(0));
    std::atomic<int> pushes_failed{0}, pops_failed{0};
    std::vector<std::thread> threads;
    for (int i = 0; i < 3; ++i) {
      threads.emplace_back([&] { pushes_failed += !full.push(1); });  // waits: full
      threads.emplace_back([&] { pops_failed += !empty.pop(); });     // waits: empty
    }
    if (round % 2) std::this_thread::yield();  // closed before or after some of them wait
    full.close();
    empty.close();
    for (auto& t : threads) t.join();
    EXPECT_EQ(pushes_failed.load(), 3);
    EXPECT_EQ(pops_failed.load(), 3);
    EXPECT_FALSE(full.push(2));
    EXPECT_EQ(full.pop(), std::nullopt);  // the queued item is dropped
  }
}

// The consumer destroys the queue as soon as its last pop returns, while the producer that woke it
// may still be inside push(); or the producer once a push that waited for room returns, while the
// consumer that made the room may still be inside pop(). The queue waits for that ring to finish
// (a use after free here shows under -fsanitize=thread or address: docs/multigrid.md).
TEST(BoundedQueue, MayBeDestroyedByTheThreadItJustWoke) {
  for (int round = 0; round < 4000; ++round) {
    auto queue = std::make_unique<BoundedQueue<int>>(1);
    BoundedQueue<int>* q = queue.get();
    const bool consumer_destroys = round % 2 == 0;
    std::thread other([q, consumer_destroys, round] {
      if (consumer_destroys) EXPECT_TRUE(q->push(round));
      else EXPECT_EQ(q->pop(), -1);
    });
    if (consumer_destroys) {
      EXPECT_EQ(queue->pop(), round);  // (waits for the push, mostly)
    } else {
      ASSERT_TRUE(queue->push(-1));
      ASSERT_TRUE(queue->push(round));  // waits for the other's pop, mostly
    }
    queue.reset();
    other.join();
  }
}

// Bells alone: two threads hand a turn back and forth; no wake-up is lost (a lost one hangs).
TEST(Bells, HandOffsBackAndForthAreNeverLost) {
  std::mutex mutex;
  Bells bells;
  Bells::Line lines[2];
  int turn = 0;
  const int rounds = 20000;
  auto play = [&](int me) {
    for (int i = 0; i < rounds; ++i) {
      Bell* wake = nullptr;
      {
        std::unique_lock lock(mutex);
        bells.wait(lock, lines[me], [&] { return turn == me; });
        turn = 1 - me;
        wake = bells.call(lines[1 - me]);
      }
      bells.ring(wake);
    }
  };
  std::thread other(play, 1);
  play(0);
  other.join();
  EXPECT_EQ(turn, 0);
  EXPECT_TRUE(lines[0].empty() && lines[1].empty());
}

}  // namespace
}  // namespace gdp::util
