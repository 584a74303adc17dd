// Polls with a growing sleep: the MPI waits of the band transport, the column gather and the end of a run.
#include "mpi/wait.h"

#include <algorithm>
#include <chrono>
#include <thread>

namespace gdp::mpi {
namespace {

// Calls `ready()` until it returns true, sleeping between polls. Open MPI's blocking calls spin on
// the progress engine at 100 % of a core, taken from the rank's own workers and I/O threads where
// cores are fewer than busy threads; sched_yield (ours or Open MPI's, gdp::MpiRun) gives every busy
// thread on the core a time slice per poll, ~4 ms against ~0.2 ms for a 20 us sleep: band solves
// under load ran 5-50x slower (docs/how-bands-work.md, "No spin-waits").
void wait_until(const std::function<bool()>& ready, const std::function<void()>& between) {
  constexpr auto kFirstSleep = std::chrono::microseconds(20), kLongestSleep = std::chrono::microseconds(640);
  auto sleep = kFirstSleep;
  for (int polls = 0; !ready(); ++polls) {
    if (between && polls % 16 == 15) between();
    std::this_thread::sleep_for(sleep);  // never sched_yield (above)
    sleep = std::min(sleep * 2, kLongestSleep);
  }
}

}  // namespace

void wait_request(MPI_Request& request, const std::function<void()>& between) {
  wait_until(
      [&] {
        int done = 0;
        MPI_Test(&request, &done, MPI_STATUS_IGNORE);
        return done != 0;
      },
      between);
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
      between);
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  data.resize(static_cast<std::size_t>(count));
  MPI_Request request;
  MPI_Imrecv(data.data(), count, MPI_BYTE, &message, &request);
  wait_request(request, between);
}

}  // namespace gdp::mpi
