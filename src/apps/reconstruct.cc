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
  double s = 0.0;
  for (std::size_t k = 0; k < image.data.size(); ++k) {
    const double d = double(r.image.data[k]) - image.data[k];
    s += d * d;
    r.max_error = std::max(r.max_error, std::abs(d));
  }
  r.rms_error = image.data.empty() ? 0.0 : std::sqrt(s / double(image.data.size()));
  return r;
}

}  // namespace gdp
