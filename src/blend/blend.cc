// gdp::blend: depth seams over the layers, then stitching of the composite they make, with alpha on the way out.
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "blend/canvas_rows.h"
#include "blend/layer_fidelity.h"
#include "blend/photometric.h"
#include "blend/seam_files.h"
#include "blend/seam_share.h"
#include "blend/graphcut_seams.h"
#include "blend/seams.h"
#include "gdp/blend.h"
#include "gdp/errors.h"
#include "gdp/mpi_run.h"
#include "gdp/sphere_rows.h"
#include "util/seconds.h"

namespace gdp {
namespace {

using Clock = util::SteadyClock;
using util::seconds_since;

// Sets the colour of pixels no layer covers to 0 and, with `alpha`, adds the alpha channel from
// the label plane (0 there, 1 elsewhere) on the way to `out`. With a `correction` sweep, also
// writes output minus composite (0 where nothing covers) to `correction_out`.
class AlphaWriter final : public RowWriter {
 public:
  AlphaWriter(RowWriter& out, const blending::LabelPlane& labels, int channels, bool alpha,
              blending::CanvasSweep* correction = nullptr, RowWriter* correction_out = nullptr)
      : out_(out), labels_(labels), channels_(channels), out_channels_(channels + (alpha ? 1 : 0)),
        sweep_(correction), correction_(correction_out), labels_row_(labels.width()),
        row_(static_cast<std::size_t>(out_channels_) * labels.width()),
        difference_(correction ? static_cast<std::size_t>(channels) * labels.width() : 0) {}
  void write_row(int y, std::span<const float> row) override {
    const int w = labels_.width();
    labels_.read_row(y, labels_row_);
    for (int c = 0; c < out_channels_; ++c)
      for (int x = 0; x < w; ++x) {
        const bool known = labels_row_[x] != 0;
        const float v = c < channels_ ? row[static_cast<std::size_t>(c) * w + x] : 1.0f;
        row_[static_cast<std::size_t>(c) * w + x] = known ? v : 0.0f;
      }
    out_.write_row(y, row_);
    if (!sweep_) return;
    const std::span<const float> composite = sweep_->composite(y);
    for (std::size_t k = 0; k < difference_.size(); ++k)
      difference_[k] = labels_row_[k % w] != 0 ? row[k] - composite[k] : 0.0f;
    correction_->write_row(y, difference_);
  }
  void commit() override {
    out_.commit();
    if (correction_) correction_->commit();
  }
  void set_columns(int begin, int end) override {
    labels_.want_columns(begin, end);
    out_.set_columns(begin, end);
    if (sweep_) sweep_->set_columns(begin, end);
    if (correction_) correction_->set_columns(begin, end);
  }

 private:
  RowWriter& out_;
  const blending::LabelPlane& labels_;
  int channels_, out_channels_;
  blending::CanvasSweep* sweep_;
  RowWriter* correction_;
  std::vector<blending::Label> labels_row_;
  std::vector<float> row_, difference_;
};

// Per-layer pins (1 for the anchor and the pinned layers) and weights, checked.
std::vector<float> layer_pins(const BlendOptions& o, int layers) {
  std::vector<float> pins(layers, 0.0f);
  if (o.anchor >= layers) throw UsageError(fmt::format("--anchor {}: there are {} layers", o.anchor + 1, layers));
  if (o.anchor >= 0) pins[o.anchor] = 1.0f;
  for (const int k : o.pinned) {
    if (k < 0 || k >= layers) throw UsageError(fmt::format("--pin {}: there are {} layers", k + 1, layers));
    pins[k] = 1.0f;
  }
  return pins;
}

std::vector<float> layer_weights(const BlendOptions& o, int layers) {
  if (o.weights.empty()) return {};
  if (static_cast<int>(o.weights.size()) != layers)
    throw UsageError(fmt::format("--weights: {} weight(s) for {} layers", o.weights.size(), layers));
  for (const double w : o.weights)
    if (!(w >= 0.0) || !std::isfinite(w)) throw UsageError(fmt::format("--weights: {}; weights are finite and >= 0", w));
  return {o.weights.begin(), o.weights.end()};
}

Domain domain_of(Wrap wrap) {
  return wrap == Wrap::None ? Domain::Planar : wrap == Wrap::Horizontal ? Domain::Cylindrical : Domain::Spherical;
}

// The seams: loaded, graph-cut, or by depth. Depth seams are deferred until the solve first reads
// labels, by then knowing the columns this process solves (mpirun): only the layers meeting them
// (and a column either side, for the seams' neighbours) are read. Their time goes to the report.
// `seams` outlives the solve (deferred seams fill it then).
void find_seams(const BlendPlan& plan, const BlendOptions& options, const SolverOptions& solver, BlendReport& r,
                blending::SeamResult& seams, blending::KeptRows* keep) {
  const std::filesystem::path& temp = solver.temp_dir;
  const int threads = solver.threads;
  const bool wrap = options.wrap != Wrap::None;
  const blending::GraphcutOptions cut{.threads = threads};
  if (!options.load_seams.empty()) {
    seams = blending::load_seams(plan, options.load_seams, temp);
    return;
  }
  if (options.seams == SeamMethod::Graphcut && blending::several_ranks()) {
    // A cut is global (each move's minimum cut spans the canvas): rank 0 finds it, the others take it.
    if (MpiRun::rank() == 0) {
      seams = blending::compute_graphcut_seams(plan, wrap, temp, options.progress, cut);
    } else {
      seams.labels = std::make_unique<blending::LabelPlane>(temp, plan.canvas.width, plan.canvas.height);
      seams.overlaps.assign(plan.layers.size(), -1);
      seams.layers_read = 0;
    }
    blending::share_labels(*seams.labels);
    if (!options.save_seams.empty())
      blending::save_seams(*seams.labels, static_cast<int>(plan.layers.size()), options.save_seams);
    return;
  }
  if (options.seams == SeamMethod::Graphcut || !options.save_seams.empty()) {
    seams = options.seams == SeamMethod::Graphcut
                ? blending::compute_graphcut_seams(plan, wrap, temp, options.progress, cut)
                : blending::compute_seams(plan, wrap, temp, options.progress, threads);
    if (!options.save_seams.empty())
      blending::save_seams(*seams.labels, static_cast<int>(plan.layers.size()), options.save_seams);
    return;
  }
  seams.labels = std::make_unique<blending::LabelPlane>(temp, plan.canvas.width, plan.canvas.height);
  seams.overlaps.assign(plan.layers.size(), -1);
  seams.labels->defer([&plan, &options, &seams, &r, temp, wrap, threads, keep](blending::LabelPlane& labels, int begin,
                                                                              int end) {
    const auto start = Clock::now();
    const int W = plan.canvas.width;
    begin = std::max(0, begin - 1);
    end = std::min(W, end + 1);
    if (wrap && (begin == 0 || end == W)) begin = 0, end = W;  // the neighbours wrap around
    const blending::SeamColumns done = blending::compute_seam_columns(plan, wrap, temp, options.progress, begin, end,
                                                                      labels, seams.overlaps, threads, keep);
    r.seam_layers_read = done.layers_read;
    r.seam_columns = {begin, end};
    r.scratch_bytes = done.distance_bytes + labels.bytes() + (keep ? keep->bytes() : 0);
    r.seconds_seams += seconds_since(start);
  });
}

// What the seams found: layers read, scratch, costs, layers known to overlap no other.
void report_seams(const BlendPlan& plan, blending::SeamResult& seams, BlendReport& r) {
  if (seams.labels) seams.labels->fill();  // a solve that never read labels (none: kept for safety)
  if (r.seam_layers_read == 0) {
    r.seam_layers_read = seams.layers_read ? seams.layers_read : static_cast<int>(plan.layers.size());
    r.seam_columns = {0, plan.canvas.width};
    r.scratch_bytes = seams.scratch_bytes;
  }
  r.seam_cost_depth = seams.depth_cost;
  r.seam_cost = seams.cost;
  blending::gather_overlaps(seams.overlaps);  // mpirun: what every rank's columns saw
  if (plan.layers.size() > 1)
    for (std::size_t k = 0; k < plan.layers.size(); ++k)
      if (seams.overlaps[k] == 0) r.isolated.push_back(plan.layers[k].name);
}

}  // namespace

void blend(const BlendPlan& plan, const BlendOptions& options, const SolverOptions& solver_options, RowWriter& out,
           BlendReport* report) {
  BlendReport local;
  BlendReport& r = report ? *report : local;
  if (options.photometric.enabled && plan.photometry.layers.empty()) {  // calibrated layers, then as below
    BlendPlan calibrated = plan;
    calibrated.photometry = r.photometry = blending::calibrate(plan, options.photometric, &r);
    if (!calibrated.photometry.layers.empty()) return blend(calibrated, options, solver_options, out, &r);
  }
  const int n = static_cast<int>(plan.layers.size());
  std::vector<float> pins = layer_pins(options, n), weights = layer_weights(options, n);
  const bool pinned = options.anchor >= 0 || !options.pinned.empty();
  SolverOptions solver = solver_options;
  solver.domain = domain_of(options.wrap);
  solver.validate();
  const int W = plan.canvas.width, H = plan.canvas.height;
  std::optional<SphereRows> sphere;
  if (options.wrap == Wrap::Both) sphere.emplace(W, H, "the canvas", options.pq_height);

  auto start = Clock::now();
  // The seam pass's decoded rows, kept for the sweep (layers in files: each decoded once).
  std::optional<blending::KeptRows> kept;
  if (plan.images.empty()) kept.emplace(plan, solver.temp_dir);
  blending::SeamResult seams;
  find_seams(plan, options, solver, r, seams, kept ? &*kept : nullptr);
  r.seconds_seams = seconds_since(start);

  // Across-seam values are not resampled onto the sphere (its blending mixes them with the NaN
  // around them): resampled spheres take zero guidance across seams.
  const bool across = options.seam_guidance == SeamGuidance::Mean && !(sphere && sphere->resampled());
  blending::CanvasSweep sweep(plan, *seams.labels, options.wrap != Wrap::None, across, kept ? &*kept : nullptr);
  blending::SweepReader composite(sweep, false), across_rows(sweep, true);
  blending::LabelReader labels(*seams.labels);
  // --correction: the composite swept again as the output rows come (the layers read once more).
  std::optional<blending::CanvasSweep> again;
  if (options.correction) again.emplace(plan, *seams.labels, options.wrap != Wrap::None, false);
  AlphaWriter alpha(out, *seams.labels, plan.colour_channels, options.alpha, again ? &*again : nullptr,
                    options.correction);
  StitchOptions stitching;
  stitching.unknown = UnknownMode::Extend;
  stitching.space = options.space;
  start = Clock::now();
  const double seconds_before = r.seconds_seams;
  RowReader& c = sphere ? sphere->input(composite, "composite") : composite;
  RowReader& l = sphere ? sphere->input(labels, "labels", true) : labels;
  if (across) stitching.across = sphere ? &sphere->input(across_rows, "across") : &across_rows;
  RowWriter& w = sphere ? sphere->output(alpha, plan.colour_channels) : alpha;
  Fidelity fidelity = options.fidelity;
  std::optional<blending::LayerFidelityReader> pin_rows, weight_rows;
  if (pinned || options.fidelity.pins) {
    pin_rows.emplace(*seams.labels, pinned ? std::move(pins) : std::vector<float>{}, options.fidelity.pins,
                     options.fidelity.pins_name, true);
    fidelity.pins = sphere ? &sphere->input(*pin_rows, "pins", true) : &*pin_rows;
  }
  if (!weights.empty() || options.fidelity.weights) {
    weight_rows.emplace(*seams.labels, std::move(weights), options.fidelity.weights, options.fidelity.weights_name, false);
    fidelity.weights = sphere ? &sphere->input(*weight_rows, "weights", true) : &*weight_rows;
  }
  stitch(c, l, stitching, solver, w, &r.solve, fidelity);
  w.commit();
  r.seconds_solve = seconds_since(start) - (r.seconds_seams - seconds_before);  // less deferred seams' time
  report_seams(plan, seams, r);
}

Image blend(const std::vector<ImageLayer>& layers, const BlendOptions& options, const SolverOptions& solver,
            BlendReport* report) {
  const BlendPlan plan = plan_blend(layers, options);
  Image out(plan.canvas.width, plan.canvas.height, plan.colour_channels + (options.alpha ? 1 : 0));
  ImageRowWriter writer(out);
  blend(plan, options, solver, writer, report);
  return out;
}

}  // namespace gdp
