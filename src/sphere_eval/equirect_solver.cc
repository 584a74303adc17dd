// Multigrid V-cycles and conjugate gradients for the intrinsic equirectangular operator.
#include "sphere_eval/equirect_solver.h"

#include <cmath>
#include <numeric>

#include "gdp/errors.h"

namespace gdp::sphere_eval {

namespace {

double dot(std::span<const double> a, std::span<const double> b) {
  return std::inner_product(a.begin(), a.end(), b.begin(), 0.0);
}

void remove_mean(std::span<double> v) {
  const double m = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  for (double& x : v) x -= m;
}

// Coarse samples feeding fine sample f along one axis, and their weights: the nearer coarse
// centre f/2 with 3/4, the next one on f's side with 1/4.
struct Taps {
  int near, far;
};
Taps taps(int f, int coarse_n, bool periodic) {
  const int near = f / 2;
  int far = f % 2 == 0 ? near - 1 : near + 1;
  if (far < 0) far = periodic ? coarse_n - 1 : 0;            // wrap in longitude, reflect at a pole
  if (far >= coarse_n) far = periodic ? 0 : coarse_n - 1;
  return {near, far};
}

// Visits every (fine index, coarse index, weight) of P.
template <class F>
void for_each_weight(int cw, int ch, F&& f) {
  const int fw = 2 * cw;
  for (int j = 0; j < 2 * ch; ++j) {
    const Taps ty = taps(j, ch, false);
    const int ys[2] = {ty.near, ty.far};
    const double wys[2] = {0.75, 0.25};
    for (int i = 0; i < fw; ++i) {
      const Taps tx = taps(i, cw, true);
      const int xs[2] = {tx.near, tx.far};
      const double wxs[2] = {0.75, 0.25};
      const std::size_t fine = static_cast<std::size_t>(j) * fw + i;
      for (int a = 0; a < 2; ++a)
        for (int c = 0; c < 2; ++c) f(fine, static_cast<std::size_t>(ys[a]) * cw + xs[c], wys[a] * wxs[c]);
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

int solve_cg(const EquirectOperator& op, std::span<const double> b_in, std::span<double> u, double tolerance,
             int max_iterations) {
  const bool singular = op.alpha == 0.0;
  std::vector<double> b(b_in.begin(), b_in.end()), r(op.size()), p(op.size()), q(op.size());
  if (singular) remove_mean(b), remove_mean(u);
  op.apply(u, q);
  for (std::size_t k = 0; k < r.size(); ++k) r[k] = b[k] - q[k];
  if (singular) remove_mean(r);
  const double stop = tolerance * tolerance * dot(b, b);
  double rr = dot(r, r);
  p = r;
  int it = 0;
  for (; it < max_iterations && rr > stop && rr > 0.0; ++it) {
    op.apply(p, q);
    const double a = rr / dot(p, q);
    for (std::size_t k = 0; k < r.size(); ++k) u[k] += a * p[k], r[k] -= a * q[k];
    if (singular) remove_mean(r);
    const double rr_new = dot(r, r);
    for (std::size_t k = 0; k < r.size(); ++k) p[k] = r[k] + (rr_new / rr) * p[k];
    rr = rr_new;
  }
  if (singular) remove_mean(u);
  return it;
}

EquirectSolver::EquirectSolver(int width, int height, double alpha, const EquirectSolverOptions& options)
    : options_(options) {
  if (options.sweeps < 0 || options.coarsest_height < 1 || !(options.coarse_tolerance > 0.0))
    throw UsageError("equirectangular solver: sweeps >= 0, coarsest height >= 1 and a positive tolerance needed");
  ops_.push_back(EquirectOperator::make(width, height, alpha));
  while (ops_.back().height % 2 == 0 && ops_.back().height > options.coarsest_height) {
    const int h = ops_.back().height / 2;
    ops_.push_back(EquirectOperator::make(2 * h, h, alpha));
  }
}

void EquirectSolver::relax(const EquirectOperator& op, std::span<double> u, std::span<const double> b) const {
  const int W = op.width;
  for (int s = 0; s < options_.sweeps; ++s)
    for (int j = 0; j < op.height; ++j) {
      double* r = u.data() + static_cast<std::size_t>(j) * W;
      const double* up = j > 0 ? r - W : r;
      const double* down = j + 1 < op.height ? r + W : r;
      const double* bj = b.data() + static_cast<std::size_t>(j) * W;
      const double inv_d = 1.0 / op.diagonal(j), ex = op.wx[j], n = op.wy[j], so = op.wy[j + 1];
      for (int i = 0; i < W; ++i) {
        const int l = i == 0 ? W - 1 : i - 1, rt = i + 1 == W ? 0 : i + 1;
        r[i] = (bj[i] + ex * (r[l] + r[rt]) + n * up[i] + so * down[i]) * inv_d;
      }
    }
}

void EquirectSolver::cycle(int level, std::span<double> u, std::span<const double> b) const {
  const EquirectOperator& op = ops_[level];
  if (level + 1 == levels()) {
    solve_cg(op, b, u, options_.coarse_tolerance, options_.max_coarse_iterations);
    return;
  }
  relax(op, u, b);
  std::vector<double> r(op.size());
  op.apply(u, r);
  for (std::size_t k = 0; k < r.size(); ++k) r[k] = b[k] - r[k];
  const EquirectOperator& coarse = ops_[level + 1];
  std::vector<double> bc(coarse.size(), 0.0), uc(coarse.size(), 0.0);
  restrict_add(coarse.width, coarse.height, r, bc);
  cycle(level + 1, uc, bc);
  prolong_add(coarse.width, coarse.height, uc, u);
  relax(op, u, b);
}

void EquirectSolver::vcycle(std::span<double> u, std::span<const double> b) const { cycle(0, u, b); }

double EquirectSolver::relative_residual(std::span<const double> u, std::span<const double> b) const {
  std::vector<double> r(ops_[0].size());
  ops_[0].apply(u, r);
  for (std::size_t k = 0; k < r.size(); ++k) r[k] = b[k] - r[k];
  const double bb = dot(b, b);
  return std::sqrt(dot(r, r) / (bb > 0.0 ? bb : 1.0));
}

}  // namespace gdp::sphere_eval
