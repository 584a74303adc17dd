// Fitting exposure and vignetting to the layers' overlaps: robust least squares, no I/O.
#pragma once

#include <cstdint>
#include <vector>

#include "gdp/blend.h"

namespace gdp::blending {

// One layer's sample of a canvas point: its values and t = (r / radius)^2 there.
struct OverlapObservation {
  int layer = 0;
  float t = 0.0f;
  float value[3] = {0.0f, 0.0f, 0.0f};
};

// Canvas points seen by two or more layers: point p's observations are obs[start[p], start[p + 1]).
struct OverlapSamples {
  int layers = 0, channels = 0;
  std::vector<std::uint32_t> start{0};
  std::vector<OverlapObservation> obs;
  int points() const { return static_cast<int>(start.size()) - 1; }
};

struct PhotometricFit {
  // Ridges, per usable residual: on each gain's distance from 1 and on the vignetting
  // coefficients. Weak: they only decide directions the overlaps leave open (docs/blend.md).
  double gain_prior = 1e-5, vignetting_prior = 1e-7;
  double low = 1.5 / 255.0, high = 1.0 - 1.5 / 255.0;  // values outside (low, high) are clipped: unused
  int iterations = 20;
  double converged = 1e-6;  // stop when no parameter moves by more
};

struct PhotometricResult {
  std::vector<double> vignetting;  // a1..an
  std::vector<double> gains;       // per layer, geometric mean 1
  std::vector<double> offsets;     // layer k, channel c: [k * channels + c], mean 0 per channel
  double rms_before = 0.0, rms_after = 0.0;  // robust RMS of the overlap residuals
};

// Fits L_k(p) = g_k V(t_k(p)) S(p) + o_k with V(t) = 1 + sum a_j t^j (terms: 0 to 3), the scene
// S(p) per point and channel eliminated (Gauss-Newton with the scene's Schur complement), Huber
// weights. Gauge: the gains' mean is 1 and each channel's offsets sum to 0; weak ridges hold the
// gains and the falloff where the overlaps cannot tell them apart (docs/blend.md).
PhotometricResult fit_photometry(const OverlapSamples& samples, int terms, const PhotometricFit& fit = {});

// V(t) of coefficients a (clamped to at least 0.05: a fit never divides by ~0).
double vignetting_gain(const std::vector<double>& a, double t);

}  // namespace gdp::blending
