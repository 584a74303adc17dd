// Running a few workers on threads: the calling thread takes worker 0; one stop policy, one error wins.
#pragma once

#include <functional>
#include <string>

#include "gdp/errors.h"

namespace gdp::util {

// What a worker throws when it was stopped because another one failed (also schedule::Marks and
// bands::ThreadHub once stopped).
class Stopped : public Error {
 public:
  using Error::Error;
};

// Runs worker(0) .. worker(count - 1), worker 0 on the calling thread and the others on their
// own threads, and returns when all are done. When one throws, `stop` (if given) is called with
// its number and the exception's what(), to stop the others. Once every worker has finished, the
// first exception thrown that is not Stopped (which explains more than "stopped") is rethrown
// here, else the first one (a worker exception never terminates the process).
void run_workers(int count, const std::function<void(int)>& worker,
                 const std::function<void(int, const std::string&)>& stop = {});

// Runs `count` workers, kept for the whole run, through steps one after another: before each,
// next() runs on one worker while the others wait and returns the step's number of tasks (-1:
// no more steps); then the workers take its tasks, task(worker, i) for each i in [0, tasks), each
// the next not yet taken. Everything next() and the tasks of a step write is seen by the next
// step. The first exception stops the run (no more tasks or steps) and is rethrown here.
void run_steps(int count, const std::function<int()>& next, const std::function<void(int, int)>& task);

}  // namespace gdp::util
