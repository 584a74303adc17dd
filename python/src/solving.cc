// Solver keywords, summaries as dicts, and Python callbacks around a solve that runs without the GIL.
#include "solving.h"

#include <algorithm>
#include <chrono>
#include <thread>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "gdp/scratch_flags.h"

namespace py = pybind11;

namespace gdp::python {

py::object Keywords::take_object(const char* key) {
  if (!rest_.contains(key)) return py::none();
  return rest_.attr("pop")(key);
}

void Keywords::wrong_type(const char* key, const py::object& value) {
  throw py::type_error(std::string(key) + "=" + py::repr(value).cast<std::string>() + ": wrong type (" +
                       py::str(py::type::of(value).attr("__name__")).cast<std::string>() + ")");
}

void Keywords::finish(const std::string& function) const {
  for (const auto& item : rest_)
    throw py::type_error(function + "() got an unexpected keyword argument '" + py::str(item.first).cast<std::string>() +
                         "'");
}

SolverArgs solver_args(Keywords& kw, int vcycles) {
  SolverArgs a;
  SolverOptions& s = a.solver;
  s.vcycles = vcycles;
  s.threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  a.vcycles_given = kw.has("vcycles") || kw.has("tolerance");
  if (kw.has("iters")) {  // iters=K: K sweeps before restriction and after prolongation
    kw.take("iters", s.sweeps);
    s.post_sweeps = s.sweeps;
  }
  kw.take("vcycles", s.vcycles);
  kw.take("tolerance", s.tolerance);
  kw.take("threads", s.threads);
  kw.take("coarsest", s.coarsest_size);
  kw.take("incore_bytes", s.incore_bytes);
  kw.take("temp", s.temp_dir);
  // The library's float scratch unless scratch="narrow" or half_scratch=True (the CLI's default is
  // narrow: docs/how-streaming-works.md, "Who gets which").
  std::string scratch;
  bool half_scratch = false;
  kw.take("scratch", scratch);
  kw.take("half_scratch", half_scratch);
  if (scratch.empty() && !half_scratch) scratch = "float";
  if (kw.has("memory")) {
    std::size_t bytes = 0;
    kw.take("memory", bytes);
    app_scratch_memory(s, bytes);
  }
  bool double_precision = false;
  kw.take("double", double_precision);
  s.precision = double_precision ? Precision::Float64 : Precision::Float32;
  s.scratch = app_scratch_precision(scratch, half_scratch, double_precision);
  kw.take("domain", a.flags.domain);
  kw.take("sphere", a.flags.sphere);
  kw.take("pq_height", a.flags.pq_height);
  kw.take("in_core", a.flags.in_core);
  kw.take("bands", a.flags.bands);
  kw.take("verbose", a.verbose);
  kw.take("residuals", s.residuals);
  a.log = kw.take_object("log");
  a.progress = kw.take_object("progress");
  a.stats = kw.take_object("stats");
  if (!a.stats.is_none() && !py::isinstance<py::dict>(a.stats)) throw py::type_error("stats must be a dict");
  a.flags.apply(s);
  s.validate();
  return a;
}

py::dict report(const SolverArgs& args, const SolveSummary& s, const py::dict& extra) {
  py::dict d = args.stats.is_none() ? py::dict() : py::reinterpret_borrow<py::dict>(args.stats);
  d["width"] = s.width;
  d["height"] = s.height;
  d["channels"] = s.channels;
  d["levels"] = s.levels;
  d["vcycles"] = s.vcycles;
  d["schedule"] = s.schedule;
  d["streamed_levels"] = s.streamed_levels;
  // None: not measured (residuals=True, verbose, log or tolerance measure them).
  d["relative_residuals"] = s.relative_residuals.empty() ? py::object(py::none()) : py::cast(s.relative_residuals);
  d["seconds_rhs"] = s.seconds_rhs;
  d["seconds_solve"] = s.seconds_solve;
  d["scratch_bytes"] = s.scratch_bytes;
  d["solver_memory_bytes"] = s.window_bytes;
  for (const auto& item : extra) d[item.first] = item.second;
  return d;
}

Released::Released(const SolverArgs& args)
    : options_(args.solver), progress_(args.progress), log_(args.log), verbose_(args.verbose) {
  options_.progress = [this](double fraction) { on_progress(fraction); };
  if (verbose_ || !log_.is_none()) options_.log = [this](const std::string& line) { on_log(line); };
}

void Released::call(const py::object& fn, const py::object& argument) {
  try {
    fn(argument);
  } catch (py::error_already_set&) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!python_error_) python_error_ = std::current_exception();
    throw std::runtime_error("stopped by a Python callback");
  }
}

void Released::on_progress(double fraction) {
  // Without a callback, only Ctrl-C is looked at, at most ten times a second.
  const double now = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (progress_.is_none() && now - last_signal_check_ < 0.1) return;
  last_signal_check_ = now;
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (!python_error_) python_error_ = std::make_exception_ptr(py::error_already_set());
    throw std::runtime_error("interrupted");
  }
  if (!progress_.is_none()) call(progress_, py::float_(fraction));
}

void Released::on_log(const std::string& line) {
  py::gil_scoped_acquire gil;
  if (!log_.is_none()) call(log_, py::str(line));
  if (verbose_) call(py::module_::import("sys").attr("stderr").attr("write"), py::str(line + "\n"));
}

}  // namespace gdp::python
