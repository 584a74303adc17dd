// Futex words to sleep on and ring, lent to waiters under their owner's lock.
#include "util/bells.h"

#include <thread>

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace gdp::util {

void Bell::sleep() {
  int armed = 0;
  if (word_.compare_exchange_strong(armed, 2)) syscall(SYS_futex, &word_, FUTEX_WAIT_PRIVATE, 2, nullptr, nullptr, 0);
}

void Bell::ring() {
  if (word_.exchange(1) == 2) syscall(SYS_futex, &word_, FUTEX_WAKE_PRIVATE, 1, nullptr, nullptr, 0);
}

Bells::~Bells() {
  while (ringing_.load(std::memory_order_acquire) != 0) std::this_thread::yield();
}

Bell* Bells::take() {
  if (spare_.empty()) return &bells_.emplace_back();
  Bell* bell = spare_.back();
  spare_.pop_back();
  return bell;
}

Bell* Bells::call(Line& line) {
  if (line.empty()) return nullptr;
  Bell* bell = line.front();
  line.erase(line.begin());
  ringing_.fetch_add(1, std::memory_order_relaxed);
  return bell;
}

void Bells::ring(Bell* bell) {
  if (!bell) return;
  bell->ring();
  ringing_.fetch_sub(1, std::memory_order_release);
}

void Bells::ring_all(Line& line) {
  for (Bell* bell : line) bell->ring();
  line.clear();
}

}  // namespace gdp::util
