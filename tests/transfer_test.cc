// Restriction is the transpose of prolongation, for every size and boundary; Galerkin coarse operators.
#include <gtest/gtest.h>

#include <random>

#include "fem/axis.h"
#include "multigrid/plane_ops.h"
#include "multigrid/window_ops.h"
#include "topology/topology.h"

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
      const bool periodic = b == fem::AxisBoundary::Periodic;
      std::vector<double> f(n), c(m), pc(n, 0.0), rf(m, 0.0), unused(m, 0.0);
      Scratch<double> s;
      for (double& v : f) v = d(rng);
      for (double& v : c) v = d(rng);
      const fem::ProlongationRow one{{0, 0}, {1.0, 0.0}};
      prolong_rows(p, one, c.data(), c.data(), {0, 0}, true, Columns::whole(n, periodic), pc.data(), 0, s);
      restrict_rows(p, one, f.data(), 0, Columns::whole(m, periodic), rf.data(), unused.data(), {0, 0}, s);
      double lhs = 0.0, rhs = 0.0;  // <P c, f> == <c, P^T f>
      for (int i = 0; i < n; ++i) lhs += pc[i] * f[i];
      for (int j = 0; j < m; ++j) rhs += c[j] * rf[j];
      EXPECT_NEAR(lhs, rhs, 1e-12) << "n=" << n << " periodic=" << (b == fem::AxisBoundary::Periodic);
    }
}

// Whole-plane prolongation from level l + 1 to level l, and its restriction.
Plane<double> prolong(const Hierarchy& h, int l, const Plane<double>& coarse) {
  const LevelGeometry& g = h.levels[l + 1];
  Plane<double> fine(h.levels[l].width(), h.levels[l].height());
  Scratch<double> s;
  const Columns cols = Columns::whole(fine.width, g.x.boundary == fem::AxisBoundary::Periodic);
  for (int j = 0; j < fine.height; ++j) {
    const fem::ProlongationRow& py = g.py.rows[j];
    prolong_rows(g.px, py, coarse.row(py.index[0]), coarse.row(py.index[1]), {0, 0}, true, cols, fine.row(j), 0, s);
  }
  return fine;
}

Plane<double> restrict_plane(const Hierarchy& h, int l, const Plane<double>& fine) {
  const LevelGeometry& g = h.levels[l + 1];
  Plane<double> coarse(g.width(), g.height());
  Scratch<double> s;
  const Columns cols = Columns::whole(coarse.width, g.x.boundary == fem::AxisBoundary::Periodic);
  for (int j = 0; j < fine.height; ++j) {
    const fem::ProlongationRow& py = g.py.rows[j];
    restrict_rows(g.px, py, fine.row(j), 0, cols, coarse.row(py.index[0]), coarse.row(py.index[1]), {0, 0}, s);
  }
  return coarse;
}

// Every coarse operator is R A P of the finer one, and R = P^T, on every domain: checked on
// unit vectors (the whole dense product) for small sizes.
class Galerkin : public ::testing::TestWithParam<std::tuple<Domain, int, int>> {};

TEST_P(Galerkin, CoarseOperatorIsRestrictionTimesFineOperatorTimesProlongation) {
  const auto [domain, w, h] = GetParam();
  const double alpha = 0.25;
  const Hierarchy hier = build_hierarchy(*topology::make_topology(domain), w, h, alpha, 2);
  ASSERT_GE(hier.levels.size(), 2u);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  for (std::size_t l = 0; l + 1 < hier.levels.size(); ++l) {
    const LevelOperator<double> fine(hier.levels[l], alpha), coarse(hier.levels[l + 1], alpha);
    Scratch<double> sf, sc;
    for (int k = 0; k < coarse.width * coarse.height; ++k) {
      Plane<double> e(coarse.width, coarse.height), ae(coarse.width, coarse.height);
      e.data[k] = 1.0;
      apply(coarse, e, ae, sc);
      const Plane<double> pe = prolong(hier, static_cast<int>(l), e);
      Plane<double> ape(fine.width, fine.height);
      apply(fine, pe, ape, sf);
      const Plane<double> rape = restrict_plane(hier, static_cast<int>(l), ape);
      for (std::size_t i = 0; i < ae.data.size(); ++i)
        ASSERT_NEAR(ae.data[i], rape.data[i], 1e-9) << "level " << l << " column " << k << " entry " << i;
    }
    // <P c, f> == <c, R f> for random planes.
    Plane<double> c(coarse.width, coarse.height), f(fine.width, fine.height);
    for (double& v : c.data) v = d(rng);
    for (double& v : f.data) v = d(rng);
    const Plane<double> pc = prolong(hier, static_cast<int>(l), c), rf = restrict_plane(hier, static_cast<int>(l), f);
    double lhs = 0.0, rhs = 0.0;
    for (std::size_t i = 0; i < f.data.size(); ++i) lhs += pc.data[i] * f.data[i];
    for (std::size_t i = 0; i < c.data.size(); ++i) rhs += c.data[i] * rf.data[i];
    EXPECT_NEAR(lhs, rhs, 1e-10) << "level " << l;
  }
}

INSTANTIATE_TEST_SUITE_P(Domains, Galerkin,
                         ::testing::Values(std::make_tuple(Domain::Planar, 13, 10), std::make_tuple(Domain::Cylindrical, 16, 9),
                                           std::make_tuple(Domain::Spherical, 32, 8), std::make_tuple(Domain::Spherical, 48, 12)));

}  // namespace
}  // namespace gdp::multigrid
