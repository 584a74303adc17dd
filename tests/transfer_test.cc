// Restriction is the transpose of prolongation, for every size and boundary.
#include <gtest/gtest.h>

#include <random>

#include "fem/axis.h"
#include "multigrid/row_ops.h"

namespace gdp::multigrid {
namespace {

TEST(Transfer, RestrictRowIsTheAdjointOfProlongRow) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  for (fem::AxisBoundary b : {fem::AxisBoundary::Neumann, fem::AxisBoundary::Periodic})
    for (int n : {1, 2, 3, 4, 5, 6, 7, 8, 9, 16, 31, 64, 101}) {
      if (b == fem::AxisBoundary::Periodic && n < 3) continue;
      const fem::Axis axis = fem::make_fine_axis(n, b);
      const fem::Prolongation p = fem::make_prolongation(axis, fem::next_size(axis));
      const int m = p.coarse_n;
      std::vector<double> f(n), c(m), pc(n, 0.0), rf(m, 0.0), unused(m, 0.0), tmp(n);
      for (double& v : f) v = d(rng);
      for (double& v : c) v = d(rng);
      const fem::ProlongationRow one{{0, 0}, {1.0, 0.0}};
      prolong_row(p, one, c.data(), c.data(), pc.data(), tmp.data());
      restrict_row(p, one, f.data(), rf.data(), unused.data(), tmp.data());
      double lhs = 0.0, rhs = 0.0;  // <P c, f> == <c, P^T f>
      for (int i = 0; i < n; ++i) lhs += pc[i] * f[i];
      for (int j = 0; j < m; ++j) rhs += c[j] * rf[j];
      EXPECT_NEAR(lhs, rhs, 1e-12) << "n=" << n << " periodic=" << (b == fem::AxisBoundary::Periodic);
    }
}

}  // namespace
}  // namespace gdp::multigrid
