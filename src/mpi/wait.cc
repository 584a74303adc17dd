// Sleeps on the doorbell or polls with a growing sleep: the MPI waits of the band transport, the column gather and the end of a run.
#include "mpi/wait.h"

#include <algorithm>
#include <chrono>
#include <thread>

#include "mpi/doorbell.h"

namespace gdp::mpi {
namespace {

using std::chrono::microseconds;

// Calls `ready()` until it returns true, sleeping between polls. Open MPI's blocking calls spin on
// the progress engine at 100 % of a core, taken from the rank's own workers and I/O threads where
// cores are fewer than busy threads; sched_yield (ours or Open MPI's, gdp::MpiRun) gives every busy
// thread on the core a time slice per poll, ~4 ms against ~0.2 ms for a 20 us sleep: band solves
// under load ran 5-50x slower (docs/how-bands-work.md, "No spin-waits"). Each sleep costs ~36 us
// of CPU on this VM: with a doorbell the rank sleeps until the peer rings (a sent message, a
// completed receive) and polls about once a wait ("Doorbells", docs/how-bands-work.md); the
// timeouts bound a wake-up that does not come.
void wait_until(const std::function<bool()>& ready, const std::function<void()>& between, int peer) {
  const bool bell = peer == kAnyRank ? all_ring() : rings(peer);
  if (!bell) {
    constexpr auto kFirstSleep = microseconds(20), kLongestSleep = microseconds(640);
    auto sleep = kFirstSleep;
    for (int polls = 0; !ready(); ++polls) {
      if (between && polls % 16 == 15) between();
      std::this_thread::sleep_for(sleep);  // never sched_yield (above)
      sleep = std::min(sleep * 2, kLongestSleep);
    }
    return;
  }
  // A point-to-point wait is woken by its peer: long timeouts. A collective's later rounds are
  // sent from the other ranks' polls, which do not ring: short ones at first.
  const auto longest = peer == kAnyRank ? microseconds(2000) : microseconds(8000);
  auto timeout = peer == kAnyRank ? microseconds(20) : microseconds(1000);
  for (int polls = 0;; ++polls) {
    const std::uint32_t seen = bell_count();
    // Twice: MPI_Improbe looks in the matched queue before its progress call pulls what has
    // arrived, so a message that woke this rank is found by the second probe.
    if (ready() || ready()) return;
    if (between && polls % 16 == 15) between();
    wait_bell(seen, timeout);
    timeout = std::min(timeout * 2, longest);
  }
}

}  // namespace

void wait_request(MPI_Request& request, int peer, const std::function<void()>& between) {
  wait_until(
      [&] {
        int done = 0;
        MPI_Test(&request, &done, MPI_STATUS_IGNORE);
        return done != 0;
      },
      between, peer);
}

void receive_message(int source, int tag, MPI_Comm comm, std::vector<unsigned char>& data,
                     const std::function<void()>& between) {
  MPI_Message message;
  MPI_Status status;
  wait_until(
      [&] {
        int found = 0;
        MPI_Improbe(source, tag, comm, &found, &message, &status);
        return found != 0;
      },
      between, source);
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  data.resize(static_cast<std::size_t>(count));
  MPI_Request request;
  MPI_Imrecv(data.data(), count, MPI_BYTE, &message, &request);
  wait_request(request, source, between);
  ring(source);
}

}  // namespace gdp::mpi
