// Conjugate gradients on the coarsest level, with the constant null space removed when singular.
#include "multigrid/coarse_cg.h"

#include <cmath>
#include <numeric>

#include "multigrid/plane_ops.h"

namespace gdp::multigrid {
namespace {

void remove_mean(std::vector<double>& v) {
  if (v.empty()) return;
  const double mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  for (double& x : v) x -= mean;
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  return std::inner_product(a.begin(), a.end(), b.begin(), 0.0);
}

}  // namespace

int solve_cg(const LevelOperator<double>& op, bool singular, const Plane<double>& b, Plane<double>& u,
             double tolerance, int max_iterations) {
  RowScratch<double> s(op.width);
  Plane<double> rhs = b, r(op.width, op.height), p(op.width, op.height), ap(op.width, op.height);
  if (singular) {
    remove_mean(rhs.data);
    remove_mean(u.data);
  }
  residual(op, u, rhs, r, s);
  if (singular) remove_mean(r.data);
  const double bnorm = std::sqrt(dot(rhs.data, rhs.data));
  if (bnorm == 0.0) {
    std::fill(u.data.begin(), u.data.end(), 0.0);
    return 0;
  }
  p.data = r.data;
  double rr = dot(r.data, r.data);
  int it = 0;
  for (; it < max_iterations && std::sqrt(rr) > tolerance * bnorm; ++it) {
    apply(op, p, ap, s);
    const double pap = dot(p.data, ap.data);
    if (pap <= 0.0) break;
    const double a = rr / pap;
    for (std::size_t k = 0; k < r.data.size(); ++k) {
      u.data[k] += a * p.data[k];
      r.data[k] -= a * ap.data[k];
    }
    if (singular) remove_mean(r.data);
    const double rr_new = dot(r.data, r.data);
    const double beta = rr_new / rr;
    rr = rr_new;
    for (std::size_t k = 0; k < r.data.size(); ++k) p.data[k] = r.data[k] + beta * p.data[k];
  }
  if (singular) remove_mean(u.data);
  return it;
}

}  // namespace gdp::multigrid
