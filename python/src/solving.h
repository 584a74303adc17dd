// The solver's options from Python keywords (the CLI's flags), Python callbacks, the GIL released while solving.
#pragma once

#include <atomic>
#include <exception>
#include <mutex>
#include <string>
#include <utility>

#include <pybind11/pybind11.h>

#include "gdp/solver.h"

namespace gdp::python {

// Keyword arguments taken one by one; what is left at the end is an unexpected keyword.
class Keywords {
 public:
  explicit Keywords(const pybind11::kwargs& kwargs) : rest_(pybind11::dict(kwargs)) {}
  bool has(const char* key) const { return rest_.contains(key); }
  template <class T>
  void take(const char* key, T& into) {
    if (!rest_.contains(key)) return;
    const pybind11::object value = rest_.attr("pop")(key);
    try {
      into = value.template cast<T>();
    } catch (const pybind11::cast_error&) {
      wrong_type(key, value);
    }
  }
  pybind11::object take_object(const char* key);
  [[noreturn]] static void wrong_type(const char* key, const pybind11::object& value);
  // Throws TypeError naming the first keyword nobody took, as Python does for `function`.
  void finish(const std::string& function) const;

 private:
  pybind11::dict rest_;
};

// Solver keywords of every solving function (docs/python.md): iters, vcycles, tolerance, threads,
// coarsest, domain, sphere, pq_height, double, in_core, incore_bytes, bands, temp, half_scratch, memory,
// verbose, residuals, log, progress, stats.
struct SolverArgs {
  SolverOptions solver;
  ScheduleFlags flags;
  bool verbose = false;
  pybind11::object log, progress, stats;  // callables and a dict to fill, or None
  bool vcycles_given = false;             // vcycles or tolerance was passed
};
// Takes the solver keywords from `kw`; vcycles defaults to `vcycles` (tonemap solves twice).
SolverArgs solver_args(Keywords& kw, int vcycles = 1);

// Fills args.stats (when a dict was given) with the summary and `extra`, and returns it as a dict.
pybind11::dict report(const SolverArgs& args, const SolveSummary& summary, const pybind11::dict& extra = {});

// Runs f(solver_options) with the GIL released. The options' progress and log hooks take the GIL
// back to call Python; an exception raised there (KeyboardInterrupt included: Ctrl-C is looked
// at on every progress report of the calling thread) stops the solve and is raised again here.
class Released {
 public:
  explicit Released(const SolverArgs& args);
  template <class F>
  decltype(auto) run(F&& f) {
    try {
      pybind11::gil_scoped_release release;
      return f(options_);
    } catch (...) {
      if (python_error_) std::rethrow_exception(python_error_);
      throw;
    }
  }

 private:
  void on_progress(double fraction);
  void on_log(const std::string& line);
  void call(const pybind11::object& fn, const pybind11::object& argument);
  SolverOptions options_;
  pybind11::object progress_, log_;
  bool verbose_;
  std::mutex mutex_;
  std::exception_ptr python_error_;
  std::atomic<double> last_signal_check_{-1.0};
};

}  // namespace gdp::python
