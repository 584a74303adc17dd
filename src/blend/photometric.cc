// Photometric calibration: overlap samples from one decimated pass over the layers, the fit, and its application to rows.
#include "blend/photometric.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "blend/layer_rows.h"
#include "gdp/errors.h"
#include "util/seconds.h"

namespace gdp::blending {

std::vector<VignettingCentre> vignetting_centres(const BlendPlan& plan, const PhotometricOptions& options) {
  const std::size_t n = plan.layers.size();
  if (!options.centres.empty() && options.centres.size() != n)
    throw UsageError(fmt::format("vignetting centres: {} given for {} layers", options.centres.size(), n));
  std::vector<VignettingCentre> out(n);
  for (std::size_t k = 0; k < n; ++k) {
    const PlacedLayer& l = plan.layers[k];
    VignettingCentre c{(l.width - 1) / 2.0, (l.height - 1) / 2.0, 0.0};
    if (!options.centres.empty()) c = options.centres[k];
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.radius))
      throw UsageError(fmt::format("vignetting centre of {}: not a finite number", l.name));
    if (c.radius <= 0.0) c.radius = 0.5 * std::hypot(static_cast<double>(l.width), static_cast<double>(l.height));
    out[k] = c;
  }
  return out;
}

namespace {

// The layers' observations of canvas point (x, y) (row y read into `open`) when two or more see it.
void sample_point(const std::vector<VignettingCentre>& centres, const std::vector<OpenLayer>& open, int x, int y,
                  OverlapSamples& s) {
  const std::size_t first = s.obs.size();
  for (const OpenLayer& o : open) {
    const Footprint& f = o.rows->where();
    if (x < f.x0 || x >= f.x1 || !o.covered[x - f.x0]) continue;
    const VignettingCentre& c = centres[o.index];
    const double dx = x - f.x0 + f.skip_x - c.x, dy = y - f.y0 + f.skip_y - c.y;
    OverlapObservation q;
    q.layer = o.index;
    q.t = static_cast<float>((dx * dx + dy * dy) / (c.radius * c.radius));
    for (int ch = 0; ch < s.channels; ++ch) q.value[ch] = o.colour[static_cast<std::size_t>(ch) * f.width() + (x - f.x0)];
    s.obs.push_back(q);
  }
  if (s.obs.size() - first >= 2) s.start.push_back(static_cast<std::uint32_t>(s.obs.size()));
  else s.obs.resize(first);
}

}  // namespace

OverlapSamples sample_overlaps(const BlendPlan& plan, const std::vector<VignettingCentre>& centres, int grid_points) {
  const int W = plan.canvas.width, H = plan.canvas.height;
  const int step = std::max(1, static_cast<int>(std::ceil(std::sqrt(double(W) * H / std::max(1, grid_points)))));
  const int n = static_cast<int>(plan.layers.size());
  std::vector<Footprint> where(n);
  std::vector<int> by_top(n);
  for (int k = 0; k < n; ++k) where[k] = footprint(plan, k), by_top[k] = k;
  std::stable_sort(by_top.begin(), by_top.end(), [&](int a, int b) { return where[a].y0 < where[b].y0; });
  OverlapSamples s;
  s.layers = n;
  s.channels = plan.colour_channels;
  std::vector<OpenLayer> open;
  std::size_t next = 0;
  for (int y = step / 2; y < H; y += step) {
    std::erase_if(open, [&](const OpenLayer& o) { return o.rows->where().y1 <= y; });  // closed after their last row
    for (; next < by_top.size() && where[by_top[next]].y0 <= y; ++next) {
      const int k = by_top[next];
      if (where[k].y1 <= y || where[k].width() <= 0) continue;
      open.emplace_back(plan, k, 0, W, open.size() < 8);  // decoded ahead
    }
    if (open.size() < 2) continue;
    for (OpenLayer& o : open) o.read(y);  // rows between are decoded, not kept
    for (int x = step / 2; x < W; x += step) sample_point(centres, open, x, y, s);
  }
  return s;
}

Photometry calibrate(const BlendPlan& plan, const PhotometricOptions& options, BlendReport* report) {
  const auto start = util::SteadyClock::now();
  if (options.vignetting_terms < 0 || options.vignetting_terms > 3)
    throw UsageError(fmt::format("vignetting terms: {}; 0 to 3 (r^2, r^4, r^6)", options.vignetting_terms));
  // The fit solves one dense system over every layer's unknowns (about 4 per layer): hundreds of
  // layers take seconds, thousands would take hours and gigabytes.
  if (plan.layers.size() > kMaxPhotometricLayers)
    throw UsageError(fmt::format("--photometric fits at most {} layers, and there are {} (leave it off for tiled "
                                 "mosaics: their exposures agree, and the blend levels offsets without it)",
                                 kMaxPhotometricLayers, plan.layers.size()));
  const std::vector<VignettingCentre> centres = vignetting_centres(plan, options);
  const OverlapSamples samples = sample_overlaps(plan, centres, options.grid_points);
  Photometry out;
  if (samples.points() == 0) return out;  // nothing overlaps: nothing to calibrate against
  const PhotometricResult fit = fit_photometry(samples, options.vignetting_terms);
  out.vignetting = fit.vignetting;
  out.layers.resize(plan.layers.size());
  for (std::size_t k = 0; k < out.layers.size(); ++k) {
    LayerPhotometry& l = out.layers[k];
    l.gain = fit.gains[k];
    for (int c = 0; c < samples.channels; ++c) l.offset[c] = fit.offsets[k * samples.channels + c];
    l.cx = centres[k].x;
    l.cy = centres[k].y;
    l.radius = centres[k].radius;
  }
  if (report) {
    report->photometric_points = samples.points();
    report->photometric_rms_before = fit.rms_before;
    report->photometric_rms_after = fit.rms_after;
    report->seconds_photometry = util::seconds_since(start);
  }
  return out;
}

RowCalibration::RowCalibration(const BlendPlan& plan, int k) {
  if (plan.photometry.layers.empty()) return;
  active_ = true;
  layer_ = plan.photometry.layers[k];
  vignetting_ = plan.photometry.vignetting;
}

void RowCalibration::apply(int row, int x0, int w, int channels, float* colour) {
  factor_.resize(w);
  const double dy = row - layer_.cy, r2 = 1.0 / (layer_.radius * layer_.radius);
  for (int i = 0; i < w; ++i) {
    const double dx = x0 + i - layer_.cx;
    factor_[i] = static_cast<float>(1.0 / (layer_.gain * vignetting_gain(vignetting_, (dx * dx + dy * dy) * r2)));
  }
  for (int c = 0; c < channels; ++c) {
    float* v = colour + static_cast<std::size_t>(c) * w;
    const float o = static_cast<float>(layer_.offset[c]);
    for (int i = 0; i < w; ++i) v[i] = (v[i] - o) * factor_[i];
  }
}

}  // namespace gdp::blending
