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
                        double tolerance, int max_iterations, std::span<const double> inverse_diagonal) {
  const std::size_t n = u.size();
  std::vector<double> b(b_in.begin(), b_in.end()), r(n), p(n), ap(n), z(n);
  // z = M^-1 r (the identity without a preconditioner).
  const auto precondition = [&] {
    for (std::size_t k = 0; k < n; ++k) z[k] = inverse_diagonal.empty() ? r[k] : inverse_diagonal[k] * r[k];
  };
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
  precondition();
  p = z;
  double rz = dot(r, z);
  int it = 0;
  for (; it < max_iterations && std::sqrt(dot(r, r)) > tolerance * bnorm; ++it) {
    apply(p, ap);
    const double pap = dot(p, ap);
    if (pap <= 0.0) break;
    const double a = rz / pap;
    for (std::size_t k = 0; k < n; ++k) {
      u[k] += a * p[k];
      r[k] -= a * ap[k];
    }
    if (singular) remove_mean(r);
    precondition();
    const double rz_new = dot(r, z);
    const double beta = rz_new / rz;
    rz = rz_new;
    for (std::size_t k = 0; k < n; ++k) p[k] = z[k] + beta * p[k];
  }
  if (singular) remove_mean(u);
  return it;
}

std::vector<double> inverse_diagonal(const LevelOperator<double>& op, const Plane<double>& diag) {
  // A applied to unit vectors, one pixel at a time (the coarsest level is small).
  Scratch<double> s;
  Plane<double> e(op.width, op.height), ae(op.width, op.height);
  std::vector<double> inverse(e.data.size());
  for (std::size_t k = 0; k < e.data.size(); ++k) {
    e.data[k] = 1.0;
    const int j = static_cast<int>(k / op.width);
    apply(op, j, window(op, e, j), whole_row(op), ae.row(j), s, diag.row(j));
    inverse[k] = 1.0 / ae.data[k];
    e.data[k] = 0.0;
  }
  return inverse;
}

int solve_cg(const LevelOperator<double>& op, bool singular, const Plane<double>& b, Plane<double>& u,
             double tolerance, int max_iterations, const Plane<double>* diag, std::span<const double> inverse) {
  Scratch<double> s;
  const auto product = [&](std::span<const double> in, std::span<double> out) {
    for (int j = 0; j < op.height; ++j)
      apply(op, j, window(op, in.data(), j), whole_row(op), out.data() + static_cast<std::size_t>(j) * op.width, s,
            diag_row(diag, j));
  };
  std::vector<double> computed;
  if (diag && inverse.empty()) inverse = computed = inverse_diagonal(op, *diag);
  return conjugate_gradients(product, singular, b.data, u.data, tolerance, max_iterations,
                             diag ? inverse : std::span<const double>{});
}

}  // namespace gdp::multigrid
