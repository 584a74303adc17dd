// gdp.stitch, sharpen, smooth, clone, tonemap and reconstruct, on arrays and (the *_file forms) on files.
#include "apps.h"

#include <string>

#include <fmt/format.h>
#include <pybind11/stl.h>

#include "docs.h"
#include "gdp/apps.h"
#include "gdp/errors.h"
#include "job.h"
#include "solving.h"

namespace py = pybind11;

namespace gdp::python {
namespace {

std::string named(const char* function, Kind kind) { return kind == Kind::Files ? std::string(function) + "_file" : function; }

// weights= and pin= (stitch, sharpen, smooth): per-pixel fidelity images, as the CLI's --weights and --pin.
Fidelity fidelity(Job& job, const py::object& weights, const py::object& pins) {
  Fidelity f;
  f.weights = job.optional_input(weights, "weights", true);  // Lanczos could make weights negative
  if (f.weights) f.weights_name = job.last_name();
  f.pins = job.optional_input(pins, "pin", true);
  if (f.pins) f.pins_name = job.last_name();
  return f;
}

py::object stitch(Kind kind, py::handle composite, py::handle labels, py::handle output, const py::kwargs& kwargs) {
  Keywords kw(kwargs);
  StitchOptions o;
  std::string unknown = "harmonic", space = "values";
  bool zero_start = false;
  kw.take("unknown", unknown);
  kw.take("deramp", o.deramp);
  kw.take("space", space);
  kw.take("zero_start", zero_start);
  const py::object weights = kw.take_object("weights"), pins = kw.take_object("pin");
  o.unknown = parse_unknown_mode(unknown);
  o.space.kind = parse_blend_space(space);
  o.start_from_composite = !zero_start;
  const SolverArgs args = solver_args(kw);
  const WriteKeywords write = write_keywords(kind, kw);
  kw.finish(named("stitch", kind));

  Job job(kind, named("stitch", kind), args.flags);
  RowReader& c = job.input(composite, "composite");
  if (kind == Kind::Files) o.composite_name = job.last_name();  // as the CLI names them in messages
  RowReader& l = job.input(labels, "labels", true);
  o.labels_name = job.last_name();
  const Fidelity f = fidelity(job, weights, pins);
  o.space.srgb_encoded = job.integer_input();
  RowWriter& w = job.output(output, write, c.channels());
  SolveSummary summary;
  Released(args).run([&](const SolverOptions& s) {
    gdp::stitch(c, l, o, s, w, &summary, f);
    job.commit();
  });
  return job.result(args, summary);
}

py::object sharpen(Kind kind, bool smooth, py::handle image, py::handle output, const py::kwargs& kwargs) {
  const char* function = smooth ? "smooth" : "sharpen";
  Keywords kw(kwargs);
  double beta = smooth ? 0.5 : 2.0, alpha = 0.0, scale_deg = 0.0;
  const bool alpha_given = kw.has("alpha");
  int scale_at = 0;
  SharpenScale scale;
  const bool by_scale = kw.has("scale") || kw.has("scale_at") || kw.has("scale_deg");
  if (alpha_given && by_scale) throw UsageError("alpha excludes scale, scale_at and scale_deg");
  if (kw.has("scale_at") && kw.has("scale_deg")) throw UsageError("scale_at excludes scale_deg");
  kw.take("beta", beta);
  kw.take("alpha", alpha);
  kw.take("scale", scale.pixels);
  if (kw.has("scale_at")) {
    kw.take("scale_at", scale_at);
    scale.at = scale_at;
  }
  if (kw.has("scale_deg")) {
    kw.take("scale_deg", scale_deg);
    scale.degrees = scale_deg;
  }
  const py::object low = kw.take_object("low"), weights = kw.take_object("weights"), pins = kw.take_object("pin");
  const SolverArgs args = solver_args(kw);
  const WriteKeywords write = write_keywords(kind, kw);
  kw.finish(named(function, kind));
  scale.validate(args.solver.domain);

  Job job(kind, named(function, kind), args.flags);
  RowReader& in = job.input(image, "image");
  RowReader* low_rows = job.optional_input(low, "low");
  const Fidelity f = fidelity(job, weights, pins);
  RowWriter& w = job.output(output, write, in.channels());
  const RowReader& given = job.main_input();
  if (!alpha_given) alpha = scale.alpha(args.solver.domain, given.width(), given.height(), in.width(), in.height());
  SolveSummary summary;
  Released(args).run([&](const SolverOptions& s) {
    if (low_rows) gdp::sharpen(in, *low_rows, alpha, beta, s, w, &summary, f);
    else gdp::sharpen(in, alpha, beta, s, w, &summary, f);
    job.commit();
  });
  py::dict extra;
  extra["alpha"] = alpha;
  extra["beta"] = beta;
  return job.result(args, summary, extra);
}

py::object clone(Kind kind, py::handle target, py::handle source, py::handle mask, py::handle output,
                 const py::kwargs& kwargs) {
  Keywords kw(kwargs);
  CloneOptions o;
  std::pair<int, int> offset{0, 0};
  kw.take("offset", offset);
  kw.take("mixed", o.mixed);
  o.offset_x = offset.first;
  o.offset_y = offset.second;
  SolverArgs args = solver_args(kw);
  // Pinned pixels slow each V-cycle's convergence: iterate to a tolerance unless told otherwise (as gdp clone).
  if (!args.vcycles_given) args.solver.tolerance = kCloneTolerance;
  const WriteKeywords write = write_keywords(kind, kw);
  kw.finish(named("clone", kind));

  Job job(kind, named("clone", kind), args.flags);
  RowReader& t = job.input(target, "target");
  if (kind == Kind::Files) o.target_name = job.last_name();  // as the CLI names them in messages
  RowReader& s = job.input(source, "source");
  if (kind == Kind::Files) o.source_name = job.last_name();
  RowReader& m = job.input(mask, "mask", true);
  if (kind == Kind::Files) o.mask_name = job.last_name();
  RowWriter& w = job.output(output, write, t.channels());
  SolveSummary summary;
  Released(args).run([&](const SolverOptions& options) {
    gdp::clone(t, s, m, o, options, w, &summary);
    job.commit();
  });
  return job.result(args, summary);
}

py::object tonemap(Kind kind, py::handle image, py::handle output, const py::kwargs& kwargs) {
  Keywords kw(kwargs);
  TonemapOptions o;
  kw.take("alpha", o.alpha);
  kw.take("beta", o.beta);
  kw.take("scales", o.scales);
  kw.take("resolution", o.resolution);
  kw.take("saturation", o.saturation);
  kw.take("gamma", o.gamma);
  kw.take("low", o.low_percentile);
  kw.take("high", o.high_percentile);
  const SolverArgs args = solver_args(kw, 2);
  const WriteKeywords write = write_keywords(kind, kw);
  kw.finish(named("tonemap", kind));
  o.validate();

  Job job(kind, named("tonemap", kind), args.flags);
  RowReader& in = job.input(image, "image");
  // Display values: the output format's own default sample type (8-bit PNG, float EXR) unless depth says.
  RowWriter& w = job.output(output, write, in.channels(), true);
  SolveSummary summary;
  Released(args).run([&](const SolverOptions& s) {
    gdp::tonemap(in, o, s, w, &summary);
    job.commit();
  });
  return job.result(args, summary);
}

}  // namespace

void register_apps(py::module_& m) {
  m.def(
      "stitch", [](py::handle c, py::handle l, const py::kwargs& kw) { return stitch(Kind::Arrays, c, l, {}, kw); },
      docs::kStitch, py::arg("composite"), py::arg("labels"));
  m.def(
      "stitch_file",
      [](py::handle c, py::handle l, py::handle o, const py::kwargs& kw) { return stitch(Kind::Files, c, l, o, kw); },
      docs::kStitchFile, py::arg("composite"), py::arg("labels"), py::arg("output"));
  for (const bool smooth : {false, true}) {
    const char* name = smooth ? "smooth" : "sharpen";
    m.def(
        name, [smooth](py::handle i, const py::kwargs& kw) { return sharpen(Kind::Arrays, smooth, i, {}, kw); },
        smooth ? docs::kSmooth : docs::kSharpen, py::arg("image"));
    m.def(
        (std::string(name) + "_file").c_str(),
        [smooth](py::handle i, py::handle o, const py::kwargs& kw) { return sharpen(Kind::Files, smooth, i, o, kw); },
        smooth ? docs::kSmoothFile : docs::kSharpenFile, py::arg("image"), py::arg("output"));
  }
  m.def(
      "clone",
      [](py::handle t, py::handle s, py::handle k, const py::kwargs& kw) { return clone(Kind::Arrays, t, s, k, {}, kw); },
      docs::kClone, py::arg("target"), py::arg("source"), py::arg("mask"));
  m.def(
      "clone_file",
      [](py::handle t, py::handle s, py::handle k, py::handle o, const py::kwargs& kw) {
        return clone(Kind::Files, t, s, k, o, kw);
      },
      docs::kCloneFile, py::arg("target"), py::arg("source"), py::arg("mask"), py::arg("output"));
  m.def(
      "tonemap", [](py::handle i, const py::kwargs& kw) { return tonemap(Kind::Arrays, i, {}, kw); }, docs::kTonemap,
      py::arg("image"));
  m.def(
      "tonemap_file", [](py::handle i, py::handle o, const py::kwargs& kw) { return tonemap(Kind::Files, i, o, kw); },
      docs::kTonemapFile, py::arg("image"), py::arg("output"));
}

}  // namespace gdp::python
