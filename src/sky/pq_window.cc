// Bounding the plates (with their extensions) in PQ coordinates: border points -> directions -> TOAST PQ.
#include "sky/pq_window.h"

#include <algorithm>
#include <cmath>

#include "gdp/sphere.h"

namespace gdp::sky {

std::optional<PqWindow> plate_window(const std::vector<Plate>& plates, int height, double extension) {
  const int w = 4 * height, steps = 256, margin = 4;
  const int depth = toast_depth(height);
  double x0 = w, x1 = -1.0, y0 = height, y1 = -1.0;
  for (const Plate& p : plates) {
    const double m = extension * std::max(p.width, p.height);
    const double left = -m, right = p.width + m, top = -m, bottom = p.height + m;
    for (const auto& b : border_points(left, top, right, bottom, steps)) {
      double lon = 0, lat = 0;
      if (!p.wcs->pixel_to_sky(b[0], b[1], lon, lat)) return std::nullopt;  // the extension leaves the projection
      const sphere::Point2 q = sphere::pq_from_direction(sphere::SquareMap::Toast, height, direction(lon, lat), depth);
      x0 = std::min(x0, q.x);
      x1 = std::max(x1, q.x);
      y0 = std::min(y0, q.y);
      y1 = std::max(y1, q.y);
    }
  }
  PqWindow win{height, static_cast<int>(std::floor(x0)) - margin, static_cast<int>(std::floor(y0)) - margin, 0, 0};
  win.width = static_cast<int>(std::ceil(x1)) + margin - win.i0;
  win.rows = static_cast<int>(std::ceil(y1)) + margin - win.j0;
  // Border points sampled every 1/256 of a side: a window this wide may have missed a wrap.
  if (win.i0 < 0 || win.j0 < 1 || win.i0 + win.width > w || win.j0 + win.rows > height - 1) return std::nullopt;
  if (win.width > w / 2) return std::nullopt;
  if (4.0 * win.width * win.rows > double(w) * height) return std::nullopt;
  return win;
}

}  // namespace gdp::sky
