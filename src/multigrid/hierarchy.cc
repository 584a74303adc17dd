// Building the multigrid hierarchy and the per-level operator coefficients.
#include "multigrid/hierarchy.h"

#include <algorithm>

namespace gdp::multigrid {

Hierarchy build_hierarchy(const topology::Topology& topo, int width, int height, double alpha,
                          int coarsest_size) {
  // Throws UsageError for sizes the domain does not admit. On the sphere this is what keeps every
  // level 4H x H (W halves only with H), so no level is odd-width: an odd periodic row halved to
  // floor(W/2) columns would leave its last column's prolongation index one past the coarse row.
  topo.validate_size(width, height);
  Hierarchy h;
  h.alpha = alpha;
  h.levels.push_back({fem::make_fine_axis(width, topo.x_boundary()),
                      fem::make_fine_axis(height, topo.y_boundary()), {}, {}});
  for (;;) {
    const LevelGeometry& fine = h.levels.back();
    if (std::max(fine.width(), fine.height()) <= coarsest_size) break;
    const auto [mw, mh] = topo.coarse_size(fine.x, fine.y);
    if (mw == fine.width() && mh == fine.height()) break;
    LevelGeometry coarse;
    const fem::Prolongation px = fem::make_prolongation(fine.x, mw);
    const fem::Prolongation py = fem::make_prolongation(fine.y, mh);
    coarse.x = fem::coarsen(fine.x, px);
    coarse.y = fem::coarsen(fine.y, py);
    coarse.px = px;
    coarse.py = py;
    h.levels.push_back(std::move(coarse));
  }
  return h;
}

template <class T>
LevelOperator<T>::LevelOperator(const LevelGeometry& g, double alpha)
    : width(g.width()), height(g.height()),
      periodic_x(g.x.boundary == fem::AxisBoundary::Periodic) {
  for (int d = 0; d < 5; ++d) {
    sx[d].resize(width);
    mx[d].resize(width);
    for (int i = 0; i < width; ++i) {
      sx[d][i] = static_cast<T>(6.0 * g.x.stiffness[i][d]);
      mx[d][i] = static_cast<T>(120.0 * g.x.mass[i][d]);
    }
  }
  // The widest run of columns around the middle with the middle column's (symmetric) stencil.
  const int mid = width / 2;
  const auto same_as_mid = [&](int i) {
    for (int d = 0; d < 5; ++d)
      if (sx[d][i] != sx[d][mid] || mx[d][i] != mx[d][mid]) return false;
    return true;
  };
  const bool symmetric = width > 0 && sx[0][mid] == sx[4][mid] && sx[1][mid] == sx[3][mid] &&
                         mx[0][mid] == mx[4][mid] && mx[1][mid] == mx[3][mid];
  if (symmetric) {
    interior_begin = mid;
    interior_end = mid + 1;
    while (interior_begin > 2 && same_as_mid(interior_begin - 1)) --interior_begin;
    while (interior_end < width - 2 && same_as_mid(interior_end)) ++interior_end;
    sx_in = {sx[2][mid], sx[3][mid], sx[4][mid]};
    mx_in = {mx[2][mid], mx[3][mid], mx[4][mid]};
  }
  // Rows are built as row tables: only rows near the ends and one interior row are kept.
  my = {height, [&](int j) {
          std::array<T, 5> r;
          for (int d = 0; d < 5; ++d) r[d] = static_cast<T>(120.0 * g.y.mass[j][d]);
          return r;
        }};
  cy = {height, [&](int j) {
          std::array<T, 5> r;
          for (int d = 0; d < 5; ++d) r[d] = static_cast<T>(6.0 * g.y.stiffness[j][d] + 6.0 * alpha * g.y.mass[j][d]);
          return r;
        }};
  offsets_ = {height, [&](int j) {
                std::array<int, 5> r;
                for (int d = 0; d < 5; ++d) {
                  const int c = g.y.column(j, d - 2);
                  r[d] = (c >= 0 && (g.y.mass[j][d] != 0.0 || g.y.stiffness[j][d] != 0.0)) ? c - j : kNone;
                }
                return r;
              }};
  mirrors_ = {height, [&](int j) {
                std::array<fem::Mirror, 5> r;
                for (int d = 0; d < 5; ++d) r[d] = g.y.mirror(j, d - 2);
                return r;
              }};
}

template struct LevelOperator<float>;
template struct LevelOperator<double>;

}  // namespace gdp::multigrid
