// Topology conformance of the level operator and the exact-gradient right-hand-side identity.
#include <gtest/gtest.h>

#include <map>

#include "fem/rhs.h"
#include "fem/stencils.h"
#include "multigrid/hierarchy.h"
#include "multigrid/plane_ops.h"
#include "test_util.h"
#include "topology/topology.h"

namespace gdp {
namespace {

using multigrid::LevelOperator;
using multigrid::Plane;

// Dense operator of the finest level, from the interior stencils and the topology's index map
// alone: A[(i,j)][map(i+dx, j+dy)] += S(dx)M(dy) + M(dx)S(dy) + alpha M(dx)M(dy).
std::map<std::pair<int, int>, double> reference_operator(const topology::Topology& t, int w, int h,
                                                         double alpha) {
  std::map<std::pair<int, int>, double> a;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const auto [ni, nj] = t.map(i + dx, j + dy, w, h);
          const double mx = fem::kMass[dx + 2], sx = fem::kStiffness[dx + 2];
          const double my = fem::kMass[dy + 2], sy = fem::kStiffness[dy + 2];
          a[{j * w + i, nj * w + ni}] += sx * my + mx * sy + alpha * mx * my;
        }
  return a;
}

// Column k of the level operator, by applying it to the unit vector e_k.
std::vector<double> operator_column(const LevelOperator<double>& op, int k) {
  Plane<double> e(op.width, op.height), out(op.width, op.height);
  e.data[k] = 1.0;
  multigrid::Scratch<double> s;
  multigrid::apply(op, e, out, s);
  for (double& v : out.data) v /= LevelOperator<double>::kScale;  // stored operator is scaled
  return {out.data.begin(), out.data.end()};
}

class Conformance : public ::testing::TestWithParam<std::tuple<Domain, int, int>> {};

TEST_P(Conformance, LevelOperatorEqualsStencilsThroughIndexMapAndIsSymmetricWithConstantNullSpace) {
  const auto [domain, w, h] = GetParam();
  const auto topo = topology::make_topology(domain);
  const double alpha = 0.0;
  const multigrid::Hierarchy hier = multigrid::build_hierarchy(*topo, w, h, alpha, 4);
  const LevelOperator<double> op(hier.levels[0], alpha);
  const auto ref = reference_operator(*topo, w, h, alpha);
  const int n = w * h;
  std::vector<std::vector<double>> cols(n);
  for (int k = 0; k < n; ++k) cols[k] = operator_column(op, k);
  for (int r = 0; r < n; ++r) {
    double row_sum = 0.0;
    for (int k = 0; k < n; ++k) {
      const auto it = ref.find({r, k});
      const double expected = it == ref.end() ? 0.0 : it->second;
      ASSERT_NEAR(cols[k][r], expected, 1e-12) << "row " << r << " column " << k;
      ASSERT_NEAR(cols[k][r], cols[r][k], 1e-12) << "symmetry " << r << "," << k;
      row_sum += cols[k][r];
    }
    EXPECT_NEAR(row_sum, 0.0, 1e-12) << "constants must be in the null space";
  }
  // Every coarser level too: symmetric, constants in the null space.
  for (std::size_t l = 1; l < hier.levels.size(); ++l) {
    const LevelOperator<double> c(hier.levels[l], alpha);
    const int m = c.width * c.height;
    std::vector<std::vector<double>> cc(m);
    for (int k = 0; k < m; ++k) cc[k] = operator_column(c, k);
    for (int r = 0; r < m; ++r) {
      double row_sum = 0.0;
      for (int k = 0; k < m; ++k) {
        ASSERT_NEAR(cc[k][r], cc[r][k], 1e-12) << "level " << l;
        row_sum += cc[k][r];
      }
      EXPECT_NEAR(row_sum, 0.0, 1e-12) << "level " << l;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Planar, Conformance,
                         ::testing::Combine(::testing::Values(Domain::Planar), ::testing::Values(1, 2, 5, 9),
                                            ::testing::Values(1, 3, 8, 11)));
INSTANTIATE_TEST_SUITE_P(Cylindrical, Conformance,
                         ::testing::Combine(::testing::Values(Domain::Cylindrical),
                                            ::testing::Values(3, 5, 8, 13), ::testing::Values(1, 4, 7)));
INSTANTIATE_TEST_SUITE_P(Spherical, Conformance,
                         ::testing::Values(std::make_tuple(Domain::Spherical, 8, 2), std::make_tuple(Domain::Spherical, 16, 4),
                                           std::make_tuple(Domain::Spherical, 24, 6),
                                           std::make_tuple(Domain::Spherical, 32, 8)));

// The assembled right-hand side of an exact gradient field equals the operator applied to the
// image (NUMERICS.md §2), with and without the screening term.
class RhsIdentity : public ::testing::TestWithParam<std::tuple<Domain, int, int, double>> {};

TEST_P(RhsIdentity, ExactGradientsGiveOperatorTimesImage) {
  const auto [domain, w, given_h, alpha] = GetParam();
  const int h = domain == Domain::Spherical ? w / 4 : given_h;  // PQ: W = 4H
  const auto topo = topology::make_topology(domain);
  const multigrid::Hierarchy hier = multigrid::build_hierarchy(*topo, w, h, alpha, 1 << 20);
  const Image img = test::random_image(w, h, 2, 7);
  test::ExactGradients src(img, domain, alpha);
  const fem::Axis& x = hier.levels[0].x;
  fem::RhsAssembler asm_(x, hier.levels[0].y, alpha, 2);
  std::vector<Plane<double>> b(2, Plane<double>(w, h));
  const auto sink = [&](int r, int c, std::span<const double> v) {
    std::copy(v.begin(), v.end(), b[c].row(r));
  };
  GuidanceRow row;
  row.x_edges = x.edges();
  row.gx.resize(2 * x.edges());
  row.gy.resize(2 * w);
  row.value.resize(2 * w);
  row.spherical = domain == Domain::Spherical;
  if (row.spherical) row.gy_above.resize(2 * w);
  for (int j = 0; j < h; ++j) {
    src.read_row(j, row);
    asm_.push(j, row, sink);
  }
  asm_.finish(sink);
  const LevelOperator<double> op(hier.levels[0], alpha);
  multigrid::Scratch<double> s;
  for (int c = 0; c < 2; ++c) {
    Plane<double> p(w, h), ap(w, h);
    std::copy(img.plane(c).begin(), img.plane(c).end(), p.data.begin());
    multigrid::apply(op, p, ap, s);
    for (int k = 0; k < w * h; ++k)
      ASSERT_NEAR(b[c].data[k], ap.data[k] / LevelOperator<double>::kScale, 1e-12) << "sample " << k;
  }
}

// A window of columns (a rank of a distributed solve): with the guidance known two columns beyond
// it, the assembled rows equal the whole rows' there, bit for bit, and are 0 elsewhere (the
// guidance beyond is poisoned: reading it shows).
TEST(RhsWindow, WindowedRowsEqualWholeRowsInTheWindow) {
  for (const Domain domain : {Domain::Planar, Domain::Cylindrical}) {
    const int w = 40, h = 9;
    const auto hier = multigrid::build_hierarchy(*topology::make_topology(domain), w, h, 0.3, 1 << 20);
    const Image img = test::random_image(w, h, 1, 3);
    test::ExactGradients src(img, domain, 0.3);
    const fem::Axis& x = hier.levels[0].x;
    // Planar windows may touch the image's edges; periodic ones do not wrap (solve_streamed reads
    // whole rows then).
    std::vector<std::pair<int, int>> windows{{11, 29}};
    if (domain == Domain::Planar) windows.insert(windows.end(), {{0, 13}, {27, 40}});
    for (const auto& [begin, end] : windows) {
      fem::RhsAssembler whole(x, hier.levels[0].y, 0.3, 1), part(x, hier.levels[0].y, 0.3, 1);
      part.set_columns(begin, end);
      Plane<double> a(w, h), b(w, h);
      GuidanceRow row, cut;
      row.x_edges = x.edges();
      row.gx.resize(x.edges());
      row.gy.resize(w);
      row.value.resize(w);
      for (int j = 0; j < h; ++j) {
        src.read_row(j, row);
        cut = row;  // the guidance as a windowed source leaves it: unknown beyond two columns
        for (int i = 0; i < w; ++i)
          if (i < begin - 2 || i >= end + 2) cut.gy[i] = cut.value[i] = 1e30;
        for (int i = 0; i < x.edges(); ++i)
          if (i < begin - 2 || i >= end + 1) cut.gx[i] = 1e30;
        whole.push(j, row, [&](int r, int, std::span<const double> v) { std::copy(v.begin(), v.end(), a.row(r)); });
        part.push(j, cut, [&](int r, int, std::span<const double> v) { std::copy(v.begin(), v.end(), b.row(r)); });
      }
      whole.finish([&](int r, int, std::span<const double> v) { std::copy(v.begin(), v.end(), a.row(r)); });
      part.finish([&](int r, int, std::span<const double> v) { std::copy(v.begin(), v.end(), b.row(r)); });
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
          ASSERT_EQ(b.at(i, j), i >= begin && i < end ? a.at(i, j) : 0.0) << begin << " " << i << "," << j;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Sizes, RhsIdentity,
                         ::testing::Combine(::testing::Values(Domain::Planar, Domain::Cylindrical),
                                            ::testing::Values(3, 4, 17), ::testing::Values(1, 2, 5, 12),
                                            ::testing::Values(0.0, 0.3)));
INSTANTIATE_TEST_SUITE_P(Spherical, RhsIdentity,
                         ::testing::Combine(::testing::Values(Domain::Spherical), ::testing::Values(8, 24, 48),
                                            ::testing::Values(0), ::testing::Values(0.0, 0.3)));

}  // namespace
}  // namespace gdp

namespace gdp {
namespace {

// Every neighbour pair is reciprocal: as many of p's 5x5 stencil offsets land on q as q's land
// on p (through the index map: reflections, wrap-around and the PQ folds).
TEST(Topology, EveryNeighbourPairIsReciprocal) {
  for (const auto& [domain, w, h] : {std::make_tuple(Domain::Planar, 7, 5), std::make_tuple(Domain::Cylindrical, 9, 4),
                                     std::make_tuple(Domain::Spherical, 16, 4), std::make_tuple(Domain::Spherical, 32, 8)}) {
    const auto topo = topology::make_topology(domain);
    std::map<std::pair<int, int>, int> count;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            const auto [ni, nj] = topo->map(i + dx, j + dy, w, h);
            ASSERT_TRUE(ni >= 0 && ni < w && nj >= 0 && nj < h);
            ++count[{j * w + i, nj * w + ni}];
          }
    for (const auto& [pq, n] : count) {
      const auto it = count.find({pq.second, pq.first});
      ASSERT_NE(it, count.end()) << topo->name() << " " << pq.first << " -> " << pq.second;
      EXPECT_EQ(it->second, n) << topo->name() << " " << pq.first << " <-> " << pq.second;
    }
  }
}

}  // namespace
}  // namespace gdp
