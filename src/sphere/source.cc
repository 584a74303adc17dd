// Resampling sources (equirectangular, PQ, cube strip) and the Lanczos-3 and nearest samplers.
#include "sphere/source.h"

#include <cmath>
#include <numbers>

#include "sphere/layouts.h"
#include "sphere/vec3.h"

namespace gdp::sphere {

namespace {

int clamp_int(double v, int lo, int hi) {
  if (!(v >= lo)) return lo;  // also NaN
  if (v > hi) return hi;
  return static_cast<int>(v);
}

// Longitude wraps; a row past a pole is the row on the other side, half a turn away.
class EquirectSource final : public SourceGrid {
 public:
  EquirectSource(int w, int h, bool sky) : w_(w), h_(h), sky_(sky) {
    width = w;
    height = band_rows = h;
  }
  Point2 coords(const Vec3& d) const override { return equirect_from_direction(w_, h_, d, sky_); }
  std::size_t offset(int ix, int iy, int, int) const override {
    if (iy < 0) {
      iy = std::min(h_ - 1, -1 - iy);
      ix += w_ / 2;
    } else if (iy >= h_) {
      iy = std::max(0, 2 * h_ - 1 - iy);
      ix += w_ / 2;
    }
    ix = ((ix % w_) + w_) % w_;
    return static_cast<std::size_t>(iy) * w_ + ix;
  }
  double pixel_angle() const override { return std::numbers::pi / h_; }

 private:
  int w_, h_;
  bool sky_;
};

class PqSource final : public SourceGrid {
 public:
  PqSource(int h, SquareMap map, int depth) : h_(h), map_(map), depth_(depth) {
    width = 4 * h;
    height = band_rows = h;
  }
  Point2 coords(const Vec3& d) const override { return pq_from_direction(map_, h_, d, depth_); }
  std::size_t offset(int ix, int iy, int, int) const override {
    const auto [i, j] = pq_wrap(h_, ix, iy);
    return static_cast<std::size_t>(j) * (4 * h_) + i;
  }
  double pixel_angle() const override { return std::sqrt(std::numbers::pi) / h_; }

 private:
  int h_;
  SquareMap map_;
  int depth_;
};

// Pixels off the home face: the direction of their centre on the home face's extended plane,
// looked up in whichever face it falls.
class CubeSource final : public SourceGrid {
 public:
  explicit CubeSource(int f) : f_(f) {
    width = band_rows = f;
    height = 6 * f;
  }
  Point2 coords(const Vec3& d) const override { return cube_from_direction(f_, d); }
  std::size_t offset(int ix, int iy, int, int hy) const override {
    const int face = std::min(5, std::max(0, hy / f_));
    const int y0 = face * f_;
    if (ix < 0 || ix >= f_ || iy < y0 || iy >= y0 + f_) {
      const Vec3 d = cube_face_direction(f_, face, ix + 0.5, iy - y0 + 0.5);
      const Point2 c = cube_from_direction(f_, d);
      const int other = std::min(5, std::max(0, static_cast<int>(c.y / f_)));
      ix = clamp_int(std::floor(c.x), 0, f_ - 1);
      iy = clamp_int(std::floor(c.y), other * f_, other * f_ + f_ - 1);
    }
    return static_cast<std::size_t>(iy) * f_ + ix;
  }
  double pixel_angle() const override { return std::sqrt(4.0 * std::numbers::pi / 6.0) / f_; }

 private:
  int f_;
};

// Lanczos-3 weights of the six taps around a sample at fraction t past tap 2, normalised so that
// constants stay constant. Tap k sits at x = t - m, m = k - 2, and sin(pi x) = (-1)^m sin(pi t),
// sin(pi x / 3) = sin(pi t / 3) cos(pi m / 3) - cos(pi t / 3) sin(pi m / 3): three sines a call.
void lanczos3(double t, double w[6]) {
  static constexpr double kCos[6] = {-0.5, 0.5, 1.0, 0.5, -0.5, -1.0};  // cos(pi m / 3), m = -2 .. 3
  static constexpr double kSin[6] = {-0.86602540378443865, -0.86602540378443865, 0.0,
                                     0.86602540378443865, 0.86602540378443865, 0.0};
  const double pt = std::numbers::pi * t;
  const double s1 = std::sin(pt), s3 = std::sin(pt / 3.0), c3 = std::cos(pt / 3.0);
  double sum = 0.0;
  for (int k = 0; k < 6; ++k) {
    const double x = t - (k - 2);
    if (std::abs(x) < 1e-9) {
      w[k] = 1.0;
    } else {
      const double px = std::numbers::pi * x;
      const double sin_px = (k % 2 == 0) ? s1 : -s1;
      w[k] = 3.0 * sin_px * (s3 * kCos[k] - c3 * kSin[k]) / (px * px);
    }
    sum += w[k];
  }
  for (int k = 0; k < 6; ++k) w[k] /= sum;
}

}  // namespace

std::unique_ptr<SourceGrid> make_source(const Projection& projection, int width, int height, int toast_depth) {
  switch (projection.layout) {
    case Layout::Equirect: return std::make_unique<EquirectSource>(width, height, projection.sky);
    case Layout::Pq: return std::make_unique<PqSource>(height, projection.map, toast_depth);
    case Layout::Cube: break;
  }
  return std::make_unique<CubeSource>(width);
}

namespace {

// Separable interpolation with kTaps x kTaps taps (weights from `kernel`).
template <int kTaps, class Kernel>
void add_separable(const Image& image, const SourceGrid& grid, const Vec3& d, float weight, float* acc,
                   Kernel kernel) {
  constexpr int kBefore = kTaps / 2 - 1;  // taps before the one at or left of the sample
  const Point2 c = grid.coords(d);
  const double x = c.x - 0.5, y = c.y - 0.5;  // pixel centres at integers
  const double fx = std::floor(x), fy = std::floor(y);
  const int x0 = static_cast<int>(fx) - kBefore, y0 = static_cast<int>(fy) - kBefore;
  double wx[kTaps], wy[kTaps];
  kernel(x - fx, wx);
  kernel(y - fy, wy);
  const int hx = clamp_int(std::floor(c.x), 0, image.width - 1);
  const int hy = clamp_int(std::floor(c.y), 0, image.height - 1);
  std::size_t off[kTaps * kTaps];
  const int band0 = hy / grid.band_rows * grid.band_rows;
  if (x0 >= 0 && x0 + kTaps <= grid.width && y0 >= band0 && y0 + kTaps <= band0 + grid.band_rows) {
    const std::size_t w = static_cast<std::size_t>(grid.width);
    const std::size_t base = static_cast<std::size_t>(y0) * w + static_cast<std::size_t>(x0);
    for (int b = 0; b < kTaps; ++b)
      for (int a = 0; a < kTaps; ++a) off[b * kTaps + a] = base + b * w + a;
  } else {
    for (int b = 0; b < kTaps; ++b)
      for (int a = 0; a < kTaps; ++a) off[b * kTaps + a] = grid.offset(x0 + a, y0 + b, hx, hy);
  }
  for (int ch = 0; ch < image.channels; ++ch) {
    const float* plane = image.plane(ch).data();
    double sum = 0.0;
    for (int b = 0; b < kTaps; ++b) {
      double row = 0.0;
      for (int a = 0; a < kTaps; ++a) row += wx[a] * plane[off[b * kTaps + a]];
      sum += wy[b] * row;
    }
    acc[ch] += weight * static_cast<float>(sum);
  }
}

}  // namespace

void add_interpolated(const Image& image, const SourceGrid& grid, const Vec3& d, float weight, float* acc) {
  add_separable<6>(image, grid, d, weight, acc, lanczos3);
}

void nearest(const Image& image, const SourceGrid& grid, const Vec3& d, float* out) {
  const Point2 c = grid.coords(d);
  const double fx = std::floor(c.x), fy = std::floor(c.y);
  const int hx = clamp_int(fx, 0, image.width - 1), hy = clamp_int(fy, 0, image.height - 1);
  const std::size_t off = grid.offset(static_cast<int>(fx), static_cast<int>(fy), hx, hy);
  for (int ch = 0; ch < image.channels; ++ch) out[ch] = image.plane(ch)[off];
}

}  // namespace gdp::sphere
