// Polls with a growing sleep: the MPI waits of the band transport, the column gather and the end of a run.
#include "mpi/wait.h"

#include <algorithm>
#include <chrono>
#include <thread>

namespace gdp::mpi {

void wait_until(const std::function<bool()>& ready, const std::function<void()>& between) {
  constexpr auto kFirstSleep = std::chrono::microseconds(20), kLongestSleep = std::chrono::microseconds(640);
  auto sleep = kFirstSleep;
  for (int polls = 0; !ready(); ++polls) {
    if (between && polls % 16 == 15) between();
    std::this_thread::sleep_for(sleep);  // never sched_yield: see wait.h
    sleep = std::min(sleep * 2, kLongestSleep);
  }
}

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
