// PQ -> target WCS: target pixel -> (lon, lat) -> PQ coordinates -> bilinear among finite PQ pixels.
#include "sky/reproject.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "sky/bilinear.h"
#include "sky/plate.h"
#include "sphere/source.h"

namespace gdp::sky {

long long reproject_pq(const Image& pq, const PqWindow& window, const Wcs& target, RowWriter& out) {
  const int w = target.width(), h = target.height(), H = window.height;
  const auto grid = sphere::make_source({sphere::Layout::Pq, sphere::SquareMap::Toast, false}, 4 * H, H, toast_depth(H));
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
      const int hx = std::clamp(static_cast<int>(std::floor(p.x)), 0, 4 * H - 1);
      const int hy = std::clamp(static_cast<int>(std::floor(p.y)), 0, H - 1);
      const int lx = hx - window.i0, ly = hy - window.j0;  // in the window
      if (lx < 0 || ly < 0 || lx >= pq.width || ly >= pq.height) continue;
      if (!std::isfinite(pq.data[static_cast<std::size_t>(ly) * pq.width + lx])) continue;
      // Finite: the nearest pixel is. The whole sphere wraps across its folds; a window (which
      // meets none) clamps.
      row[x] = window.whole()
                   ? bilinear_finite(p.x, p.y, [&](int i, int j) { return pq.data[grid->offset(i, j, hx, hy)]; })
                   : bilinear_clamped(pq.data.data(), pq.width, pq.height, p.x - window.i0, p.y - window.j0);
      ++covered;
    }
    out.write_row(y, row);
  }
  return covered;
}

}  // namespace gdp::sky
