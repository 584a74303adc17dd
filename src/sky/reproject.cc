// PQ -> target WCS: target pixel -> (lon, lat) -> PQ coordinates -> cubic (bilinear near blanks) among finite PQ pixels.
#include "sky/reproject.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "sky/interpolate.h"
#include "sky/plate.h"
#include "sphere/source.h"

namespace gdp::sky {

PqSampler::PqSampler(const Image& pq, const PqWindow& window)
    : pq_(pq),
      window_(window),
      grid_(sphere::make_source({sphere::Layout::Pq, sphere::SquareMap::Toast, false}, 4 * window.height,
                                window.height, toast_depth(window.height))) {}

PqSampler::~PqSampler() = default;

float PqSampler::at(const sphere::Vec3& d) const {
  const int H = window_.height;
  const sphere::Point2 p = grid_->coords(d);
  const int hx = std::clamp(static_cast<int>(std::floor(p.x)), 0, 4 * H - 1);
  const int hy = std::clamp(static_cast<int>(std::floor(p.y)), 0, H - 1);
  const int lx = hx - window_.i0, ly = hy - window_.j0;  // in the window
  const float nan = std::numeric_limits<float>::quiet_NaN();
  if (lx < 0 || ly < 0 || lx >= pq_.width || ly >= pq_.height) return nan;
  if (!std::isfinite(pq_.data[static_cast<std::size_t>(ly) * pq_.width + lx])) return nan;
  // Finite: the nearest pixel is. The whole sphere wraps across its folds; a window (which
  // meets none) clamps.
  return window_.whole()
             ? interpolate_finite(p.x, p.y, [&](int i, int j) { return pq_.data[grid_->offset(i, j, hx, hy)]; })
             : interpolate_clamped(pq_.data.data(), pq_.width, pq_.height, p.x - window_.i0, p.y - window_.j0);
}

long long reproject_pq(const Image& pq, const PqWindow& window, const Wcs& target, RowWriter& out) {
  const int w = target.width(), h = target.height();
  const PqSampler sampler(pq, window);
  std::vector<double> xy(2 * static_cast<std::size_t>(w)), sky(2 * static_cast<std::size_t>(w));
  std::vector<unsigned char> ok(w);
  std::vector<float> row(w);
  long long covered = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      xy[2 * x] = x + 0.5;
      xy[2 * x + 1] = y + 0.5;
    }
    target.pixel_to_sky(xy, sky, ok);
    for (int x = 0; x < w; ++x) {
      row[x] = ok[x] ? sampler.at(direction(sky[2 * x], sky[2 * x + 1])) : std::numeric_limits<float>::quiet_NaN();
      if (std::isfinite(row[x])) ++covered;
    }
    out.write_row(y, row);
  }
  return covered;
}

}  // namespace gdp::sky
