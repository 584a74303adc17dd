// Resampling targets: equirectangular and cube rows by formula, PQ rows from the fast grid.
#include "sphere/target.h"

#include <cmath>
#include <numbers>

#include "sphere/layouts.h"
#include "sphere/vec3.h"

namespace gdp::sphere {

namespace {

// Differences over half a pixel either side of each centre, from a formula f(x, y).
template <class F>
void fill_by_formula(int width, int y_index, F&& f, TargetRow& r) {
  r.d.resize(width);
  r.du.resize(width);
  r.dv.resize(width);
  const double y = y_index + 0.5;
  for (int i = 0; i < width; ++i) {
    const double x = i + 0.5;
    r.d[i] = f(x, y);
    r.du[i] = f(x + 0.5, y) - f(x - 0.5, y);
    r.dv[i] = f(x, y + 0.5) - f(x, y - 0.5);
  }
}

class EquirectTarget final : public TargetCursor {
 public:
  EquirectTarget(int w, int h, bool sky) : w_(w), h_(h), sky_(sky) {}
  // Derivatives by formula: d/dx = (2 pi / W) east (negated for sky), d/dy = -(pi / H) north.
  const TargetRow& row(int j) override {
    r_.d.resize(w_);
    r_.du.resize(w_);
    r_.dv.resize(w_);
    const double kx = 2.0 * std::numbers::pi / w_ * (sky_ ? -1.0 : 1.0), ky = std::numbers::pi / h_;
    for (int i = 0; i < w_; ++i) {
      const Vec3 d = equirect_direction(w_, h_, i + 0.5, j + 0.5, sky_);
      r_.d[i] = d;
      r_.du[i] = {-kx * d.y, kx * d.x, 0.0};
      const double rho = std::hypot(d.x, d.y);
      const double cx = rho > 0 ? d.x / rho : 1.0, cy = rho > 0 ? d.y / rho : 0.0;
      r_.dv[i] = {ky * d.z * cx, ky * d.z * cy, -ky * rho};
    }
    return r_;
  }

 private:
  int w_, h_;
  bool sky_;
  TargetRow r_;
};

class CubeTarget final : public TargetCursor {
 public:
  explicit CubeTarget(int f) : f_(f) {}
  const TargetRow& row(int j) override {
    const int face = j / f_, y0 = face * f_;
    fill_by_formula(f_, j - y0, [&](double x, double y) { return cube_face_direction(f_, face, x, y); }, r_);
    return r_;
  }

 private:
  int f_;
  TargetRow r_;
};

// Central differences between neighbouring pixels; rows -1 and H are the wrapped ones.
class PqTarget final : public TargetCursor {
 public:
  PqTarget(int h, SquareMap map) : h_(h), w_(4 * h), map_(map) {}
  const TargetRow& row(int j) override {
    const std::vector<Vec3>& above = dirs(j - 1, j);
    const std::vector<Vec3>& here = dirs(j, j);
    const std::vector<Vec3>& below = dirs(j + 1, j);
    r_.d = here;
    r_.du.resize(w_);
    r_.dv.resize(w_);
    for (int i = 0; i < w_; ++i) {
      r_.du[i] = 0.5 * (here[(i + 1) % w_] - here[(i + w_ - 1) % w_]);
      r_.dv[i] = 0.5 * (below[i] - above[i]);
    }
    return r_;
  }

 private:
  // Keeps three rows, so a cursor walking down computes each row once; a new row replaces one
  // that row `centre` does not need.
  const std::vector<Vec3>& dirs(int j, int centre) {
    for (auto& c : cache_)
      if (c.first == j) return c.second;
    auto* slot = &cache_[0];
    for (auto& c : cache_)
      if (c.first < centre - 1 || c.first > centre + 1) slot = &c;
    auto& s = *slot;
    s.first = j;
    s.second.resize(w_);
    pq_row(map_, h_, j, s.second);
    return s.second;
  }
  int h_, w_;
  SquareMap map_;
  std::pair<int, std::vector<Vec3>> cache_[3] = {{-9, {}}, {-9, {}}, {-9, {}}};
  TargetRow r_;
};

}  // namespace

std::unique_ptr<TargetCursor> make_target(const Projection& projection, int width, int height) {
  switch (projection.layout) {
    case Layout::Equirect: return std::make_unique<EquirectTarget>(width, height, projection.sky);
    case Layout::Pq: return std::make_unique<PqTarget>(height, projection.map);
    case Layout::Cube: break;
  }
  return std::make_unique<CubeTarget>(width);
}

}  // namespace gdp::sphere
