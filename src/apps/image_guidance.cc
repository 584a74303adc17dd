// Differences of an image as guidance rows; non-finite samples (FITS blanks) give no guidance.
#include "apps/image_guidance.h"

#include <cmath>

namespace gdp::apps {

ImageGuidance::ImageGuidance(const Image& source, const Image* values, double alpha, double beta)
    : src_(source), values_(values), alpha_(alpha), beta_(beta) {}

void ImageGuidance::read_row(int j, GuidanceRow& out) {
  const int w = src_.width, e = out.x_edges;
  for (int c = 0; c < src_.channels; ++c) {
    const auto row = src_.row(c, j);
    for (int i = 0; i < e; ++i) {
      const int i2 = (i + 1) % w;
      const double d = double(row[i2]) - row[i];
      out.gx[c * e + i] = std::isfinite(d) && keep(i, j, i2, j) ? beta_ * d - offset(c, i, j, true) : 0.0;
    }
    if (j + 1 < src_.height) {
      const auto next = src_.row(c, j + 1);
      for (int i = 0; i < w; ++i) {
        const double d = double(next[i]) - row[i];
        out.gy[c * w + i] = std::isfinite(d) && keep(i, j, i, j + 1) ? beta_ * d - offset(c, i, j, false) : 0.0;
      }
    }
    if (values_ && alpha_ != 0.0) {
      const auto v = values_->row(c, j);
      for (int i = 0; i < w; ++i) out.value[c * w + i] = std::isfinite(v[i]) ? v[i] : 0.0;
    }
  }
}

}  // namespace gdp::apps
