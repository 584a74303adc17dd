// Stencil identities of the folded fine axes and the Galerkin coarse axes.
#include <gtest/gtest.h>

#include <cmath>

#include "fem/axis.h"
#include "fem/stencils.h"

namespace gdp::fem {
namespace {

// Dense n x n matrix of one of an axis's banded matrices.
std::vector<std::vector<double>> dense(const Axis& a, const RowTable<std::array<double, 5>>& m) {
  std::vector<std::vector<double>> d(a.n, std::vector<double>(a.n, 0.0));
  for (int i = 0; i < a.n; ++i)
    for (int k = -2; k <= 2; ++k) {
      const int c = a.column(i, k);
      if (c >= 0) d[i][c] += m[i][k + 2];
    }
  return d;
}

void expect_symmetric(const std::vector<std::vector<double>>& m) {
  for (std::size_t i = 0; i < m.size(); ++i)
    for (std::size_t j = 0; j < m.size(); ++j) EXPECT_NEAR(m[i][j], m[j][i], 1e-12) << i << "," << j;
}

double row_sum(const std::vector<double>& r) {
  double s = 0.0;
  for (double v : r) s += v;
  return s;
}

TEST(Axis, InteriorStencilsSumToOneAndZero) {
  double m = 0.0, s = 0.0, d = 0.0;
  for (double v : kMass) m += v;
  for (double v : kStiffness) s += v;
  for (double v : kDerivative) d += v;
  EXPECT_NEAR(m, 1.0, 1e-15);
  EXPECT_NEAR(s, 0.0, 1e-15);
  EXPECT_NEAR(d, 0.0, 1e-15);
}

TEST(Axis, FoldedBoundaryRowsMatchExactIntegration) {
  const Axis a = make_fine_axis(10, AxisBoundary::Neumann);
  // Row 0 from the diagonal outwards: mass 23/30, 9/40, 1/120; stiffness 2/3, -1/2, -1/6.
  EXPECT_NEAR(a.mass[0][2], 23.0 / 30, 1e-15);
  EXPECT_NEAR(a.mass[0][3], 9.0 / 40, 1e-15);
  EXPECT_NEAR(a.mass[0][4], 1.0 / 120, 1e-15);
  EXPECT_NEAR(a.stiffness[0][2], 2.0 / 3, 1e-15);
  EXPECT_NEAR(a.stiffness[0][3], -0.5, 1e-15);
  EXPECT_NEAR(a.stiffness[0][4], -1.0 / 6, 1e-15);
  EXPECT_EQ(a.mass[0][0], 0.0);
  EXPECT_EQ(a.mass[0][1], 0.0);
  // Row 1: mass 9/40, 11/20, 13/60, 1/120; stiffness -1/2, 1, -1/3, -1/6.
  EXPECT_NEAR(a.mass[1][1], 9.0 / 40, 1e-15);
  EXPECT_NEAR(a.mass[1][2], 11.0 / 20, 1e-15);
  EXPECT_NEAR(a.stiffness[1][1], -0.5, 1e-15);
  EXPECT_NEAR(a.stiffness[1][2], 1.0, 1e-15);
  // The last rows mirror the first ones.
  for (int d = 0; d < 5; ++d) {
    EXPECT_DOUBLE_EQ(a.mass[9][d], a.mass[0][4 - d]);
    EXPECT_DOUBLE_EQ(a.stiffness[8][d], a.stiffness[1][4 - d]);
  }
}

class AxisSizes : public ::testing::TestWithParam<std::tuple<int, AxisBoundary>> {};

TEST_P(AxisSizes, FineAndCoarseRowsAreSymmetricWithUnitMassAndZeroStiffness) {
  const auto [n, boundary] = GetParam();
  Axis a = make_fine_axis(n, boundary);
  double scale = 1.0;
  for (int level = 0; level < 6; ++level) {
    SCOPED_TRACE(::testing::Message() << "n=" << a.n << " level " << level);
    const auto m = dense(a, a.mass), s = dense(a, a.stiffness);
    expect_symmetric(m);
    expect_symmetric(s);
    double total_mass = 0.0;
    for (int i = 0; i < a.n; ++i) {
      EXPECT_NEAR(row_sum(s[i]), 0.0, 1e-12);  // constants are harmonic
      total_mass += row_sum(m[i]);
    }
    // Total mass is the domain's length in finest-level units (exact nesting or not, P
    // preserves constants, so 1^T M 1 is kept by the Galerkin product); a rediscretised odd
    // periodic axis measures its own, slightly longer, length.
    EXPECT_NEAR(total_mass, boundary == AxisBoundary::Periodic ? a.n * a.scale : n, n * 1e-12 + 1e-9);
    EXPECT_DOUBLE_EQ(a.scale, scale);
    // Interior rows are the exactly refined stencils 2^l M and 2^-l S.
    for (int i = 3; i + 3 < a.n; ++i)
      for (int d = 0; d < 5; ++d) {
        EXPECT_NEAR(a.mass[i][d], scale * kMass[d], 1e-12);
        EXPECT_NEAR(a.stiffness[i][d], kStiffness[d] / scale, 1e-12);
      }
    const int m_next = next_size(a);
    if (m_next == a.n) break;
    a = coarsen(a, make_prolongation(a, m_next));
    scale *= 2.0;
  }
}

INSTANTIATE_TEST_SUITE_P(Neumann, AxisSizes,
                         ::testing::Combine(::testing::Values(1, 2, 3, 5, 7, 8, 13, 64, 97, 100),
                                            ::testing::Values(AxisBoundary::Neumann)));
INSTANTIATE_TEST_SUITE_P(Periodic, AxisSizes,
                         ::testing::Combine(::testing::Values(3, 5, 8, 12, 13, 64, 97),
                                            ::testing::Values(AxisBoundary::Periodic)));

TEST(Axis, ProlongationRowsSumToOne) {
  for (int n : {1, 2, 3, 8, 13}) {
    for (AxisBoundary b : {AxisBoundary::Neumann, AxisBoundary::Periodic}) {
      const Axis a = make_fine_axis(n, b);
      const Prolongation p = make_prolongation(a, next_size(a));
      ASSERT_EQ(static_cast<int>(p.rows.size()), n);
      for (const auto& r : p.rows) {
        EXPECT_DOUBLE_EQ(r.weight[0] + r.weight[1], 1.0);
        EXPECT_GE(r.index[0], 0);
        EXPECT_LT(r.index[0], p.coarse_n);
        EXPECT_LT(r.index[1], p.coarse_n);
      }
    }
  }
}

// Fine sample i reads coarse i / 2: halving an odd axis to n / 2 (rounding down) would make the
// last sample read one past the coarse axis, so it is refused.
TEST(Axis, ProlongationRefusesToHalveAnOddAxisRoundingDown) {
  EXPECT_THROW(make_prolongation(make_fine_axis(63, AxisBoundary::Periodic), 31), std::logic_error);
  EXPECT_EQ(make_prolongation(make_fine_axis(63, AxisBoundary::Periodic), 32).rows.back().index[0], 31);
}

TEST(Axis, EvenSizesNestExactlyIncludingBoundaryRows) {
  // For n divisible by 2, the coarse axis is the fine folded axis of n/2 samples with the
  // stencils scaled: M by 2, S by 1/2 (B-spline refinement is exact there).
  const Axis fine = make_fine_axis(16, AxisBoundary::Neumann);
  const Axis coarse = coarsen(fine, make_prolongation(fine, 8));
  const Axis direct = make_fine_axis(8, AxisBoundary::Neumann);
  for (int i = 0; i < 8; ++i)
    for (int d = 0; d < 5; ++d) {
      EXPECT_NEAR(coarse.mass[i][d], 2.0 * direct.mass[i][d], 1e-14);
      EXPECT_NEAR(coarse.stiffness[i][d], 0.5 * direct.stiffness[i][d], 1e-14);
    }
}

}  // namespace
}  // namespace gdp::fem

namespace gdp::fem {
namespace {

// Row tables keep only rows near the ends: every level's rows must equal whole tables.
TEST(RowTables, CompressedAxesEqualWholeOnes) {
  constexpr int kWhole = 1 << 20;  // keeps every row
  for (AxisBoundary boundary : {AxisBoundary::Neumann, AxisBoundary::Periodic}) {
    for (int n : {17, 18, 19, 40, 41, 97, 130, 257, 1001}) {
      Axis small = make_fine_axis(n, boundary), whole = make_fine_axis(n, boundary, kWhole);
      for (int level = 0; level < 8 && small.n > 2; ++level) {
        SCOPED_TRACE(::testing::Message() << "n=" << n << " level " << level);
        for (int i = 0; i < small.n; ++i) {
          ASSERT_EQ(small.mass[i], whole.mass[i]) << i;
          ASSERT_EQ(small.stiffness[i], whole.stiffness[i]) << i;
          if (level == 0) {
            ASSERT_EQ(small.derivative[i], whole.derivative[i]) << i;
          }
        }
        const int m = next_size(small);
        if (m == small.n) break;
        const Prolongation p = make_prolongation(small, m);
        small = coarsen(small, p);
        whole = coarsen(whole, p, kWhole);
      }
    }
  }
}

}  // namespace
}  // namespace gdp::fem
