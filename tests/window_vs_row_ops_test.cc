// Transition check: the window kernels on whole rows give the row kernels' bits.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "multigrid/plane_ops.h"
#include "multigrid/row_ops.h"
#include "multigrid/window_ops.h"
#include "topology/topology.h"

namespace gdp::multigrid {
namespace {

template <class T>
Plane<T> random_plane(int w, int h, unsigned seed, T lo = -1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(lo, 1.0);
  Plane<T> p(w, h);
  for (T& v : p.data) v = static_cast<T>(d(rng));
  return p;
}

template <class T>
RowWindow<T> row_window(const LevelOperator<T>& op, const Plane<T>& u, int j) {
  return window(op, u, j).rows;
}

template <class T>
void check(Domain domain, int w, int h, bool with_diag) {
  const Hierarchy hier = build_hierarchy(*topology::make_topology(domain), w, h, 0.01, 4);
  for (std::size_t l = 0; l + 1 < hier.levels.size(); ++l) {
    const LevelOperator<T> op(hier.levels[l], hier.alpha);
    const LevelGeometry& g = hier.levels[l + 1];
    const bool periodic = op.periodic_x;
    const int n = op.width, m = g.width();
    Plane<T> u = random_plane<T>(n, op.height, 1), v = u, b = random_plane<T>(n, op.height, 2);
    const Plane<T> diag = random_plane<T>(n, op.height, 3, 0);
    const Plane<T> coarse = random_plane<T>(m, g.height(), 4);
    RowScratch<T> rs(n);
    Scratch<T> ws;
    std::vector<T> r1(n), r2(n), tmp(n);
    Plane<T> c1(m, g.height()), c2(m, g.height()), p1(n, op.height), p2(n, op.height);
    const Columns whole = Columns::whole(n, periodic);
    const double tol = sizeof(T) == 4 ? 2e-6 : 1e-14;  // relative to the operator's scale (720)
    const auto near = [&](const T* x, const T* y, std::size_t count, const char* what) {
      for (std::size_t i = 0; i < count; ++i)
        ASSERT_NEAR(x[i], y[i], tol * (1000 + std::abs(x[i]))) << what << " level " << l << " at " << i;
    };
    for (int sweep = 0; sweep < 2; ++sweep)
      for (int j = 0; j < op.height; ++j) {
        const T* d = with_diag ? diag.row(j) : nullptr;
        residual_row(op, j, row_window(op, u, j), b.row(j), r1.data(), rs, d);
        residual(op, j, window(op, v, j), whole, b.row(j), r2.data(), ws, d);
        near(r1.data(), r2.data(), n, "residual");
        apply_row(op, j, row_window(op, u, j), r1.data(), rs, d);
        apply(op, j, window(op, v, j), whole, r2.data(), ws, d);
        near(r1.data(), r2.data(), n, "apply");
        relax_row(op, j, row_window(op, u, j), u.row(j), b.row(j), rs, d);
        relax(op, j, window(op, v, j), whole, v.row(j), b.row(j), ws, d);
        near(u.row(j), v.row(j), n, "relax");
        std::copy_n(u.row(j), n, v.row(j));
        const fem::ProlongationRow& py = g.py.rows[j];
        restrict_row(g.px, py, u.row(j), c1.row(py.index[0]), c1.row(py.index[1]), tmp.data());
        restrict_rows(g.px, py, v.row(j), 0, Columns::whole(m, periodic), c2.row(py.index[0]), c2.row(py.index[1]),
                      {0, 0}, ws);
        prolong_row(g.px, py, coarse.row(py.index[0]), coarse.row(py.index[1]), p1.row(j), tmp.data());
        prolong_rows(g.px, py, coarse.row(py.index[0]), coarse.row(py.index[1]), {0, 0}, true, whole, p2.row(j), 0, ws);
        near(p1.row(j), p2.row(j), n, "prolong");
      }
    near(c1.data.data(), c2.data.data(), c1.data.size(), "restrict");
  }
}

TEST(WindowVsRowOps, SameBits) {
  for (Domain d : {Domain::Planar, Domain::Cylindrical, Domain::Spherical})
    for (auto [w, h] : {std::pair{64, 32}, std::pair{67, 37}, std::pair{300, 150}})
      for (bool diag : {false, true}) {
        SCOPED_TRACE(::testing::Message() << int(d) << " " << w << "x" << h << " diag " << diag);
        check<float>(d, w, h, diag);
        check<double>(d, w, h, diag);
      }
}

}  // namespace
}  // namespace gdp::multigrid
