// Resampling sources (equirectangular, PQ, cube strip) and the bicubic and nearest samplers.
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
  EquirectSource(int w, int h, bool sky) : w_(w), h_(h), sky_(sky) {}
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
  PqSource(int h, SquareMap map, int depth) : h_(h), map_(map), depth_(depth) {}
  Point2 coords(const Vec3& d) const override { return pq_from_direction(map_, h_, d, depth_); }
  std::size_t offset(int ix, int iy, int, int) const override {
    auto [i, j] = pq_wrap(h_, ix, iy);
    j = std::min(h_ - 1, std::max(0, j));  // stencils reach at most two rows out
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
  explicit CubeSource(int f) : f_(f) {}
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

void catmull_rom(double t, double w[4]) {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = 0.5 * (-t3 + 2.0 * t2 - t);
  w[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
  w[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
  w[3] = 0.5 * (t3 - t2);
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

void add_bicubic(const Image& image, const SourceGrid& grid, const Vec3& d, float weight, float* acc) {
  const Point2 c = grid.coords(d);
  const double x = c.x - 0.5, y = c.y - 0.5;  // pixel centres at integers
  const double fx = std::floor(x), fy = std::floor(y);
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  double wx[4], wy[4];
  catmull_rom(x - fx, wx);
  catmull_rom(y - fy, wy);
  const int hx = clamp_int(std::floor(c.x), 0, image.width - 1);
  const int hy = clamp_int(std::floor(c.y), 0, image.height - 1);
  std::size_t off[16];
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a) off[b * 4 + a] = grid.offset(x0 - 1 + a, y0 - 1 + b, hx, hy);
  for (int ch = 0; ch < image.channels; ++ch) {
    const float* plane = image.plane(ch).data();
    double sum = 0.0;
    for (int b = 0; b < 4; ++b) {
      double row = 0.0;
      for (int a = 0; a < 4; ++a) row += wx[a] * plane[off[b * 4 + a]];
      sum += wy[b] * row;
    }
    acc[ch] += weight * static_cast<float>(sum);
  }
}

void nearest(const Image& image, const SourceGrid& grid, const Vec3& d, float* out) {
  const Point2 c = grid.coords(d);
  const double fx = std::floor(c.x), fy = std::floor(c.y);
  const int hx = clamp_int(fx, 0, image.width - 1), hy = clamp_int(fy, 0, image.height - 1);
  const std::size_t off = grid.offset(static_cast<int>(fx), static_cast<int>(fy), hx, hy);
  for (int ch = 0; ch < image.channels; ++ch) out[ch] = image.plane(ch)[off];
}

}  // namespace gdp::sphere
