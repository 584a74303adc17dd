// Row filters of the tone-mapping pyramid, each reading rows through a domain-aware window.
#include "apps/tonemap_filters.h"

#include <algorithm>
#include <cmath>

namespace gdp::apps::tonemap {

void gradient_magnitude(RowWindow& level, int y, std::span<float> out) {
  const int w = level.width();
  const std::span<const float> up = level.row(y - 1), here = level.row(y), down = level.row(y + 1);
  for (int i = 0; i < w; ++i) {
    const double gx = 0.5 * (double(here[level.column(i + 1)]) - here[level.column(i - 1)]);
    const double gy = 0.5 * (double(down[i]) - up[i]);
    out[i] = static_cast<float>(std::sqrt(gx * gx + gy * gy));
  }
}

void reduce_row(RowWindow& fine, int r, std::span<float> out) {
  static constexpr double kTaps[4] = {0.125, 0.375, 0.375, 0.125};
  const int wc = coarser(fine.width());
  std::span<const float> rows[4];
  for (int t = 0; t < 4; ++t) rows[t] = fine.row(2 * r - 1 + t);
  for (int q = 0; q < wc; ++q) {
    double sum = 0.0;
    for (int s = 0; s < 4; ++s) {
      const int i = fine.column(2 * q - 1 + s);
      double v = 0.0;
      for (int t = 0; t < 4; ++t) v += kTaps[t] * rows[t][i];
      sum += kTaps[s] * v;
    }
    out[q] = static_cast<float>(sum);
  }
}

void multiply_phi(std::span<const float> g, double a, double beta, std::span<float> inout) {
  if (!(a > 0.0) || beta == 1.0) return;
  const double floor = kFloor * a;
  for (std::size_t i = 0; i < g.size(); ++i)
    inout[i] = static_cast<float>(inout[i] * std::pow(std::max(double(g[i]), floor) / a, beta - 1.0));
}

Expander::Expander(schedule::RowStore<float>& coarse, Domain domain, int coarse_width, int coarse_height,
                   int fine_width)
    : store_(coarse), window_(domain, coarse_width, coarse_height, 3), fine_width_(fine_width),
      in_(coarse_width), mixed_(coarse_width) {
  store_.rewind();
}

void Expander::row(int y, std::span<float> out) {
  const int r = y / 2, hc = window_.height(), wc = window_.width();
  while (window_.pushed() < std::min(r + 2, hc)) {
    store_.read(in_);
    window_.push(in_);
  }
  const std::span<const float> near = window_.row(r), far = window_.row(y % 2 ? r + 1 : r - 1);
  for (int q = 0; q < wc; ++q) mixed_[q] = 0.75f * near[q] + 0.25f * far[q];
  for (int i = 0; i < fine_width_; ++i) {
    const int q = i / 2, other = window_.column(i % 2 ? q + 1 : q - 1);
    out[i] = 0.75f * mixed_[q] + 0.25f * mixed_[other];
  }
}

}  // namespace gdp::apps::tonemap
