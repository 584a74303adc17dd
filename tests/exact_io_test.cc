// util/exact_io: every byte moved through short counts and EINTR; errors and a short end name the file.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "gdp/errors.h"
#include "io/scratch_stream.h"
#include "util/exact_io.h"

namespace gdp {
namespace {

std::vector<unsigned char> pattern(std::size_t n, unsigned seed) {
  std::vector<unsigned char> b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<unsigned char>((i * 7 + seed) % 251);
  return b;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const OutputError& e) {
    return e.what();
  }
  return "(no OutputError)";
}

TEST(ExactIo, WritesAndReadsBackAtOffsets) {
  const int fd = io::open_unlinked(std::filesystem::temp_directory_path(), "exact-io-test");
  const util::FileName name{"/x/f"};
  const auto a = pattern(300001, 1), b = pattern(4096, 2);
  util::write_exactly_at(fd, a.data(), a.size(), 0, name);
  util::write_exactly_at(fd, b.data(), b.size(), 1000, name);  // over part of a
  std::vector<unsigned char> got(a.size());
  util::read_exactly_at(fd, got.data(), got.size(), 0, name);
  for (std::size_t i = 0; i < got.size(); ++i) {
    const unsigned char want = i >= 1000 && i < 1000 + b.size() ? b[i - 1000] : a[i];
    ASSERT_EQ(got[i], want) << i;
  }
  ::close(fd);
}

TEST(ExactIo, AShortReadAtTheEndIsCountedOrNamed) {
  const int fd = io::open_unlinked(std::filesystem::temp_directory_path(), "exact-io-test");
  const auto a = pattern(1000, 3);
  util::write_exactly(fd, a.data(), a.size(), {"/x/f"});  // sequential, at the file's position
  std::vector<unsigned char> got(600, 0xee);
  EXPECT_EQ(util::read_up_to_at(fd, got.data(), got.size(), 700, {"/x/f"}), 300u);
  for (std::size_t i = 0; i < 300; ++i) ASSERT_EQ(got[i], a[700 + i]) << i;
  EXPECT_EQ(got[300], 0xee);  // nothing past the end touched
  EXPECT_EQ(message_of([&] { util::read_exactly_at(fd, got.data(), got.size(), 700, {"/x/f", "scratch file in "}); }),
            "scratch file in /x/f: cannot read: the file ends early");
  ::close(fd);
}

TEST(ExactIo, AFailedWriteNamesTheFileAndTheHint) {
  const int fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  const auto a = pattern(10, 4);
  const util::FileName name{"/x/f", "checkpoint ", " (try elsewhere)"};
  EXPECT_EQ(message_of([&] { util::write_exactly_at(fd, a.data(), a.size(), 0, name); }),
            "checkpoint /x/f: cannot write: Bad file descriptor (try elsewhere)");
  const util::Transfer t = util::write_full(fd, a.data(), a.size());
  EXPECT_EQ(t.done, 0u);
  EXPECT_EQ(t.error, EBADF);
  ::close(fd);
  const int full = ::open("/dev/full", O_WRONLY | O_CLOEXEC);
  if (full < 0) GTEST_SKIP() << "no /dev/full";
  EXPECT_EQ(message_of([&] { util::write_exactly(full, a.data(), a.size(), {"/dev/full"}); }),
            "/dev/full: cannot write: No space left on device");
  ::close(full);
}

void on_signal(int) {}

// A pipe takes 64 KiB at a time and a signal without SA_RESTART interrupts the blocked writer:
// short counts and EINTR, and still every byte in order.
TEST(ExactIo, ShortCountsAndInterruptsLoseNothing) {
  struct sigaction sa {}, old{};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART
  ASSERT_EQ(::sigaction(SIGUSR1, &sa, &old), 0);
  int p[2];
  ASSERT_EQ(::pipe(p), 0);
  const auto a = pattern(std::size_t{4} << 20, 5);
  std::atomic<bool> done{false};
  util::Transfer t;
  std::thread writer([&] {
    t = util::write_full(p[1], a.data(), a.size());
    done = true;
  });
  std::thread nudger([&, handle = writer.native_handle()] {
    while (!done) {
      ::pthread_kill(handle, SIGUSR1);
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  });
  std::vector<unsigned char> got;
  std::vector<unsigned char> piece(5000);
  while (got.size() < a.size()) {
    const ssize_t k = ::read(p[0], piece.data(), piece.size());
    if (k < 0 && errno == EINTR) continue;
    ASSERT_GT(k, 0);
    got.insert(got.end(), piece.begin(), piece.begin() + k);
  }
  nudger.join();  // first: it stops once the writer is done, and uses the writer's handle till then
  writer.join();
  ::close(p[0]);
  ::close(p[1]);
  ::sigaction(SIGUSR1, &old, nullptr);
  EXPECT_EQ(t.error, 0);
  EXPECT_EQ(t.done, a.size());
  EXPECT_TRUE(got == a);
}

}  // namespace
}  // namespace gdp
