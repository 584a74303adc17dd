// gdp.read_image, write_image, reconstruct and the sphere resampling (to_pq, from_pq), on arrays and files.
#include <string>

#include <fmt/format.h>
#include <pybind11/stl.h>

#include "apps.h"
#include "arrays.h"
#include "docs.h"
#include "gdp/apps.h"
#include "gdp/errors.h"
#include "gdp/image_stream.h"
#include "gdp/sphere.h"
#include "job.h"
#include "solving.h"

namespace py = pybind11;

namespace gdp::python {
namespace {

std::string fspath(py::handle value) { return py::str(py::module_::import("os").attr("fspath")(value)).cast<std::string>(); }

py::array_t<float> read(py::handle path) {
  const std::string name = fspath(path);
  ReadResult r;
  {
    const py::gil_scoped_release release;
    r = read_image(name);
  }
  return to_array(r.image, false);
}

void write(py::handle path, const py::array& array, const py::kwargs& kwargs) {
  Keywords kw(kwargs);
  WriteKeywords w = write_keywords(Kind::Files, kw);
  kw.finish("write_image");
  if (!w.options.sample_type) w.options.sample_type = sample_type_of(array);
  const Image image = to_image(array, "image");
  const std::string name = fspath(path);
  py::gil_scoped_release release;
  write_image(name, image, w.options);
}

// reconstruct: arrays give (image, rms_error, max_error); files a summary with both errors. With
// sphere=True the image must be PQ already (resample with to_pq first).
py::object reconstruct(Kind kind, py::handle image, py::handle output, const py::kwargs& kwargs) {
  const std::string function = kind == Kind::Files ? "reconstruct_file" : "reconstruct";
  Keywords kw(kwargs);
  SolverArgs args = solver_args(kw);
  const WriteKeywords write = write_keywords(kind, kw);
  kw.finish(function);
  ReadResult in;
  if (kind == Kind::Files) {
    const std::string name = fspath(image);
    const py::gil_scoped_release release;
    in = read_image(name);
  }
  else in.image = to_image(array_arg(image, function, "image"), "image");
  if (args.flags.sphere && in.image.width != 4 * in.image.height)
    throw UsageError(fmt::format("{}(): sphere=True needs a PQ image (width 4 x height), this one is {}x{}: "
                                 "resample it with gdp.to_pq first", function, in.image.width, in.image.height));
  SolveSummary summary;
  const ReconstructResult r =
      Released(args).run([&](const SolverOptions& s) { return gdp::reconstruct(in.image, s, &summary); });
  py::dict extra;
  extra["rms_error"] = r.rms_error;
  extra["max_error"] = r.max_error;
  py::dict d = report(args, summary, extra);
  if (kind == Kind::Arrays) {
    const bool two_d = py::reinterpret_borrow<py::array>(image).ndim() == 2;  // checked by array_arg above
    return py::make_tuple(to_array(r.image, two_d), r.rms_error, r.max_error);
  }
  if (!output.is_none()) {
    WriteOptions w = write.options;
    if (!w.sample_type) w.sample_type = in.info.sample_type;
    const std::string name = fspath(output);
    py::gil_scoped_release release;
    write_image(name, r.image, w);
  }
  return d;
}

struct Resampling {
  int size = 0;
  sphere::Projection pq{sphere::Layout::Pq}, other{sphere::Layout::Equirect};
  sphere::ResampleOptions options;
};

// The keywords of to_pq / from_pq (the CLI's gdp sphere to-pq / from-pq flags).
Resampling resampling(Keywords& kw, bool to_pq) {
  Resampling r;
  std::string map = "toast", format = "equirect";
  kw.take(to_pq ? "height" : "width", r.size);
  kw.take("map", map);
  kw.take("nearest", r.options.nearest);
  kw.take("sky", r.other.sky);
  kw.take("threads", r.options.threads);
  if (!to_pq) kw.take("format", format);
  r.pq.map = sphere::parse_square_map(map);
  if (format != "equirect" && format != "cube")
    throw UsageError(fmt::format("format must be equirect or cube, got '{}'", format));
  r.other.layout = format == "cube" ? sphere::Layout::Cube : sphere::Layout::Equirect;
  return r;
}

py::object resample(Kind kind, bool to_pq, py::handle image, py::handle output, const py::kwargs& kwargs) {
  const std::string function = std::string(to_pq ? "to_pq" : "from_pq") + (kind == Kind::Files ? "_file" : "");
  Keywords kw(kwargs);
  Resampling r = resampling(kw, to_pq);
  const WriteKeywords write = write_keywords(kind, kw);
  kw.finish(function);
  const sphere::Projection& from = to_pq ? r.other : r.pq;
  const sphere::Projection& to = to_pq ? r.pq : r.other;
  if (kind == Kind::Arrays) {
    const py::array array = array_arg(image, function, "image");
    const Image in = to_image(array, "image");
    const auto [w, h] = sphere::plan_resampling(to_pq, r.other.layout, r.size, in.width, in.height, in.channels, "image");
    Image out;
    {
      const py::gil_scoped_release release;
      out = sphere::resample(in, from, to, w, h, r.options);
    }
    return to_array(out, array.ndim() == 2);
  }
  const std::string input = fspath(image), name = fspath(output);
  std::array<int, 3> shape{};
  {
    const py::gil_scoped_release release;
    ImageFileReader in(input);
    const auto [w, h] = sphere::plan_resampling(to_pq, r.other.layout, r.size, in.width(), in.height(),
                                                  in.channels(), input);
    WriteOptions options = write.options;
    if (!options.sample_type) options.sample_type = in.info().sample_type;
    ImageFileWriter out(name, w, h, in.channels(), options);
    sphere::resample(in, from, out, to, w, h, r.options);
    out.commit();
    shape = {w, h, in.channels()};
  }
  py::dict d;
  d["width"] = shape[0];
  d["height"] = shape[1];
  d["channels"] = shape[2];
  return d;
}

}  // namespace

void register_images(py::module_& m) {
  m.def("read_image", &read, docs::kReadImage, py::arg("path"));
  m.def("write_image", &write, docs::kWriteImage, py::arg("path"), py::arg("image"));
  m.def(
      "reconstruct", [](py::handle i, const py::kwargs& kw) { return reconstruct(Kind::Arrays, i, py::none(), kw); },
      docs::kReconstruct, py::arg("image"));
  m.def(
      "reconstruct_file",
      [](py::handle i, py::handle o, const py::kwargs& kw) { return reconstruct(Kind::Files, i, o, kw); },
      docs::kReconstructFile, py::arg("image"), py::arg("output") = py::none());
  for (const bool to_pq : {true, false}) {
    const std::string name = to_pq ? "to_pq" : "from_pq";
    m.def(
        name.c_str(), [to_pq](py::handle i, const py::kwargs& kw) { return resample(Kind::Arrays, to_pq, i, {}, kw); },
        to_pq ? docs::kToPq : docs::kFromPq, py::arg("image"));
    m.def(
        (name + "_file").c_str(),
        [to_pq](py::handle i, py::handle o, const py::kwargs& kw) { return resample(Kind::Files, to_pq, i, o, kw); },
        to_pq ? docs::kToPqFile : docs::kFromPqFile, py::arg("input"), py::arg("output"));
  }
}

}  // namespace gdp::python
