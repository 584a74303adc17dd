// PMPI latency injector (LD_PRELOAD): messages become visible to MPI_Improbe only a set time after they arrive.
//
// gdp's MPI transport receives by polling MPI_Improbe for a (source, tag) and then MPI_Mrecv.
// This library wraps MPI_Improbe: every message the real probe matches is held, with the time it
// was first seen, and handed out only GDP_MPI_DELAY_US microseconds later, in order per (source,
// tag, communicator). So each message's delivery is delayed by at least that much, without
// touching gdp. When it is first seen (GDP_MPI_DELAY_FROM):
//   receive (default): when the receiver first probes for it (or for an earlier message with the
//     same source and tag): every receive waits the whole delay, however early the message was
//     sent - only fewer messages help;
//   arrival: when it reaches the receiving process - a background thread per process probes the
//     communicators gdp receives on every 100 us (so up to 100 us late; polling more often costs
//     the 2-core machine measurable time) - as a network with that latency would do: a message
//     sent early enough costs nothing.
// Usage (bench/mpi_latency.sh):
//   mpirun -np 2 -x LD_PRELOAD=build/bench/libgdp_mpi_delay.so -x GDP_MPI_DELAY_US=1000 gdp ...
#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <map>
#include <mutex>
#include <thread>
#include <tuple>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

struct Held {
  MPI_Message message;
  MPI_Status status;
  Clock::time_point ready;
};

std::mutex mutex;
std::map<std::tuple<MPI_Comm, int, int>, std::deque<Held>> held;
std::vector<MPI_Comm> watched;  // arrival mode: communicators the poller drains
std::thread poller;
std::atomic<bool> stopping{false};

std::chrono::microseconds delay() {
  static const long us = [] {
    const char* v = std::getenv("GDP_MPI_DELAY_US");
    return v ? std::atol(v) : 0L;
  }();
  return std::chrono::microseconds(us);
}

bool from_arrival() {
  static const bool arrival = [] {
    const char* v = std::getenv("GDP_MPI_DELAY_FROM");
    return v && std::strcmp(v, "arrival") == 0;
  }();
  return arrival;
}

// Holds every message of `comm` that has arrived from (source, tag) - any, with MPI_ANY_*.
// Call with `mutex` held.
int hold_arrived(int source, int tag, MPI_Comm comm) {
  for (;;) {
    int got = 0;
    Held h{};
    const int rc = PMPI_Improbe(source, tag, comm, &got, &h.message, &h.status);
    if (rc != MPI_SUCCESS) return rc;
    if (!got) return MPI_SUCCESS;
    h.ready = Clock::now() + delay();
    held[{comm, h.status.MPI_SOURCE, h.status.MPI_TAG}].push_back(h);
  }
}

void poll_arrivals() {
  while (!stopping) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      for (MPI_Comm c : watched) hold_arrived(MPI_ANY_SOURCE, MPI_ANY_TAG, c);
    }
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
}

void stop_poller() {
  stopping = true;
  if (poller.joinable()) poller.join();
}

struct StopAtExit {  // for a process that ends without MPI_Finalize (destroyed before `poller`)
  ~StopAtExit() { stop_poller(); }
} stop_at_exit;

}  // namespace

extern "C" int MPI_Improbe(int source, int tag, MPI_Comm comm, int* flag, MPI_Message* message, MPI_Status* status) {
  if (source == MPI_ANY_SOURCE || tag == MPI_ANY_TAG) return PMPI_Improbe(source, tag, comm, flag, message, status);
  std::lock_guard<std::mutex> lock(mutex);
  if (from_arrival() && std::find(watched.begin(), watched.end(), comm) == watched.end()) {
    watched.push_back(comm);
    if (!poller.joinable()) poller = std::thread(poll_arrivals);
  }
  if (const int rc = hold_arrived(source, tag, comm); rc != MPI_SUCCESS) return rc;
  std::deque<Held>& queue = held[{comm, source, tag}];
  *flag = !queue.empty() && queue.front().ready <= Clock::now();
  if (*flag) {
    *message = queue.front().message;
    if (status != MPI_STATUS_IGNORE) *status = queue.front().status;
    queue.pop_front();
  }
  return MPI_SUCCESS;
}

// The poller must stop probing a communicator before it is freed, and before MPI ends.
extern "C" int MPI_Comm_free(MPI_Comm* comm) {
  {
    std::lock_guard<std::mutex> lock(mutex);
    watched.erase(std::remove(watched.begin(), watched.end(), *comm), watched.end());
  }
  return PMPI_Comm_free(comm);
}

extern "C" int MPI_Finalize() {
  stop_poller();
  return PMPI_Finalize();
}
