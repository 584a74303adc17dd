// The solved log luminance, stored while the solver writes it; its percentiles; the display pass.
#include "apps/tonemap_display.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace gdp::apps::tonemap {

SolvedRows::SolvedRows(int width, int height, const schedule::StorePolicy& policy)
    : width_(width), height_(height), store_(policy, width, height, "tonemap-solution"),
      min_(std::numeric_limits<double>::infinity()), max_(-std::numeric_limits<double>::infinity()) {}

void SolvedRows::write_row(int, std::span<const float> row) {
  store_.append(row.first(width_));
  for (float v : row.first(width_))
    if (std::isfinite(v)) {
      min_ = std::min(min_, double(v));
      max_ = std::max(max_, double(v));
    }
}

std::pair<double, double> SolvedRows::percentiles(double low, double high) {
  if (!(min_ <= max_)) return {0.0, 0.0};
  constexpr int kBins = 1 << 16;
  const double span = std::max(max_ - min_, 1e-30), scale = kBins / span;
  std::vector<std::uint64_t> bins(kBins, 0);
  std::vector<float> row(width_);
  std::uint64_t n = 0;
  store_.rewind();
  for (int y = 0; y < height_; ++y) {
    store_.read(row);
    for (float v : row)
      if (std::isfinite(v)) {
        ++bins[std::min(kBins - 1, static_cast<int>((v - min_) * scale))];
        ++n;
      }
  }
  // The value below which `p` percent of the pixels lie: the upper edge of the bin reaching it.
  const auto at = [&](double p) {
    const double want = p / 100.0 * double(n);
    std::uint64_t seen = 0;
    for (int b = 0; b < kBins; ++b) {
      seen += bins[b];
      if (double(seen) >= want && seen > 0) return min_ + (b + 1) / scale;
    }
    return max_;
  };
  return {std::min(at(low), max_), std::min(at(high), max_)};
}

void SolvedRows::write_display(RowReader& in, const DisplayMap& map, RowWriter& out) {
  std::vector<float> u(width_), input(static_cast<std::size_t>(in.channels()) * width_), row(input.size());
  store_.rewind();
  for (int y = 0; y < height_; ++y) {
    store_.read(u);
    in.read_row(y, input);
    display_row(input, u, width_, in.channels(), map, row);
    out.write_row(y, row);
  }
}

}  // namespace gdp::apps::tonemap
