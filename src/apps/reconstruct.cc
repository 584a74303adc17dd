// Reconstructing an image from its own gradients from a zero start, with the error it makes.
#include <algorithm>
#include <cmath>

#include "apps/image_guidance.h"
#include "gdp/apps.h"

namespace gdp {

ReconstructResult reconstruct(const Image& image, const SolverOptions& solver, SolveSummary* summary) {
  apps::ImageGuidance guidance(image, nullptr, 0.0, 1.0);
  ReconstructResult r;
  r.image = solve(guidance, solver, nullptr, summary);
  match_means(r.image, channel_means(image));
  restore_non_finite(r.image, image);
  double s = 0.0, n = 0.0;
  for (std::size_t k = 0; k < image.data.size(); ++k) {
    if (!std::isfinite(image.data[k])) continue;
    const double d = double(r.image.data[k]) - image.data[k];
    s += d * d;
    n += 1.0;
    r.max_error = std::max(r.max_error, std::abs(d));
  }
  r.rms_error = n > 0.0 ? std::sqrt(s / n) : 0.0;
  return r;
}

}  // namespace gdp
