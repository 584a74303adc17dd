// What one call of an application reads and writes: arrays or files in, an array or a file out,
// resampled to the PQ domain and back when the call asks for sphere=True.
#pragma once

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/numpy.h>

#include "gdp/image_stream.h"
#include "gdp/solver.h"
#include "gdp/sphere_rows.h"
#include "solving.h"

namespace gdp::python {

// Arrays (the in-memory functions) or file names (the *_file functions).
enum class Kind { Arrays, Files };

// The keywords of an output file: depth ("8", "16", "half", "float"), quality, tiled, compression.
struct WriteKeywords {
  std::string depth;
  WriteOptions options;
};
// Takes them from `kw` for Kind::Files (arrays have none).
WriteKeywords write_keywords(Kind kind, Keywords& kw);

class Job {
 public:
  Job(Kind kind, const std::string& function, const ScheduleFlags& flags)
      : kind_(kind), function_(function), flags_(flags) {}
  ~Job();

  // Opens an image argument: an array (converted now, under the GIL) or a file name (str or
  // os.PathLike, streamed). The first one is the main input: it sets the output's size and, with
  // sphere=True, the PQ resampling, which the others follow (`nearest` for label maps and masks).
  RowReader& input(const pybind11::handle& value, const std::string& name, bool nearest = false);
  // The same, or nullptr for None (optional inputs).
  RowReader* optional_input(const pybind11::handle& value, const std::string& name, bool nearest = false);
  // True when the main input was an 8- or 16-bit array or file (display-encoded values).
  bool integer_input() const { return integer_; }

  // The main input as given (before any resampling to PQ).
  const RowReader& main_input() const { return *readers_.front(); }
  // The name the last input is called in errors: its file name, or the argument's name.
  const std::string& last_name() const { return last_name_; }

  // The rows the application writes (after the inputs): into an array, or into the file `output`
  // (sample type: `write.depth`, else the main input's, or with `format_default` the output
  // format's own). Through SphereRows when sphere=True.
  RowWriter& output(const pybind11::handle& output, const WriteKeywords& write, int channels,
                    bool format_default = false);
  // After the application has written every row (no GIL needed).
  void commit() { rows_out_->commit(); }
  // The array written (with `summary` in the stats dict when one was given), or for a file the
  // summary as a dict; `extra` is added to the summary.
  pybind11::object result(const SolverArgs& args, const SolveSummary& summary, const pybind11::dict& extra = {});

 private:
  std::string path_of(const pybind11::handle& value, const std::string& name) const;
  Kind kind_;
  std::string function_;
  ScheduleFlags flags_;
  bool integer_ = false, two_d_ = false;
  std::string main_name_, last_name_;
  ImageFileInfo main_info_;
  std::deque<Image> images_;
  std::vector<std::unique_ptr<RowReader>> readers_;
  std::unique_ptr<SphereRows> sphere_;
  Image result_;
  std::unique_ptr<RowWriter> writer_;
  RowWriter* rows_out_ = nullptr;
};

}  // namespace gdp::python
