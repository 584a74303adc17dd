// Gradient-domain applications: each builds guidance for the one solver.
#pragma once

#include "gdp/image.h"
#include "gdp/solver.h"

namespace gdp {

// What to do with pixels whose label is the reserved "unknown" colour (all channels 1.0, white).
enum class UnknownMode {
  Black,     // fill smoothly for the solve, then output black there
  Harmonic,  // no gradients into or inside them: a smooth (harmonic) fill
  Label,     // white is an ordinary label
};

struct StitchOptions {
  UnknownMode unknown = UnknownMode::Harmonic;
  bool deramp = false;            // subtract each label's mean gradient (removes linear ramps)
  bool start_from_composite = true;  // initial guess: the composite (else zero)
};

// Seamless stitching: gradients of the composite, zero across label changes; the output's mean
// (over known pixels) matches the composite's. Labels are compared exactly, any channel count.
Image stitch(const Image& composite, const Image& labels, const StitchOptions& options,
             const SolverOptions& solver, SolveSummary* summary = nullptr);

// Gradient-domain sharpening (beta > 1) or smoothing (beta < 1): fit gradients beta * grad(I)
// and values I with weight alpha. alpha = 1 / s^2 changes detail finer than about s pixels.
Image sharpen(const Image& image, double alpha, double beta, const SolverOptions& solver,
              SolveSummary* summary = nullptr);

struct ReconstructResult {
  Image image;
  double rms_error = 0.0;  // against the input, after matching means, per value
  double max_error = 0.0;
};

// Rebuilds an image from its own gradients from a zero start (a self-test on real data).
ReconstructResult reconstruct(const Image& image, const SolverOptions& solver, SolveSummary* summary = nullptr);

// Shifts each channel so that its mean over the pixels where mask is true (all when empty)
// equals target[c]. Means skip non-finite samples.
void match_means(Image& image, const std::vector<double>& target, const std::vector<bool>& mask = {});
std::vector<double> channel_means(const Image& image, const std::vector<bool>& mask = {});

// Non-finite input samples (NaN blanks in FITS, say) carry no guidance; applications put them
// back unchanged in their output with this.
void restore_non_finite(Image& out, const Image& input);

}  // namespace gdp
