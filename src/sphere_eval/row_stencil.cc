// Per-row stencil operators: application, Gauss-Seidel, transfers and Galerkin coarsening.
#include "sphere_eval/row_stencil.h"

#include <string>

#include "gdp/errors.h"

namespace gdp::sphere_eval {

namespace {

// The coarse samples feeding fine sample f along one axis: the nearer coarse centre f/2 with
// weight 3/4, the next one on f's side with 1/4 (wrapped in longitude, reflected at a pole).
struct Taps1d {
  int near, far;
};
Taps1d taps_1d(int f, int coarse_n, bool periodic) {
  const int near = f / 2;
  int far = f % 2 == 0 ? near - 1 : near + 1;
  if (far < 0) far = periodic ? coarse_n - 1 : 0;
  if (far >= coarse_n) far = periodic ? 0 : coarse_n - 1;
  return {near, far};
}

// Calls f(fine index, coarse index, weight) for every entry of P.
template <class F>
void for_each_weight(int cw, int ch, F&& f) {
  constexpr double w[2] = {0.75, 0.25};
  const int fw = 2 * cw;
  for (int j = 0; j < 2 * ch; ++j) {
    const Taps1d ty = taps_1d(j, ch, false);
    const int ys[2] = {ty.near, ty.far};
    for (int i = 0; i < fw; ++i) {
      const Taps1d tx = taps_1d(i, cw, true);
      const int xs[2] = {tx.near, tx.far};
      const std::size_t fine = static_cast<std::size_t>(j) * fw + i;
      for (int a = 0; a < 2; ++a)
        for (int c = 0; c < 2; ++c) f(fine, static_cast<std::size_t>(ys[a]) * cw + xs[c], w[a] * w[c]);
    }
  }
}

}  // namespace

void prolong_add(int cw, int ch, std::span<const double> coarse, std::span<double> fine) {
  for_each_weight(cw, ch, [&](std::size_t f, std::size_t c, double w) { fine[f] += w * coarse[c]; });
}

void restrict_add(int cw, int ch, std::span<const double> fine, std::span<double> coarse) {
  for_each_weight(cw, ch, [&](std::size_t f, std::size_t c, double w) { coarse[c] += w * fine[f]; });
}

RowStencilOperator RowStencilOperator::from(const EquirectOperator& op) {
  RowStencilOperator s;
  s.width_ = op.width;
  s.height_ = op.height;
  s.singular_ = op.alpha == 0.0;
  for (int j = 0; j < op.height; ++j) {
    s.diagonal_.push_back(op.diagonal(j));
    std::vector<Tap> t = {{-1, 0, -op.wx[j]}, {1, 0, -op.wx[j]}};
    if (j > 0) t.push_back({0, -1, -op.wy[j]});
    if (j + 1 < op.height) t.push_back({0, 1, -op.wy[j + 1]});
    s.taps_.push_back(std::move(t));
  }
  return s;
}

// Probing: one coarse unit vector per row, all in column 0, in rows five apart. Coarse stencils
// reach two rows each way, so L_c e = Pᵀ L P e holds each probed row's column of L_c untouched by
// the others; by symmetry that column is the row's stencil.
RowStencilOperator RowStencilOperator::galerkin(const RowStencilOperator& fine) {
  const int cw = fine.width_ / 2, ch = fine.height_ / 2;
  if (fine.width_ % 2 != 0 || fine.height_ % 2 != 0 || cw < 5)
    throw UsageError("cannot coarsen a " + std::to_string(fine.width_) + "x" + std::to_string(fine.height_) +
                     " equirectangular level");
  RowStencilOperator s;
  s.width_ = cw;
  s.height_ = ch;
  s.singular_ = fine.singular_;
  s.diagonal_.resize(ch);
  s.taps_.resize(ch);
  std::vector<double> e(static_cast<std::size_t>(cw) * ch), pe(fine.size()), lpe(fine.size()), col(e.size());
  for (int r = 0; r < 5; ++r) {
    std::fill(e.begin(), e.end(), 0.0);
    std::fill(pe.begin(), pe.end(), 0.0);
    std::fill(col.begin(), col.end(), 0.0);
    for (int J = r; J < ch; J += 5) e[static_cast<std::size_t>(J) * cw] = 1.0;
    prolong_add(cw, ch, e, pe);
    fine.apply(pe, lpe);
    restrict_add(cw, ch, lpe, col);
    for (int J = r; J < ch; J += 5)
      for (int dy = -2; dy <= 2; ++dy) {
        if (J + dy < 0 || J + dy >= ch) continue;
        for (int dx = -2; dx <= 2; ++dx) {
          const double c = col[static_cast<std::size_t>(J + dy) * cw + (dx + cw) % cw];
          if (dx == 0 && dy == 0) s.diagonal_[J] = c;
          else if (c != 0.0) s.taps_[J].push_back({dx, dy, c});
        }
      }
  }
  return s;
}

void RowStencilOperator::apply(std::span<const double> u, std::span<double> out) const {
  const int W = width_;
  for (int j = 0; j < height_; ++j) {
    const double* r = u.data() + static_cast<std::size_t>(j) * W;
    double* o = out.data() + static_cast<std::size_t>(j) * W;
    for (int i = 0; i < W; ++i) o[i] = diagonal_[j] * r[i];
    for (const Tap& t : taps_[j]) {
      const double* n = r + static_cast<std::ptrdiff_t>(t.dy) * W;
      for (int i = 0; i < W; ++i) o[i] += t.c * n[(i + t.dx + W) % W];
    }
  }
}

void RowStencilOperator::relax(std::span<double> u, std::span<const double> b, int sweeps) const {
  const int W = width_;
  for (int s = 0; s < sweeps; ++s)
    for (int j = 0; j < height_; ++j) {
      double* r = u.data() + static_cast<std::size_t>(j) * W;
      const double* bj = b.data() + static_cast<std::size_t>(j) * W;
      const double inv_d = 1.0 / diagonal_[j];
      for (int i = 0; i < W; ++i) {
        double v = bj[i];
        for (const Tap& t : taps_[j]) v -= t.c * r[static_cast<std::ptrdiff_t>(t.dy) * W + (i + t.dx + W) % W];
        r[i] = v * inv_d;
      }
    }
}

}  // namespace gdp::sphere_eval
