// The intrinsic equirectangular baseline solver: operator properties, right-hand side identity, convergence.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "gdp/errors.h"
#include "sphere_eval/equirect_operator.h"
#include "sphere_eval/equirect_solver.h"
#include "sphere_eval/row_stencil.h"

namespace gdp::sphere_eval {
namespace {

std::vector<double> random_values(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(0.0, 1.0);
  std::vector<double> v(n);
  for (double& x : v) x = d(rng);
  return v;
}

std::vector<double> applied(const EquirectOperator& op, const std::vector<double>& u) {
  std::vector<double> out(op.size());
  op.apply(u, out);
  return out;
}

// A smooth test image with detail in every latitude band: a few spherical harmonics plus noise.
std::vector<double> test_image(const EquirectOperator& op, unsigned seed) {
  std::vector<double> p = random_values(op.size(), seed);
  for (int j = 0; j < op.height; ++j)
    for (int i = 0; i < op.width; ++i) {
      const double lat = op.row_latitude(j), lon = (i + 0.5) * 2.0 * std::numbers::pi / op.width;
      p[j * op.width + i] = 0.3 * p[j * op.width + i] + std::sin(lat) + std::cos(lat) * std::cos(lon) +
                            0.5 * std::cos(lat) * std::cos(lat) * std::sin(2 * lon);
    }
  return p;
}

double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b, bool remove_mean = false) {
  double mean = 0.0;
  if (remove_mean) {
    for (std::size_t k = 0; k < a.size(); ++k) mean += a[k] - b[k];
    mean /= static_cast<double>(a.size());
  }
  double m = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) m = std::max(m, std::abs(a[k] - mean - b[k]));
  return m;
}

TEST(EquirectOperator, RejectsGridsThatAreNotTwoToOne) {
  EXPECT_THROW(EquirectOperator::make(10, 4), UsageError);
  EXPECT_THROW(EquirectOperator::make(0, 0), UsageError);
  EXPECT_THROW(EquirectOperator::make(8, 4, -1.0), UsageError);
  EXPECT_NO_THROW(EquirectOperator::make(2, 1));
}

TEST(EquirectOperator, CellAreasTileTheSphere) {
  const auto op = EquirectOperator::make(64, 32);
  double total = 0.0;
  for (double a : op.area) total += a * op.width;
  EXPECT_NEAR(total, 4.0 * std::numbers::pi, 1e-12);
  EXPECT_EQ(op.wy.front(), 0.0);  // no flux through the poles
  EXPECT_EQ(op.wy.back(), 0.0);
}

TEST(EquirectOperator, IsSymmetric) {
  for (double alpha : {0.0, 0.7}) {
    const auto op = EquirectOperator::make(12, 6, alpha);
    const std::size_t n = op.size();
    std::vector<std::vector<double>> cols(n);
    for (std::size_t a = 0; a < n; ++a) {
      std::vector<double> e(n, 0.0);
      e[a] = 1.0;
      cols[a] = applied(op, e);
    }
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t b = 0; b < n; ++b) ASSERT_DOUBLE_EQ(cols[a][b], cols[b][a]) << a << " " << b;
    // Diagonally dominant with positive diagonal: positive semidefinite.
    for (std::size_t a = 0; a < n; ++a) {
      double off = 0.0;
      for (std::size_t b = 0; b < n; ++b)
        if (b != a) off += std::abs(cols[a][b]);
      EXPECT_GE(cols[a][a] + 1e-12, off);
    }
  }
}

TEST(EquirectOperator, ConstantsAreTheNullSpace) {
  const auto op = EquirectOperator::make(64, 32);
  for (double v : applied(op, std::vector<double>(op.size(), 3.0))) ASSERT_NEAR(v, 0.0, 1e-12);
  // With screening the constant 1 gives the cell areas.
  const auto screened = EquirectOperator::make(64, 32, 2.0);
  const auto l1 = applied(screened, std::vector<double>(screened.size(), 1.0));
  for (int j = 0; j < 32; ++j) ASSERT_NEAR(l1[j * 64 + 5], 2.0 * screened.area[j], 1e-12);
}

// The spherical harmonics of degree 1 (x, y, z on the sphere) satisfy -Δu = 2u: the discrete
// operator must reproduce it, with an error shrinking as the grid is refined.
TEST(EquirectOperator, ApproximatesLaplaceBeltrami) {
  double previous = 1.0;
  for (int h : {16, 32, 64}) {
    const auto op = EquirectOperator::make(2 * h, h);
    std::vector<double> u(op.size());
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < 2 * h; ++i) {
        const double lat = op.row_latitude(j), lon = (i + 0.5) * std::numbers::pi / h;
        u[j * 2 * h + i] = std::cos(lat) * std::cos(lon) + std::sin(lat);
      }
    const auto lu = applied(op, u);
    double err = 0.0, norm = 0.0;  // area-weighted L2 of L u / area - 2 u
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < 2 * h; ++i) {
        const double e = lu[j * 2 * h + i] / op.area[j] - 2.0 * u[j * 2 * h + i];
        err += op.area[j] * e * e, norm += op.area[j] * 4.0 * u[j * 2 * h + i] * u[j * 2 * h + i];
      }
    const double rel = std::sqrt(err / norm);
    EXPECT_LT(rel, 0.6 * previous) << "H = " << h;
    previous = rel;
  }
  EXPECT_LT(previous, 1e-2);
}

TEST(EquirectOperator, OwnGradientsGiveTheOperatorAppliedToTheImage) {
  const auto op = EquirectOperator::make(64, 32);
  const auto p = random_values(op.size(), 7);
  const auto b = divergence_rhs(op, spherical_gradients(op, p));
  const auto lp = applied(op, p);
  EXPECT_LT(max_abs_diff(b, lp), 1e-11);
  // And a different image's gradients do not.
  const auto q = random_values(op.size(), 8);
  EXPECT_GT(max_abs_diff(divergence_rhs(op, spherical_gradients(op, q)), lp), 0.1);
}

TEST(EquirectOperator, ValueTermIsTheScreenedPart) {
  const auto op = EquirectOperator::make(16, 8, 0.5);
  const auto p = random_values(op.size(), 3);
  auto b = divergence_rhs(op, spherical_gradients(op, p));
  add_value_term(op, p, b);
  EXPECT_LT(max_abs_diff(b, applied(op, p)), 1e-12);
}

TEST(EquirectTransfer, RestrictionIsTheTransposeAndConstantsProlongExactly) {
  const int cw = 8, ch = 4;
  const auto c = random_values(cw * ch, 1), f = random_values(4 * cw * ch, 2);
  std::vector<double> pc(f.size(), 0.0), rf(c.size(), 0.0);
  prolong_add(cw, ch, c, pc);
  restrict_add(cw, ch, f, rf);
  double a = 0.0, b = 0.0;
  for (std::size_t k = 0; k < f.size(); ++k) a += pc[k] * f[k];
  for (std::size_t k = 0; k < c.size(); ++k) b += c[k] * rf[k];
  EXPECT_NEAR(a, b, 1e-12);
  std::vector<double> ones(c.size(), 1.0), fine(f.size(), 0.0);
  prolong_add(cw, ch, ones, fine);
  for (double v : fine) ASSERT_DOUBLE_EQ(v, 1.0);
}

// Applying the stored Galerkin stencils equals restricting L applied to the prolonged vector, and
// the coarse operator keeps the fine one's symmetry and null space.
TEST(EquirectTransfer, GalerkinStencilsAreRestrictedOperatorOfProlongation) {
  for (double alpha : {0.0, 0.3}) {
    const auto fine = RowStencilOperator::from(EquirectOperator::make(32, 16, alpha));
    const auto coarse = RowStencilOperator::galerkin(fine);
    const auto mid = RowStencilOperator::galerkin(coarse);  // a Galerkin product of a Galerkin product
    for (const auto* pair : {&fine, &coarse}) {
      const RowStencilOperator& f = *pair;
      const RowStencilOperator& c = pair == &fine ? coarse : mid;
      const auto v = random_values(c.size(), 4);
      std::vector<double> pv(f.size(), 0.0), lpv(f.size()), expected(c.size(), 0.0), got(c.size());
      prolong_add(c.width(), c.height(), v, pv);
      f.apply(pv, lpv);
      restrict_add(c.width(), c.height(), lpv, expected);
      c.apply(v, got);
      EXPECT_LT(max_abs_diff(got, expected), 1e-12);
      std::vector<double> ones(c.size(), 1.0), l1(c.size());
      c.apply(ones, l1);
      if (alpha == 0.0) {
        for (double x : l1) ASSERT_NEAR(x, 0.0, 1e-12);
      }
      // Symmetry: <x, L y> = <L x, y>.
      const auto x = random_values(c.size(), 5), y = random_values(c.size(), 6);
      std::vector<double> lx(c.size()), ly(c.size());
      c.apply(x, lx);
      c.apply(y, ly);
      double a = 0.0, b = 0.0;
      for (std::size_t k = 0; k < x.size(); ++k) a += x[k] * ly[k], b += lx[k] * y[k];
      EXPECT_NEAR(a, b, 1e-12 * std::abs(a));
    }
  }
  EXPECT_THROW(RowStencilOperator::galerkin(RowStencilOperator::from(EquirectOperator::make(8, 4))), UsageError);
}

TEST(EquirectSolver, CoarsensToTheCoarsestHeight) {
  EquirectSolverOptions o;
  o.coarsest_height = 8;
  const EquirectSolver s(128, 64, 0.0, o);
  ASSERT_EQ(s.levels(), 4);
  EXPECT_EQ(s.level(3).width(), 16);
  EXPECT_EQ(s.level(3).height(), 8);
}

TEST(EquirectSolver, VCyclesReduceTheResidual) {
  EquirectSolverOptions o;
  o.coarsest_height = 4;
  const EquirectSolver s(128, 64, 0.0, o);
  const auto p = test_image(s.fine(), 11);
  const auto b = divergence_rhs(s.fine(), spherical_gradients(s.fine(), p));
  std::vector<double> u(p.size(), 0.0);
  double previous = s.relative_residual(u, b);
  EXPECT_DOUBLE_EQ(previous, 1.0);
  for (int n = 0; n < 5; ++n) {
    s.vcycle(u, b);
    const double r = s.relative_residual(u, b);
    EXPECT_LT(r, 0.9 * previous) << "cycle " << n + 1;
    previous = r;
  }
}

TEST(EquirectSolver, ManyVCyclesReachTheImage) {
  EquirectSolverOptions o;
  o.coarsest_height = 4;
  const EquirectSolver s(64, 32, 0.0, o);
  const auto p = test_image(s.fine(), 5);
  const auto b = divergence_rhs(s.fine(), spherical_gradients(s.fine(), p));
  std::vector<double> u(p.size(), 0.0);
  int n = 0;
  while (s.relative_residual(u, b) > 1e-13 && n < 500) s.vcycle(u, b), ++n;
  EXPECT_LT(max_abs_diff(u, p, true), 1e-10) << n << " V-cycles";
}

TEST(EquirectSolver, ConjugateGradientsReachTheImage) {
  const auto op = EquirectOperator::make(128, 64);
  const auto p = test_image(op, 9);
  const auto b = divergence_rhs(op, spherical_gradients(op, p));
  std::vector<double> u(p.size(), 0.0);
  solve_cg(RowStencilOperator::from(op), b, u, 1e-14, 100000);
  EXPECT_LT(max_abs_diff(u, p, true), 1e-10);
}

TEST(EquirectSolver, ScreenedSystemHasAUniqueSolution) {
  EquirectSolverOptions o;
  o.coarsest_height = 4;
  const EquirectSolver s(64, 32, 0.5, o);
  const auto p = test_image(s.fine(), 13);
  auto b = divergence_rhs(s.fine(), spherical_gradients(s.fine(), p));
  add_value_term(s.fine(), p, b);
  std::vector<double> u(p.size(), 0.0);
  for (int n = 0; n < 200 && s.relative_residual(u, b) > 1e-13; ++n) s.vcycle(u, b);
  EXPECT_LT(max_abs_diff(u, p), 1e-10);  // no constant to remove
}

}  // namespace
}  // namespace gdp::sphere_eval
