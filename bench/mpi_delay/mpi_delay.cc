// PMPI latency injector (LD_PRELOAD): messages become visible to MPI_Improbe only a set time after they arrive.
//
// gdp's MPI transport receives by polling MPI_Improbe for a (source, tag) and then MPI_Mrecv.
// This library wraps MPI_Improbe: every message the real probe matches is held, with the time it
// was first seen, and handed out only GDP_MPI_DELAY_US microseconds later, in order per (source,
// tag, communicator). So each message's delivery is delayed by at least that much, as a slow
// network would do, without touching gdp. Usage (bench/mpi_latency.sh):
//   mpirun -np 2 -x LD_PRELOAD=build/bench/mpi_delay/libgdp_mpi_delay.so -x GDP_MPI_DELAY_US=1000 gdp ...
#include <mpi.h>

#include <chrono>
#include <cstdlib>
#include <deque>
#include <map>
#include <mutex>
#include <tuple>

namespace {

using Clock = std::chrono::steady_clock;

struct Held {
  MPI_Message message;
  MPI_Status status;
  Clock::time_point ready;
};

std::mutex mutex;
std::map<std::tuple<MPI_Comm, int, int>, std::deque<Held>> held;

std::chrono::microseconds delay() {
  static const long us = [] {
    const char* v = std::getenv("GDP_MPI_DELAY_US");
    return v ? std::atol(v) : 0L;
  }();
  return std::chrono::microseconds(us);
}

}  // namespace

extern "C" int MPI_Improbe(int source, int tag, MPI_Comm comm, int* flag, MPI_Message* message, MPI_Status* status) {
  if (source == MPI_ANY_SOURCE || tag == MPI_ANY_TAG) return PMPI_Improbe(source, tag, comm, flag, message, status);
  std::lock_guard<std::mutex> lock(mutex);
  std::deque<Held>& queue = held[{comm, source, tag}];
  for (;;) {  // hold everything that has arrived
    int got = 0;
    Held h{};
    const int rc = PMPI_Improbe(source, tag, comm, &got, &h.message, &h.status);
    if (rc != MPI_SUCCESS) return rc;
    if (!got) break;
    h.ready = Clock::now() + delay();
    queue.push_back(h);
  }
  *flag = !queue.empty() && queue.front().ready <= Clock::now();
  if (*flag) {
    *message = queue.front().message;
    if (status != MPI_STATUS_IGNORE) *status = queue.front().status;
    queue.pop_front();
  }
  return MPI_SUCCESS;
}
