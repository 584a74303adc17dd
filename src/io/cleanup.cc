// Registry of files to delete on interruption, with signal handlers that use it.
#include "gdp/cleanup.h"

#include <unistd.h>

#include <array>
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <cstring>

namespace gdp::cleanup {
namespace {

// Fixed storage so the signal handler needs no allocation or locks: a slot is claimed with
// `claimed`, filled, then published with `ready`.
struct Slot {
  std::atomic<bool> claimed{false};
  std::atomic<bool> ready{false};
  char path[4096];
};
std::array<Slot, 64> g_slots;

void on_signal(int sig) {
  remove_tracked();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

}  // namespace

int track(const std::string& path) {
  if (path.size() >= sizeof(Slot::path)) return -1;
  // Also when a library calls exit() (libjpeg does on some errors) before the owner untracks.
  static const bool at_exit = std::atexit(remove_tracked) == 0;
  (void)at_exit;
  for (int i = 0; i < static_cast<int>(g_slots.size()); ++i) {
    bool expected = false;
    if (!g_slots[i].claimed.compare_exchange_strong(expected, true)) continue;
    std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
    g_slots[i].ready.store(true);
    return i;
  }
  return -1;
}

void untrack(int handle) {
  if (handle < 0 || handle >= static_cast<int>(g_slots.size())) return;
  g_slots[handle].ready.store(false);
  g_slots[handle].claimed.store(false);
}

void remove_tracked() noexcept {
  for (Slot& s : g_slots)
    if (s.ready.load()) ::unlink(s.path);
}

void install_signal_handlers() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) std::signal(sig, on_signal);
  // A file-size limit (ulimit -f) then fails the write (EFBIG), which the writer reports and
  // cleans up after, instead of killing the process.
  std::signal(SIGXFSZ, SIG_IGN);
}

}  // namespace gdp::cleanup
