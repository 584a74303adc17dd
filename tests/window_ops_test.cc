// Window kernels: a row split into bands with halo columns gives the whole-row results.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "gdp/errors.h"
#include "multigrid/plane_ops.h"
#include "multigrid/window_ops.h"
#include "topology/topology.h"

namespace gdp::multigrid {
namespace {

constexpr int kHalo = 6;

struct Levels {
  Hierarchy h;
  std::vector<LevelOperator<double>> ops;
  Levels(Domain d, int w, int hgt) {
    auto topo = topology::make_topology(d);
    if (d == Domain::Spherical) hgt = w / 4;  // PQ: W = 4H
    h = build_hierarchy(*topo, w, hgt, 0.01, 4);
    for (const auto& g : h.levels) ops.emplace_back(g, h.alpha);
  }
};

Plane<double> random_plane(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  Plane<double> p(w, h);
  for (double& v : p.data) v = d(rng);
  return p;
}

// Columns [a - kHalo, b + kHalo) of row j (wrapped where periodic, zero outside otherwise).
std::vector<double> band_row(const Plane<double>& p, int j, int a, int b, bool periodic) {
  std::vector<double> r(b - a + 2 * kHalo, 0.0);
  for (int i = a - kHalo; i < b + kHalo; ++i) {
    if (periodic) r[i - a + kHalo] = p.at(fem::wrap_index(i, p.width), j);
    else if (i >= 0 && i < p.width) r[i - a + kHalo] = p.at(i, j);
  }
  return r;
}

// Every row of a plane as band [a, b) holds it; mirrored rows are read whole.
struct BandCopy {
  std::vector<std::vector<double>> rows;
  int origin;
  BandCopy(const Plane<double>& p, int a, int b, bool periodic) : origin(a - kHalo) {
    for (int j = 0; j < p.height; ++j) rows.push_back(band_row(p, j, a, b, periodic));
  }
  Window<double> window(const LevelOperator<double>& op, int j, const Plane<double>& whole) const {
    Window<double> w;
    for (int d = 0; d < 5; ++d) {
      const int r = op.row_of(j, d);
      if (r < 0) continue;
      const bool mirrored = op.mirror_of(j, d) != fem::Mirror::None;
      w.rows[d] = mirrored ? whole.row(r) : rows[r].data();
      w.origin[d] = mirrored ? 0 : origin;
    }
    return w;
  }
};

// Bands of a row n wide: the first one reaching across column 0 on periodic levels.
std::vector<std::pair<int, int>> bands(int n) { return {{0, n / 3}, {n / 3, 2 * n / 3 + 1}, {2 * n / 3 + 1, n}}; }

class WindowOps : public ::testing::TestWithParam<std::tuple<Domain, int>> {};

TEST_P(WindowOps, ResidualAndOperatorOverBandsEqualWholeRows) {
  const auto [domain, width] = GetParam();
  const Levels s(domain, width, 16);
  const auto& op = s.ops[0];
  const bool periodic = op.periodic_x;
  const Plane<double> u = random_plane(op.width, op.height, 1), b = random_plane(op.width, op.height, 2);
  const Plane<double> diag = random_plane(op.width, op.height, 9);
  Scratch<double> ws;
  std::vector<double> whole(op.width), applied(op.width);
  for (auto [A, B] : bands(op.width)) {
    const BandCopy uc(u, A, B, periodic), bc(b, A, B, periodic), dc(diag, A, B, periodic);
    for (int j = 0; j < op.height; ++j) {
      residual(op, j, window(op, u, j), Columns::whole(op.width, periodic), b.row(j), whole.data(), ws, diag.row(j));
      apply(op, j, window(op, u, j), Columns::whole(op.width, periodic), applied.data(), ws);
      std::vector<double> out(B - A + 2 * kHalo, 0.0), out2 = out;
      const Window<double> w = uc.window(op, j, u);
      const Columns cols = Columns::range(op.width, periodic, A - 2, B + 2);
      residual(op, j, w, cols, bc.rows[j].data(), out.data(), ws, dc.rows[j].data());
      apply(op, j, w, cols, out2.data(), ws);
      for (int i = cols.begin; i < cols.end; ++i) {
        ASSERT_NEAR(out[i - A + kHalo], whole[fem::wrap_index(i, op.width)], 1e-12) << "row " << j << " col " << i;
        ASSERT_NEAR(out2[i - A + kHalo], applied[fem::wrap_index(i, op.width)], 1e-12) << "row " << j << " col " << i;
      }
    }
  }
}

// Relaxing a range in two parts, in order, equals relaxing it whole, in either direction.
TEST_P(WindowOps, SplitRangesEqualOneRangeInEitherDirection) {
  const auto [domain, width] = GetParam();
  const Levels s(domain, width, 12);
  const auto& op = s.ops[0];
  const Plane<double> b = random_plane(op.width, op.height, 6), diag = random_plane(op.width, op.height, 7);
  Scratch<double> ws;
  for (bool forward : {true, false})
    for (const Plane<double>* d : {static_cast<const Plane<double>*>(nullptr), &diag}) {
      Plane<double> u = random_plane(op.width, op.height, 5), v = u;
      const int j = op.height / 2, mid = 31;
      Window<double> wu, wv;
      for (int r = 0; r < 5; ++r) {
        wu.rows[r] = u.row(op.row_of(j, r));
        wv.rows[r] = v.row(op.row_of(j, r));
      }
      const auto sweep = [&](const Window<double>& w, Plane<double>& p, int a, int e) {
        relax(op, j, w, Columns::range(op.width, false, a, e, forward), p.row(j), b.row(j), ws, d ? d->row(j) : nullptr);
      };
      sweep(wu, u, 10, 50);
      sweep(wv, v, forward ? 10 : mid, forward ? mid : 50);
      sweep(wv, v, forward ? mid : 10, forward ? 50 : mid);
      for (int i = 0; i < op.width; ++i) ASSERT_NEAR(u.at(i, j), v.at(i, j), 1e-12) << i << (forward ? " fwd" : " bwd");
    }
}

// A periodic band relaxed across column 0 in unwrapped columns equals the same columns relaxed
// on a copy of the row shifted to lie inside [0, n).
TEST_P(WindowOps, RelaxAcrossTheWrapEqualsShiftedColumns) {
  const auto [domain, width] = GetParam();
  const Levels s(domain, width, 12);
  const auto& op = s.ops[0];
  if (!op.periodic_x) GTEST_SKIP() << "planar rows do not wrap";
  const Plane<double> u = random_plane(op.width, op.height, 3), b = random_plane(op.width, op.height, 4);
  Scratch<double> ws;
  const int j = op.height / 2, A = 2, B = 16, shift = op.width;  // band [2, 16) holds [-4, 22)
  for (bool forward : {true, false}) {
    const BandCopy uc(u, A, B, true), bc(b, A, B, true);
    std::vector<double> row = uc.rows[j];
    Window<double> w = uc.window(op, j, u);
    w.rows[2] = row.data();
    relax(op, j, w, Columns::range(op.width, true, -2, 18, forward), row.data(), bc.rows[j].data(), ws);
    // The same columns + n: read from the whole plane's rows (wrapped by hand).
    Plane<double> v = u;
    Window<double> wv = window(op, v, j);
    std::vector<double> ext(3 * op.width);
    for (int i = 0; i < 3 * op.width; ++i) ext[i] = v.at(i % op.width, j);
    wv.rows[2] = ext.data();
    std::vector<double> bext(3 * op.width);
    for (int i = 0; i < 3 * op.width; ++i) bext[i] = b.at(i % op.width, j);
    std::array<std::vector<double>, 5> copies;
    for (int d = 0; d < 5; ++d) {
      const int r = op.row_of(j, d);
      if (d == 2 || r < 0 || op.mirror_of(j, d) != fem::Mirror::None) continue;
      copies[d].resize(3 * op.width);
      for (int i = 0; i < 3 * op.width; ++i) copies[d][i] = u.at(i % op.width, r);
      wv.rows[d] = copies[d].data();
    }
    relax(op, j, wv, Columns::range(op.width, true, -2 + shift, 18 + shift, forward), ext.data(), bext.data(), ws);
    for (int i = -2; i < 18; ++i) ASSERT_NEAR(row[i - A + kHalo], ext[i + shift], 1e-12) << i;
  }
}

// Relax is pointwise Gauss-Seidel: u_i += (b_i - ((A + D) u)_i) / (A + D)_ii, i in the sweep's order, with the
// newest values (whole rows, wrapping on periodic levels; planar ranges in either direction, their neighbours'
// values held), with and without a diagonal term. The kernel runs in T on u, b, D rounded to T; the reference in
// double from the same values and coefficients. Returns the largest difference over the row, relative to the
// largest correction or value, whichever is larger.
template <class T>
double relax_against_pointwise(const LevelOperator<T>& op, int j, Columns cols, bool with_diag, Scratch<T>& ws) {
  const int n = op.width;
  const auto rounded = [&](unsigned seed, bool positive) {
    Plane<double> p = random_plane(n, op.height, seed);
    for (double& x : p.data) x = static_cast<T>(positive ? 0.5 + 0.25 * x : x);
    return p;
  };
  const auto as_t = [](const Plane<double>& p) {
    Plane<T> q(p.width, p.height);
    std::copy(p.data.begin(), p.data.end(), q.data.begin());
    return q;
  };
  const Plane<double> b = rounded(11, false), diag = rounded(12, true), v0 = rounded(10, false);
  const Plane<T> bt = as_t(b), dt = as_t(diag);
  Plane<T> u = as_t(v0);
  Plane<double> v = v0;
  relax(op, j, window(op, u, j), cols, u.row(j), bt.row(j), ws, with_diag ? dt.row(j) : nullptr);
  double moved = 0.0;
  for (int step = 0; step < cols.end - cols.begin; ++step) {
    const int i = cols.forward ? cols.begin + step : cols.end - 1 - step;
    double au = 0.0, k0 = with_diag ? diag.at(i, j) : 0.0;
    for (int dy = 0; dy < 5; ++dy) {
      const int r = op.row_of(j, dy);
      if (r < 0) continue;
      for (int dx = 0; dx < 5; ++dx) {
        const int c = op.periodic_x ? fem::wrap_index(i + dx - 2, n) : i + dx - 2;
        const double k = double(op.sx[dx][i]) * op.my[j][dy] + double(op.mx[dx][i]) * op.cy[j][dy];
        if (c >= 0 && c < n) au += k * v.at(c, r);
        if (dy == 2 && dx == 2) k0 += k;
      }
    }
    const double dx = (b.at(i, j) - au - (with_diag ? diag.at(i, j) * v.at(i, j) : 0.0)) / k0;
    v.at(i, j) += dx;
    moved = std::max(moved, std::abs(dx));
  }
  double worst = 0.0, size = moved;
  for (int i = 0; i < n; ++i) {
    worst = std::max(worst, std::abs(u.at(i, j) - v.at(i, j)));
    size = std::max(size, std::abs(v.at(i, j)));
  }
  return worst / size;
}

// The rows relax_against_pointwise checks on a level: whole rows (both directions where planar; periodic ones
// wrap forward) and planar ranges in both directions, on rows 0, 1 and the middle one, unless mirrored.
template <class T>
double relax_error(const LevelOperator<T>& op, bool with_diag, Scratch<T>& ws) {
  const int n = op.width;
  std::vector<Columns> ranges{Columns::whole(n, op.periodic_x)};
  if (!op.periodic_x)
    for (bool fwd : {true, false})
      ranges.insert(ranges.end(), {Columns::range(n, false, 0, n, fwd), Columns::range(n, false, 1, n - 3, fwd),
                                   Columns::range(n, false, 3, n - 1, fwd)});
  double worst = 0.0;
  for (int j : {0, std::min(1, op.height - 1), op.height / 2}) {
    bool mirrored = false;
    for (int d = 0; d < 5; ++d) mirrored |= op.row_of(j, d) >= 0 && op.mirror_of(j, d) != fem::Mirror::None;
    if (mirrored) continue;
    for (const Columns& cols : ranges)
      if (cols.end > cols.begin) worst = std::max(worst, relax_against_pointwise(op, j, cols, with_diag, ws));
  }
  return worst;
}

// The kernels apply the stiffness to differences (sum_d sx[d] a_{i+d} as sum_d sx[d] (a_{i+d} - a_i)), which takes
// every row of sx, on every level, to sum to zero: exactly in float; in double to the rounding of the coarse levels'
// end columns (Galerkin products such as -1.4999999999999998, whose exact value sums to zero).
TEST_P(WindowOps, StiffnessRowsSumToZero) {
  const auto [domain, width] = GetParam();
  const Levels s(domain, width, 16);
  for (std::size_t l = 0; l < s.h.levels.size(); ++l) {
    const LevelOperator<double>& od = s.ops[l];
    const LevelOperator<float> of(s.h.levels[l], s.h.alpha);
    for (int i = 0; i < od.width; ++i) {
      EXPECT_EQ(of.sx[0][i] + of.sx[1][i] + of.sx[2][i] + of.sx[3][i] + of.sx[4][i], 0.0f) << of.width << " " << i;
      EXPECT_NEAR(od.sx[0][i] + od.sx[1][i] + od.sx[2][i] + od.sx[3][i] + od.sx[4][i], 0.0, 4e-15) << od.width << " " << i;
    }
  }
}

TEST_P(WindowOps, RelaxIsPointwiseGaussSeidel) {
  const auto [domain, width] = GetParam();
  const Levels s(domain, width, 16);
  Scratch<double> ws;
  for (const LevelOperator<double>& op : s.ops)
    for (bool d : {false, true}) EXPECT_LT(relax_error(op, d, ws), 1e-10) << "width " << op.width << (d ? " diag" : "");
}

// The same on narrow levels, 1 to 17 columns wide (a tall thin image's coarse levels, where the sweep's blocks of
// eight run short), planar and periodic (3 columns at least), alpha = 0 and > 0, in double and float (to float's
// rounding).
TEST(WindowOpsNarrow, RelaxIsPointwiseGaussSeidelOnNarrowLevels) {
  Scratch<double> wd;
  Scratch<float> wf;
  for (Domain domain : {Domain::Planar, Domain::Cylindrical})
    for (double alpha : {0.0, 0.01})
      for (int width = domain == Domain::Planar ? 1 : 3; width <= 17; ++width) {
        const auto topo = topology::make_topology(domain);
        const Hierarchy h = build_hierarchy(*topo, width, 40, alpha, 1);
        for (const LevelGeometry& g : h.levels) {
          const LevelOperator<double> od(g, alpha);
          const LevelOperator<float> of(g, alpha);
          for (bool d : {false, true}) {
            const std::string what = "width " + std::to_string(g.width()) + " of " + std::to_string(width) +
                                     (od.periodic_x ? " periodic" : " planar") + " alpha " + std::to_string(alpha) +
                                     (d ? " diag" : "");
            EXPECT_LT(relax_error(od, d, wd), 1e-10) << what;
            EXPECT_LT(relax_error(of, d, wf), 2e-5) << what << " float";
          }
        }
      }
}

TEST_P(WindowOps, RestrictAndProlongOverBandsEqualWholeRows) {
  const auto [domain, width] = GetParam();
  const Levels s(domain, width, 16);
  const LevelGeometry& g = s.h.levels[1];
  const bool periodic = s.ops[0].periodic_x;
  const int n = s.h.levels[0].width(), m = g.width();
  const Plane<double> fine = random_plane(n, s.h.levels[0].height(), 7);
  const Plane<double> coarse = random_plane(m, g.height(), 8);
  Scratch<double> ws;
  // Whole rows.
  Plane<double> restricted(m, g.height()), prolonged(n, fine.height);
  for (int j = 0; j < fine.height; ++j) {
    const fem::ProlongationRow& py = g.py.rows[j];
    restrict_rows(g.px, py, fine.row(j), 0, Columns::whole(m, periodic), restricted.row(py.index[0]),
                  restricted.row(py.index[1]), {0, 0}, ws);
    prolong_rows(g.px, py, coarse.row(py.index[0]), coarse.row(py.index[1]), {0, 0}, true,
                 Columns::whole(n, periodic), prolonged.row(j), 0, ws);
  }
  // Bands [A, B) of the fine level own coarse columns [A/2, B/2). Their restrictions, added up
  // (own columns from the band's rows; across a spherical fold straight into whole rows, as the
  // band schedule's fold exchange does), equal the whole rows'.
  Plane<double> total(m, g.height());
  for (auto [A, B] : {std::pair{0, 24}, std::pair{24, 40}, std::pair{40, n}}) {
    const int ca = A / 2, cb = (B + 1) / 2;
    Plane<double> r(cb - ca + 2 * kHalo, g.height());
    for (int j = 0; j < fine.height; ++j) {
      const fem::ProlongationRow& py = g.py.rows[j];
      const std::vector<double> f = band_row(fine, j, A, B, periodic);
      const bool folded = py.mirror != fem::Mirror::None;
      restrict_rows(g.px, py, f.data(), A - kHalo, Columns::range(m, periodic, ca, cb), r.row(py.index[0]),
                    folded ? total.row(py.index[1]) : r.row(py.index[1]), {ca - kHalo, folded ? 0 : ca - kHalo}, ws);
      // Prolongation reads a mirrored coarse row whole; from whole coarse rows too (a gathered level).
      for (bool whole : {false, true}) {
        std::vector<double> p(B - A + 2 * kHalo, 0.0), c0 = band_row(coarse, py.index[0], ca, cb, periodic),
                                                       c1 = band_row(coarse, py.index[1], ca, cb, periodic);
        const double* coarse0 = whole ? coarse.row(py.index[0]) : c0.data();
        const double* coarse1 = folded || whole ? coarse.row(py.index[1]) : c1.data();
        const Columns cols = Columns::range(n, periodic, A - 4, B + 4);
        prolong_rows(g.px, py, coarse0, coarse1, {whole ? 0 : ca - kHalo, folded || whole ? 0 : ca - kHalo}, whole,
                     cols, p.data(), A - kHalo, ws);
        for (int i = cols.begin; i < cols.end; ++i)
          ASSERT_NEAR(p[i - A + kHalo], prolonged.at(fem::wrap_index(i, n), j), 1e-12) << "row " << j << " col " << i;
      }
    }
    for (int J = 0; J < g.height(); ++J)
      for (int i = ca; i < cb; ++i) total.at(i, J) += r.at(i - ca + kHalo, J);
  }
  for (int J = 0; J < g.height(); ++J)
    for (int i = 0; i < m; ++i) ASSERT_NEAR(total.at(i, J), restricted.at(i, J), 1e-12) << J << " " << i;
}

INSTANTIATE_TEST_SUITE_P(Domains, WindowOps,
                         ::testing::Combine(::testing::Values(Domain::Planar, Domain::Cylindrical),
                                            ::testing::Values(64, 63)));
// PQ images are 4H x H with H even (odd widths are refused below).
INSTANTIATE_TEST_SUITE_P(Sphere, WindowOps,
                         ::testing::Combine(::testing::Values(Domain::Spherical), ::testing::Values(64, 72)));

// No PQ level is odd-width: the hierarchy refuses a spherical size that is not 4H x H with H even
// (an odd periodic row halved to W / 2 columns would prolong its last column from one past the
// coarse row), and on valid sizes W halves only with H, so every level stays 4H x H.
TEST(WindowOpsSphere, NoLevelIsOddWidth) {
  const auto topo = topology::make_topology(Domain::Spherical);
  for (auto [w, h] : {std::pair{63, 16}, std::pair{64, 12}, std::pair{60, 15}})
    EXPECT_THROW(build_hierarchy(*topo, w, h, 0.01, 4), UsageError) << w << "x" << h;
  for (int h : {2, 6, 12, 16, 40}) {
    const Hierarchy hier = build_hierarchy(*topo, 4 * h, h, 0.01, 1);
    for (const LevelGeometry& g : hier.levels) {
      EXPECT_EQ(g.width(), 4 * g.height());
      for (const fem::ProlongationRow& r : g.px.rows) EXPECT_LT(r.index[0], g.width());
    }
  }
}

}  // namespace
}  // namespace gdp::multigrid
