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

std::array<int, 2> plate_rows(const Plate& plate, const PqWindow& window, double extension) {
  constexpr int kSteps = 64;
  const double m = extension * std::max(plate.width, plate.height);
  const double left = -m, top = -m, dx = (plate.width + 2 * m) / kSteps, dy = (plate.height + 2 * m) / kSteps;
  std::vector<double> xy, sky(2 * (kSteps + 1) * (kSteps + 1));
  for (int b = 0; b <= kSteps; ++b)
    for (int a = 0; a <= kSteps; ++a) xy.insert(xy.end(), {left + a * dx, top + b * dy});
  std::vector<unsigned char> ok((kSteps + 1) * (kSteps + 1));
  plate.wcs->pixel_to_sky(xy, sky, ok);
  const std::array<int, 2> every{0, window.rows - 1};
  const int depth = toast_depth(window.height);
  double y0 = window.height, y1 = -1.0;
  for (std::size_t k = 0; k < ok.size(); ++k) {
    if (!ok[k]) return every;
    const double y = sphere::pq_from_direction(sphere::SquareMap::Toast, window.height,
                                               direction(sky[2 * k], sky[2 * k + 1]), depth).y;
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  // A grid cell's diagonal in PQ rows (the PQ's mean pixel: sqrt(4 pi / 4H^2) radians).
  const double cell = std::hypot(dx, dy) * plate.scale * M_PI / 180.0 / (std::sqrt(M_PI) / window.height);
  const double margin = 1.5 * cell + 4.0;
  const int first = static_cast<int>(std::floor(y0 - margin)) - window.j0;
  const int last = static_cast<int>(std::ceil(y1 + margin)) - window.j0;
  return {std::clamp(first, 0, window.rows - 1), std::clamp(last, 0, window.rows - 1)};
}

}  // namespace gdp::sky
