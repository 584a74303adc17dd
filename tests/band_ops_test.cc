// Column-range kernels: a row split into bands with halo columns gives the whole-row results.
#include <gtest/gtest.h>

#include <random>

#include "multigrid/band_ops.h"
#include "multigrid/plane_ops.h"
#include "multigrid/row_ops.h"
#include "topology/topology.h"

namespace gdp::multigrid {
namespace {

constexpr int kHalo = 6;

struct Levels {
  Hierarchy h;
  std::vector<LevelOperator<double>> ops;
  Levels(Domain d, int w, int hgt) {
    auto topo = topology::make_topology(d);
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

struct BandCopy {
  std::vector<std::vector<double>> rows;  // every row of the plane, band columns plus halo
  BandWindow<double> window(const LevelOperator<double>& op, int j, int origin, const Plane<double>& whole,
                            std::array<std::vector<double>, 5>& whole_copy) {
    BandWindow<double> w;
    for (int d = 0; d < 5; ++d) {
      const int r = op.row_of(j, d);
      if (r < 0) continue;
      if (op.mirror_of(j, d) != fem::Mirror::None) {  // mirrored rows: a whole-row copy
        whole_copy[d].assign(whole.row(r), whole.row(r) + whole.width);
        w.rows[d] = whole_copy[d].data();
        w.origin[d] = 0;
      } else {
        w.rows[d] = rows[r].data();
        w.origin[d] = origin;
      }
    }
    return w;
  }
};

class BandOps : public ::testing::TestWithParam<Domain> {};

TEST_P(BandOps, ResidualOverBandsEqualsWholeRows) {
  const Levels s(GetParam(), 64, 16);
  const auto& op = s.ops[0];
  const bool periodic = op.periodic_x;
  const Plane<double> u = random_plane(op.width, op.height, 1), b = random_plane(op.width, op.height, 2);
  RowScratch<double> rs(op.width);
  BandScratch<double> bs;
  std::vector<double> whole(op.width);
  std::array<std::vector<double>, 5> mirror_copy;
  for (auto [A, B] : {std::pair{0, 20}, std::pair{20, 44}, std::pair{44, 64}}) {
    BandCopy uc, bc;
    for (int j = 0; j < op.height; ++j) {
      uc.rows.push_back(band_row(u, j, A, B, periodic));
      bc.rows.push_back(band_row(b, j, A, B, periodic));
    }
    for (int j = 0; j < op.height; ++j) {
      residual_row(op, j, window(op, u, j), b.row(j), whole.data(), rs);
      std::vector<double> out(B - A + 2 * kHalo, 0.0);
      const BandWindow<double> w = uc.window(op, j, A - kHalo, u, mirror_copy);
      residual_columns(op, j, w, bc.rows[j].data(), out.data(), A - kHalo, A, B, bs);
      for (int i = A; i < B; ++i) ASSERT_NEAR(out[i - A + kHalo], whole[i], 1e-12) << "row " << j << " col " << i;
    }
  }
}

TEST_P(BandOps, ForwardSweepOverTheWholeRowIsRelaxRow) {
  const Levels s(GetParam(), 48, 12);
  const auto& op = s.ops[0];
  if (op.periodic_x) GTEST_SKIP() << "periodic rows couple their ends inside one sweep";
  Plane<double> u = random_plane(op.width, op.height, 3);
  const Plane<double> b = random_plane(op.width, op.height, 4);
  Plane<double> v = u;
  RowScratch<double> rs(op.width);
  BandScratch<double> bs;
  for (int j = 0; j < op.height; ++j) {
    relax_row(op, j, window(op, u, j), u.row(j), b.row(j), rs);
    BandWindow<double> w;
    for (int d = 0; d < 5; ++d)
      if (op.row_of(j, d) >= 0) w.rows[d] = v.row(op.row_of(j, d));
    relax_columns(op, j, w, v.row(j), b.row(j), 0, op.width, true, bs);
  }
  for (std::size_t k = 0; k < u.data.size(); ++k) ASSERT_NEAR(u.data[k], v.data[k], 1e-12);
}

// A backward sweep over a range equals a forward sweep over the mirrored problem's range; here:
// splitting a range into two halves relaxed in order equals relaxing it whole.
TEST_P(BandOps, SplitRangesEqualOneRangeInEitherDirection) {
  const Levels s(GetParam(), 64, 12);
  const auto& op = s.ops[0];
  const Plane<double> b = random_plane(op.width, op.height, 6);
  BandScratch<double> bs;
  for (bool forward : {true, false}) {
    Plane<double> u = random_plane(op.width, op.height, 5), v = u;
    const int j = op.height / 2;
    BandWindow<double> wu, wv;
    for (int d = 0; d < 5; ++d) {
      wu.rows[d] = u.row(op.row_of(j, d));
      wv.rows[d] = v.row(op.row_of(j, d));
    }
    relax_columns(op, j, wu, u.row(j), b.row(j), 10, 50, forward, bs);
    if (forward) {
      relax_columns(op, j, wv, v.row(j), b.row(j), 10, 31, true, bs);
      relax_columns(op, j, wv, v.row(j), b.row(j), 31, 50, true, bs);
    } else {
      relax_columns(op, j, wv, v.row(j), b.row(j), 31, 50, false, bs);
      relax_columns(op, j, wv, v.row(j), b.row(j), 10, 31, false, bs);
    }
    for (int i = 0; i < op.width; ++i) ASSERT_NEAR(u.at(i, j), v.at(i, j), 1e-12) << i << (forward ? " fwd" : " bwd");
  }
}

TEST_P(BandOps, RestrictAndProlongOverBandsEqualWholeRows) {
  const Levels s(GetParam(), 64, 16);
  const LevelGeometry& g = s.h.levels[1];
  const bool periodic = s.ops[0].periodic_x;
  const int n = s.h.levels[0].width(), m = g.width();
  const Plane<double> fine = random_plane(n, s.h.levels[0].height(), 7);
  const Plane<double> coarse = random_plane(m, g.height(), 8);
  // Whole rows.
  Plane<double> restricted(m, g.height()), prolonged(n, fine.height);
  std::vector<double> tmp(n);
  for (int j = 0; j < fine.height; ++j) {
    const fem::ProlongationRow& py = g.py.rows[j];
    restrict_row(g.px, py, fine.row(j), restricted.row(py.index[0]), restricted.row(py.index[1]), tmp.data());
    prolong_row(g.px, py, coarse.row(py.index[0]), coarse.row(py.index[1]), prolonged.row(j), tmp.data());
  }
  // Bands [A, B) of the fine level own coarse columns [A/2, B/2). Their restrictions, added up
  // (own columns from the band's rows; across a spherical fold straight into whole rows, as the
  // band schedule's fold exchange does), equal the whole rows'.
  BandScratch<double> scratch;
  Plane<double> total(m, g.height());
  for (auto [A, B] : {std::pair{0, 24}, std::pair{24, 40}, std::pair{40, 64}}) {
    const int ca = A / 2, cb = B / 2;
    Plane<double> r(cb - ca + 2 * kHalo, g.height());
    for (int j = 0; j < fine.height; ++j) {
      const fem::ProlongationRow& py = g.py.rows[j];
      const std::vector<double> f = band_row(fine, j, A, B, periodic);
      const bool folded = py.mirror != fem::Mirror::None;
      restrict_columns(g.px, py, periodic, f.data(), A - kHalo, A - kHalo, B + kHalo, r.row(py.index[0]),
                       folded ? total.row(py.index[1]) : r.row(py.index[1]),
                       {ca - kHalo, folded ? 0 : ca - kHalo}, ca, cb, scratch);
      // Prolongation reads a mirrored coarse row whole.
      std::vector<double> p(B - A + 2 * kHalo, 0.0), c0 = band_row(coarse, py.index[0], ca, cb, periodic),
                                                     c1 = band_row(coarse, py.index[1], ca, cb, periodic);
      const double* coarse1 = folded ? coarse.row(py.index[1]) : c1.data();
      prolong_columns(g.px, py, periodic, c0.data(), coarse1, {ca - kHalo, folded ? 0 : ca - kHalo}, false, p.data(),
                      A - kHalo, A - 4, B + 4);
      for (int i = A - 4; i < B + 4; ++i) {
        if (!periodic && (i < 0 || i >= n)) continue;
        ASSERT_NEAR(p[i - A + kHalo], prolonged.at(fem::wrap_index(i, n), j), 1e-12) << "row " << j << " col " << i;
      }
    }
    for (int J = 0; J < g.height(); ++J)
      for (int i = ca; i < cb; ++i) total.at(i, J) += r.at(i - ca + kHalo, J);
  }
  for (int J = 0; J < g.height(); ++J)
    for (int i = 0; i < m; ++i) ASSERT_NEAR(total.at(i, J), restricted.at(i, J), 1e-12) << J << " " << i;
}

INSTANTIATE_TEST_SUITE_P(Domains, BandOps, ::testing::Values(Domain::Planar, Domain::Cylindrical, Domain::Spherical));

}  // namespace
}  // namespace gdp::multigrid
