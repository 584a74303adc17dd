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

namespace {

// The PQ points of a 65 x 65 grid over the extended plate: their bounding box {x0, x1, y0, y1}
// (PQ pixels of the whole image) and a margin of 1.5 grid cells and 4 pixels (TOAST pixels vary
// 1.45x in size); nullopt when a point has no sky position.
std::optional<std::array<double, 5>> extended_bounds(const Plate& plate, const PqWindow& window, double extension) {
  constexpr int kSteps = 64;
  const double m = extension * std::max(plate.width, plate.height);
  const double left = -m, top = -m, dx = (plate.width + 2 * m) / kSteps, dy = (plate.height + 2 * m) / kSteps;
  std::vector<double> xy, sky(2 * (kSteps + 1) * (kSteps + 1));
  for (int b = 0; b <= kSteps; ++b)
    for (int a = 0; a <= kSteps; ++a) xy.insert(xy.end(), {left + a * dx, top + b * dy});
  std::vector<unsigned char> ok((kSteps + 1) * (kSteps + 1));
  plate.wcs->pixel_to_sky(xy, sky, ok);
  const int depth = toast_depth(window.height);
  std::array<double, 5> b{4.0 * window.height, -1.0, double(window.height), -1.0, 0.0};
  for (std::size_t k = 0; k < ok.size(); ++k) {
    if (!ok[k]) return std::nullopt;
    const sphere::Point2 q =
        sphere::pq_from_direction(sphere::SquareMap::Toast, window.height, direction(sky[2 * k], sky[2 * k + 1]), depth);
    b = {std::min(b[0], q.x), std::max(b[1], q.x), std::min(b[2], q.y), std::max(b[3], q.y), 0.0};
  }
  // A grid cell's diagonal in PQ pixels (the PQ's mean pixel: sqrt(4 pi / 4H^2) radians).
  const double cell = std::hypot(dx, dy) * plate.scale * M_PI / 180.0 / (std::sqrt(M_PI) / window.height);
  b[4] = 1.5 * cell + 4.0;
  return b;
}

std::array<int, 2> clipped(double from, double to, int offset, int count) {
  return {std::clamp(static_cast<int>(std::floor(from)) - offset, 0, count - 1),
          std::clamp(static_cast<int>(std::ceil(to)) - offset, 0, count - 1)};
}

}  // namespace

std::array<int, 2> plate_rows(const Plate& plate, const PqWindow& window, double extension) {
  const auto b = extended_bounds(plate, window, extension);
  if (!b) return {0, window.rows - 1};
  return clipped((*b)[2] - (*b)[4], (*b)[3] + (*b)[4], window.j0, window.rows);
}

std::array<int, 2> plate_columns(const Plate& plate, const PqWindow& window, double extension) {
  if (window.whole()) return {0, window.width - 1};  // the rows wrap around: every column
  const auto b = extended_bounds(plate, window, extension);
  if (!b) return {0, window.width - 1};
  return clipped((*b)[0] - (*b)[4], (*b)[1] + (*b)[4], window.i0, window.width);
}

std::vector<int> plate_owners(const std::vector<Plate>& plates, const PqWindow& window, int ranks) {
  std::vector<int> owners;
  const int depth = toast_depth(window.height);
  for (const Plate& p : plates) {
    const double x = sphere::pq_from_direction(sphere::SquareMap::Toast, window.height, p.centre, depth).x - window.i0;
    const int column = std::clamp(static_cast<int>(std::floor(x)), 0, window.width - 1);
    owners.push_back(static_cast<int>(static_cast<long long>(column) * ranks / window.width));
  }
  return owners;
}

}  // namespace gdp::sky
