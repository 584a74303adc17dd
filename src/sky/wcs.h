// World coordinates of a sky image: a FITS header's celestial WCS parsed by wcslib, pixel <-> (RA, Dec) both ways.
#pragma once

#include <memory>
#include <span>
#include <string>

namespace gdp::sky {

// Pixels are gdp's: pixel (i, j) covers [i, i + 1) x [j, j + 1), rows top down, so continuous
// (x, y) is FITS pixel (x + 0.5, height + 0.5 - y). Sky coordinates are the WCS's longitude and
// latitude in degrees (RA and Dec for equatorial headers; frame() names them).
class Wcs {
 public:
  // `header`: FITS header cards (80 characters each) of an image `width` x `height`; every
  // projection and distortion (SIP, TPV, DSS, ...) wcslib reads, CD or PC + CDELT, informal
  // forms wcsfix repairs. Throws InputError "`name`: ..." naming the keyword or the problem when
  // the header has no celestial WCS or wcslib rejects it.
  Wcs(const std::string& header, int width, int height, const std::string& name);
  ~Wcs();
  Wcs(const Wcs&) = delete;
  Wcs& operator=(const Wcs&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  // "RA", "GLON", "ELON", ...: the longitude axis's type (images blend only in one frame).
  const std::string& frame() const { return frame_; }
  // The projection's code ("TAN", "CAR", ...).
  const std::string& projection() const { return projection_; }

  // n points: xy = x0, y0, x1, y1, ...  ->  sky = lon0, lat0, ... (degrees); ok[k] = 0 where
  // the point has no sky position (outside the projection's domain). Not thread-safe: one Wcs
  // per thread.
  void pixel_to_sky(std::span<const double> xy, std::span<double> sky, std::span<unsigned char> ok) const;
  void sky_to_pixel(std::span<const double> sky, std::span<double> xy, std::span<unsigned char> ok) const;
  // One point; false when it has no position.
  bool pixel_to_sky(double x, double y, double& lon, double& lat) const;
  bool sky_to_pixel(double lon, double lat, double& x, double& y) const;

 private:
  bool one_point(bool to_sky, double a, double b, double& u, double& v) const;
  struct Prm;
  std::unique_ptr<Prm> prm_;
  int width_, height_;
  std::string frame_, projection_;
};

}  // namespace gdp::sky
