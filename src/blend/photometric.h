// Photometric calibration of blend layers: overlap samples in, a fitted exposure and vignetting model out, applied as rows are read.
#pragma once

#include <vector>

#include "blend/photometric_fit.h"
#include "gdp/blend.h"

namespace gdp::blending {

// Each layer's vignetting centre and radius: options.centres (a radius <= 0 becomes half the
// layer's diagonal), else the layer's own centre. UsageError for a list of another length than
// the layers or a non-finite entry.
std::vector<VignettingCentre> vignetting_centres(const BlendPlan& plan, const PhotometricOptions& options);

// One decimated pass over the layers (opened at their first row, closed after their last): the
// canvas points of a grid of about `grid_points` points that two or more layers cover, with each
// layer's values (as read, uncalibrated) and t = (r / radius)^2 there. Memory: the samples (about
// 24 bytes per layer per sampled overlap point) and the rows of the layers crossing a grid row.
OverlapSamples sample_overlaps(const BlendPlan& plan, const std::vector<VignettingCentre>& centres, int grid_points);

// The most layers one fit takes (its dense system grows as (4K+3)^2 for K layers).
inline constexpr std::size_t kMaxPhotometricLayers = 500;

// Samples, fits and returns the calibration for `plan` (its photometry must be empty), with the
// fit's figures in `report`. UsageError for vignetting_terms outside 0..3 or more than
// kMaxPhotometricLayers layers.
Photometry calibrate(const BlendPlan& plan, const PhotometricOptions& options, BlendReport* report = nullptr);

// Layer k's calibration applied to its rows (identity when the plan has none).
class RowCalibration {
 public:
  RowCalibration(const BlendPlan& plan, int k);
  bool active() const { return active_; }
  // Layer row `row`, the layer's own columns [x0, x0 + w): colour channel-major (stride w).
  void apply(int row, int x0, int w, int channels, float* colour);

 private:
  bool active_ = false;
  LayerPhotometry layer_;
  std::vector<double> vignetting_;
  std::vector<float> factor_;
};

}  // namespace gdp::blending
