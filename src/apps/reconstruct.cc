// Reconstructing an image from its own gradients from a zero start, with the error it makes.
#include <algorithm>
#include <cmath>

#include "gdp/apps.h"

namespace gdp {

ReconstructResult reconstruct(const Image& image, const SolverOptions& solver, SolveSummary* summary) {
  ReconstructResult r;
  r.image = Image(image.width, image.height, image.channels);
  ImageRowReader in(image);
  ImageRowWriter writer(r.image);
  reconstruct(in, solver, writer, summary);
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
