// Per-channel means over a mask, mean matching, and restoring non-finite input samples.
#include <cmath>

#include "gdp/apps.h"

namespace gdp {

std::vector<double> channel_means(const Image& image, const std::vector<bool>& mask) {
  std::vector<double> means(image.channels, 0.0);
  for (int c = 0; c < image.channels; ++c) {
    double s = 0.0, n = 0.0;
    const auto p = image.plane(c);
    for (std::size_t k = 0; k < p.size(); ++k)
      if ((mask.empty() || mask[k]) && std::isfinite(p[k])) {
        s += p[k];
        n += 1.0;
      }
    means[c] = n > 0.0 ? s / n : 0.0;
  }
  return means;
}

void restore_non_finite(Image& out, const Image& input) {
  for (std::size_t k = 0; k < out.data.size(); ++k)
    if (!std::isfinite(input.data[k])) out.data[k] = input.data[k];
}

void match_means(Image& image, const std::vector<double>& target, const std::vector<bool>& mask) {
  const std::vector<double> now = channel_means(image, mask);
  for (int c = 0; c < image.channels; ++c) {
    const float shift = static_cast<float>(target[c] - now[c]);
    for (float& v : image.plane(c)) v += shift;
  }
}

}  // namespace gdp
