// Inputs and output of one application call: arrays or files, on the plane or through SphereRows.
#include "job.h"

#include <fmt/format.h>

#include "arrays.h"
#include "gdp/errors.h"
#include "gdp/strip_files.h"

namespace py = pybind11;

namespace gdp::python {

Job::~Job() = default;

std::string Job::path_of(const py::handle& value, const std::string& name) const {
  if (!py::isinstance<py::str>(value) && !py::hasattr(value, "__fspath__"))
    throw py::type_error(fmt::format("{}(): {} must be a file name (str or os.PathLike), got {}", function_, name,
                                     py::str(py::type::of(value).attr("__name__")).cast<std::string>()));
  return py::str(py::module_::import("os").attr("fspath")(value)).cast<std::string>();
}

RowReader& Job::input(const py::handle& value, const std::string& name, bool nearest) {
  const bool main = readers_.empty();
  std::string shown = name;
  if (kind_ == Kind::Arrays) {
    const py::array array = array_arg(value, function_, name);
    images_.push_back(to_image(array, name));
    readers_.push_back(std::make_unique<ImageRowReader>(images_.back()));
    if (main) {
      integer_ = is_integer(array);
      two_d_ = array.ndim() == 2;
      main_info_.sample_type = sample_type_of(array).value_or(SampleType::Float);
    }
  } else {
    shown = path_of(value, name);
  }
  // Opening files and resampling to PQ need no Python.
  const py::gil_scoped_release release;
  if (kind_ == Kind::Files) {
    auto file = std::make_unique<StripFilesReader>(shown);
    if (main) {
      main_info_ = file->info();
      integer_ = main_info_.sample_type == SampleType::UInt8 || main_info_.sample_type == SampleType::UInt16;
    }
    readers_.push_back(std::move(file));
  }
  RowReader& reader = *readers_.back();
  last_name_ = shown;
  if (main) {
    main_name_ = shown;
    if (flags_.sphere) sphere_ = std::make_unique<SphereRows>(reader.width(), reader.height(), shown, flags_.pq_height);
  }
  return sphere_ ? sphere_->input(reader, shown, nearest) : reader;
}

RowReader* Job::optional_input(const py::handle& value, const std::string& name, bool nearest) {
  return value.is_none() ? nullptr : &input(value, name, nearest);
}

WriteKeywords write_keywords(Kind kind, Keywords& kw) {
  WriteKeywords w;
  if (kind == Kind::Arrays) return w;
  kw.take("depth", w.depth);
  kw.take("quality", w.options.jpeg_quality);
  kw.take("tiled", w.options.tiled);
  kw.take("compression", w.options.compression);
  if (w.options.jpeg_quality < 1 || w.options.jpeg_quality > 100)
    throw UsageError(fmt::format("--quality must be in 1..100, got {}", w.options.jpeg_quality));
  w.options.sample_type = parse_depth(w.depth);
  return w;
}

RowWriter& Job::output(const py::handle& output, const WriteKeywords& write, int channels, bool format_default) {
  if (readers_.empty()) throw std::logic_error("Job::output before any input");
  const RowReader& main = *readers_.front();
  if (kind_ == Kind::Arrays) {
    result_ = Image(main.width(), main.height(), channels);
    writer_ = std::make_unique<ImageRowWriter>(result_);
  } else {
    WriteOptions w = write.options;
    if (!w.sample_type && !format_default) w.sample_type = main_info_.sample_type;
    check_compression(path_of(output, "output"), w.compression);  // as the CLI does
    writer_ = std::make_unique<ImageFileWriter>(path_of(output, "output"), main.width(), main.height(), channels, w);
  }
  rows_out_ = sphere_ ? &sphere_->output(*writer_, channels) : writer_.get();
  return *rows_out_;
}

py::object Job::result(const SolverArgs& args, const SolveSummary& summary, const py::dict& extra) {
  py::dict d = report(args, summary, extra);
  if (kind_ == Kind::Files) return d;
  return to_array(result_, two_d_);
}

}  // namespace gdp::python
