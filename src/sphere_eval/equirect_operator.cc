// The intrinsic Laplace-Beltrami operator on an equirectangular grid: weights, application, right-hand sides.
#include "sphere_eval/equirect_operator.h"

#include <cmath>
#include <numbers>
#include <string>

#include "gdp/errors.h"

namespace gdp::sphere_eval {

namespace {
constexpr double kPi = std::numbers::pi;
}

EquirectOperator EquirectOperator::make(int width, int height, double alpha) {
  if (height < 1 || width != 2 * height)
    throw UsageError("equirectangular grid must be W x H with W = 2H >= 2, got " + std::to_string(width) + "x" +
                     std::to_string(height));
  if (!(alpha >= 0.0)) throw UsageError("screening weight alpha must be >= 0");
  EquirectOperator op;
  op.width = width;
  op.height = height;
  op.alpha = alpha;
  const double dlon = 2.0 * kPi / width, dlat = kPi / height;
  op.wx.resize(height);
  op.area.resize(height);
  op.wy.assign(height + 1, 0.0);  // the pole edges have zero length
  for (int j = 0; j < height; ++j) {
    const double c = std::cos(op.row_latitude(j));
    op.wx[j] = dlat / (c * dlon);
    // ∫ cos φ dφ over the row: sin(top) - sin(bottom) = 2 cos φ_j sin(Δθ/2).
    op.area[j] = dlon * 2.0 * c * std::sin(0.5 * dlat);
  }
  for (int j = 1; j < height; ++j) op.wy[j] = std::cos(kPi / 2 - j * dlat) * dlon / dlat;
  return op;
}

double EquirectOperator::row_latitude(int j) const { return kPi / 2 - (j + 0.5) * kPi / height; }
double EquirectOperator::dx(int j) const { return std::cos(row_latitude(j)) * 2.0 * kPi / width; }
double EquirectOperator::dy() const { return kPi / height; }

void EquirectOperator::apply(std::span<const double> u, std::span<double> out) const {
  const int W = width;
  for (int j = 0; j < height; ++j) {
    const double* r = u.data() + static_cast<std::size_t>(j) * W;
    const double* up = j > 0 ? r - W : r;               // weight 0 at the poles
    const double* down = j + 1 < height ? r + W : r;
    double* o = out.data() + static_cast<std::size_t>(j) * W;
    const double d = diagonal(j), ex = wx[j], n = wy[j], s = wy[j + 1];
    for (int i = 0; i < W; ++i) {
      const int l = i == 0 ? W - 1 : i - 1, rr = i + 1 == W ? 0 : i + 1;
      o[i] = d * r[i] - ex * (r[l] + r[rr]) - n * up[i] - s * down[i];
    }
  }
}

EdgeGradients spherical_gradients(const EquirectOperator& op, std::span<const double> p) {
  const int W = op.width, H = op.height;
  EdgeGradients g;
  g.gx.resize(op.size());
  g.gy.assign(op.size(), 0.0);
  for (int j = 0; j < H; ++j) {
    const double* r = p.data() + static_cast<std::size_t>(j) * W;
    double* gx = g.gx.data() + static_cast<std::size_t>(j) * W;
    const double inv_dx = 1.0 / op.dx(j);
    for (int i = 0; i < W; ++i) gx[i] = (r[i + 1 == W ? 0 : i + 1] - r[i]) * inv_dx;
    if (j + 1 < H) {
      double* gy = g.gy.data() + static_cast<std::size_t>(j) * W;
      for (int i = 0; i < W; ++i) gy[i] = (r[i + W] - r[i]) / op.dy();
    }
  }
  return g;
}

std::vector<double> divergence_rhs(const EquirectOperator& op, const EdgeGradients& g) {
  const int W = op.width, H = op.height;
  const double dlat = op.dy();
  std::vector<double> b(op.size());
  for (int j = 0; j < H; ++j) {
    // Edge lengths: meridian segments Δθ; parallels cos φ Δλ (= wy Δθ) at the row's top and bottom.
    const double len_top = op.wy[j] * dlat, len_bottom = op.wy[j + 1] * dlat;
    const double* gx = g.gx.data() + static_cast<std::size_t>(j) * W;
    double* o = b.data() + static_cast<std::size_t>(j) * W;
    for (int i = 0; i < W; ++i) {
      const int l = i == 0 ? W - 1 : i - 1;
      double flux_out = dlat * (gx[i] - gx[l]);
      if (j + 1 < H) flux_out += len_bottom * g.gy[static_cast<std::size_t>(j) * W + i];
      if (j > 0) flux_out -= len_top * g.gy[static_cast<std::size_t>(j - 1) * W + i];
      o[i] = -flux_out;
    }
  }
  return b;
}

void add_value_term(const EquirectOperator& op, std::span<const double> w, std::span<double> b) {
  for (int j = 0; j < op.height; ++j)
    for (int i = 0; i < op.width; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * op.width + i;
      b[k] += op.alpha * op.area[j] * w[k];
    }
}

}  // namespace gdp::sphere_eval
