// PQ -> target WCS: target pixel -> (lon, lat) -> PQ coordinates -> bilinear among finite PQ pixels.
#include "sky/reproject.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "sky/plate.h"
#include "sphere/source.h"

namespace gdp::sky {

long long reproject_pq(const Image& pq, const Wcs& target, RowWriter& out) {
  const int w = target.width(), h = target.height(), H = pq.height;
  const auto grid = sphere::make_source({sphere::Layout::Pq, sphere::SquareMap::Toast, false}, pq.width, H,
                                        static_cast<int>(std::ceil(std::log2(2.0 * H))) + 3);
  const float nan = std::numeric_limits<float>::quiet_NaN();
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
      row[x] = nan;
      if (!ok[x]) continue;
      const sphere::Point2 p = grid->coords(direction(sky[2 * x], sky[2 * x + 1]));
      const int hx = std::clamp(static_cast<int>(std::floor(p.x)), 0, pq.width - 1);
      const int hy = std::clamp(static_cast<int>(std::floor(p.y)), 0, H - 1);
      if (!std::isfinite(pq.data[static_cast<std::size_t>(hy) * pq.width + hx])) continue;
      const double fx = p.x - 0.5, fy = p.y - 0.5;
      const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
      double sum = 0.0, weight = 0.0;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const float v = pq.data[grid->offset(x0 + dx, y0 + dy, hx, hy)];
          const double wt = (dx ? fx - x0 : 1.0 - (fx - x0)) * (dy ? fy - y0 : 1.0 - (fy - y0));
          if (!std::isfinite(v) || wt == 0.0) continue;
          sum += wt * v;
          weight += wt;
        }
      row[x] = static_cast<float>(sum / weight);  // weight > 0: the nearest pixel is finite
      ++covered;
    }
    out.write_row(y, row);
  }
  return covered;
}

}  // namespace gdp::sky
