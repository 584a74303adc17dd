// Running a few workers on threads: the calling thread takes worker 0, the first exception wins.
#pragma once

#include <functional>

namespace gdp::schedule {

// Runs worker(0) .. worker(count - 1), worker 0 on the calling thread and the others on their
// own threads, and returns when all are done. If any throws, the first exception is rethrown
// here after every worker has finished (a worker exception never terminates the process).
void run_workers(int count, const std::function<void(int)>& worker);

}  // namespace gdp::schedule
