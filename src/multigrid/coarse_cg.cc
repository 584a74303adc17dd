// Conjugate gradients on the coarsest level, with the constant null space removed when singular.
#include "multigrid/coarse_cg.h"

#include <cmath>
#include <numeric>
#include <vector>

#include "multigrid/plane_ops.h"

namespace gdp::multigrid {
namespace {

void remove_mean(std::span<double> v) {
  if (v.empty()) return;
  const double mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  for (double& x : v) x -= mean;
}

double dot(std::span<const double> a, std::span<const double> b) {
  return std::inner_product(a.begin(), a.end(), b.begin(), 0.0);
}

}  // namespace

int conjugate_gradients(const ApplyOperator& apply, bool singular, std::span<const double> b_in, std::span<double> u,
                        double tolerance, int max_iterations) {
  const std::size_t n = u.size();
  std::vector<double> b(b_in.begin(), b_in.end()), r(n), p(n), ap(n);
  if (singular) {
    remove_mean(b);
    remove_mean(u);
  }
  apply(u, ap);
  for (std::size_t k = 0; k < n; ++k) r[k] = b[k] - ap[k];
  if (singular) remove_mean(r);
  const double bnorm = std::sqrt(dot(b, b));
  if (bnorm == 0.0) {
    std::fill(u.begin(), u.end(), 0.0);
    return 0;
  }
  p = r;
  double rr = dot(r, r);
  int it = 0;
  for (; it < max_iterations && std::sqrt(rr) > tolerance * bnorm; ++it) {
    apply(p, ap);
    const double pap = dot(p, ap);
    if (pap <= 0.0) break;
    const double a = rr / pap;
    for (std::size_t k = 0; k < n; ++k) {
      u[k] += a * p[k];
      r[k] -= a * ap[k];
    }
    if (singular) remove_mean(r);
    const double rr_new = dot(r, r);
    const double beta = rr_new / rr;
    rr = rr_new;
    for (std::size_t k = 0; k < n; ++k) p[k] = r[k] + beta * p[k];
  }
  if (singular) remove_mean(u);
  return it;
}

int solve_cg(const LevelOperator<double>& op, bool singular, const Plane<double>& b, Plane<double>& u,
             double tolerance, int max_iterations) {
  RowScratch<double> s(op.width);
  const auto apply = [&](std::span<const double> in, std::span<double> out) {
    for (int j = 0; j < op.height; ++j)
      apply_row(op, j, window(op, in.data(), j), out.data() + static_cast<std::size_t>(j) * op.width, s);
  };
  return conjugate_gradients(apply, singular, b.data, u.data, tolerance, max_iterations);
}

}  // namespace gdp::multigrid
