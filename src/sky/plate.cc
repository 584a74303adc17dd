// Loading a sky plate (FITS pixels and WCS), its footprint on the sphere, and interpolated samples of it.
#include "sky/plate.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "io/fits_image.h"
#include "sky/interpolate.h"
#include "sphere/vec3.h"

namespace gdp::sky {

namespace {
constexpr double kDeg = M_PI / 180.0;
}

sphere::Vec3 direction(double lon, double lat) {
  const double a = lon * kDeg, d = lat * kDeg;
  return {std::cos(d) * std::cos(a), std::cos(d) * std::sin(a), std::sin(d)};
}

void lon_lat(const sphere::Vec3& d, double& lon, double& lat) {
  lon = std::atan2(d.y, d.x) / kDeg;
  if (lon < 0.0) lon += 360.0;
  lat = std::atan2(d.z, std::hypot(d.x, d.y)) / kDeg;
}

float Plate::sample(double x, double y) const { return interpolate_clamped(pixels.data(), width, height, x, y); }

bool Plate::has_value(double x, double y) const {
  return std::isfinite(bilinear_clamped(pixels.data(), width, height, x, y));
}

std::vector<std::array<double, 2>> border_points(double left, double top, double right, double bottom, int steps) {
  std::vector<std::array<double, 2>> points;
  for (int k = 0; k <= steps; ++k) {
    const double t = double(k) / steps, x = left + t * (right - left), y = top + t * (bottom - top);
    points.insert(points.end(), {{x, top}, {x, bottom}, {left, y}, {right, y}});
  }
  return points;
}

void read_pixels(Plate& p) {
  const std::unique_ptr<io::FitsImage> image = io::open_fits(p.name);
  p.pixels.resize(static_cast<std::size_t>(p.width) * p.height);
  try {
    image->read(p.plane, 0, p.height, 0, p.width, p.pixels.data());
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: {}", p.name, e.what()));
  }
  double sum = 0.0;
  long long finite = 0;
  for (const float v : p.pixels)
    if (std::isfinite(v)) {
      sum += v;
      ++finite;
    }
  if (finite == 0) throw InputError(fmt::format("{}: every pixel is blank", p.name));
  p.mean = sum / static_cast<double>(finite);
}

Plate load_plate(const std::string& path, long plane) {
  Plate p = open_plate(path, plane);
  read_pixels(p);
  p.fade_to = p.mean;
  return p;
}

Plate open_plate(const std::string& path, long plane) {
  Plate p;
  p.name = path;
  const std::unique_ptr<io::FitsImage> image = io::open_fits(path);
  p.width = image->width();
  p.height = image->height();
  p.planes = image->planes();
  p.plane = plane;
  if (plane < 0 || plane >= p.planes)
    throw InputError(fmt::format("{}: --plane {} but the image has {} plane(s)", path, plane + 1, p.planes));
  p.wcs = std::make_unique<Wcs>(image->header(), p.width, p.height, path);
  // The footprint: the centre and the widest angle to points around the border.
  double lon = 0, lat = 0;
  if (!p.wcs->pixel_to_sky(p.width / 2.0, p.height / 2.0, lon, lat))
    throw InputError(fmt::format("{}: the plate's centre has no sky position in its WCS", path));
  p.centre = direction(lon, lat);
  double widest = 0.0;
  const int steps = 64;
  for (const auto& b : border_points(0.0, 0.0, p.width, p.height, steps))
    if (p.wcs->pixel_to_sky(b[0], b[1], lon, lat)) widest = std::max(widest, sphere::angle(p.centre, direction(lon, lat)));
  double lon1 = 0, lat1 = 0, lon2 = 0, lat2 = 0;
  p.wcs->pixel_to_sky(p.width / 2.0 + 1.0, p.height / 2.0, lon1, lat1);
  p.wcs->pixel_to_sky(p.width / 2.0, p.height / 2.0 + 1.0, lon2, lat2);
  p.scale = std::min(sphere::angle(p.centre, direction(lon1, lat1)), sphere::angle(p.centre, direction(lon2, lat2))) / kDeg;
  // Margin: border points sampled every 1/64 of a side, and two pixels.
  p.cos_radius = std::cos(std::min(M_PI, widest * (1.0 + 1.0 / steps) + 2.0 * p.scale * kDeg));
  p.cos_reach = std::cos(std::min(M_PI, 2.5 * widest + 2.0 * p.scale * kDeg));
  return p;
}

}  // namespace gdp::sky
