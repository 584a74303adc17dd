// Test tool run under mpirun -np 2: rank 1 sends rank 0 a message after a pause; rank 0 prints how often its waiting thread slept.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "bands/mpi_transport.h"
#include "gdp/mpi_run.h"

int main(int argc, char** argv) {
  gdp::MpiRun run(argc, argv);
  const int pause_ms = argc > 1 ? std::atoi(argv[1]) : 1000;
  gdp::bands::MpiHub hub(1);
  if (gdp::MpiRun::rank() == 1) {
    std::this_thread::sleep_for(std::chrono::milliseconds(pause_ms));
    hub.own().send(0, 7, gdp::bands::Bytes{1, 2, 3});
  } else if (gdp::MpiRun::rank() == 0) {
    rusage before{}, after{};
    getrusage(RUSAGE_THREAD, &before);
    const gdp::bands::Bytes got = hub.own().receive(1, 7);
    getrusage(RUSAGE_THREAD, &after);
    // Each poll that finds nothing sleeps once: a voluntary context switch.
    std::printf("sleeps %ld message %zu bytes %d %d %d\n", after.ru_nvcsw - before.ru_nvcsw, got.size(),
                got.size() == 3 ? got[0] : -1, got.size() == 3 ? got[1] : -1, got.size() == 3 ? got[2] : -1);
  }
  return 0;
}
