// The pyramid's row filters: gradient magnitude, 2x reduction, 2x bilinear expansion, Fattal's phi.
#pragma once

#include <span>
#include <vector>

#include "apps/tonemap_window.h"
#include "schedule/row_store.h"

namespace gdp::apps::tonemap {

// |grad H| at row y by central differences (in the level's own pixels), from rows y - 1..y + 1.
void gradient_magnitude(RowWindow& level, int y, std::span<float> out);

// Width or height of the next coarser level.
inline int coarser(int n) { return (n + 1) / 2; }

// Row r of the next coarser level: the [1 3 3 1] / 8 filter along both axes over fine rows and
// columns 2r - 1..2r + 2 (cell-centred: the coarse pixel sits between its two middle fine
// ones, so the PQ folds, which lie on pixel corners, stay folds of the coarse level).
void reduce_row(RowWindow& fine, int r, std::span<float> out);

// Fattal's phi = (a / g) (g / a)^beta = (g / a)^(beta - 1), multiplied into `inout`; gradients
// below kFloor * a count as kFloor * a, so flat regions are amplified at most
// kFloor^(beta - 1) per level. a <= 0 (a flat level) leaves `inout` alone.
inline constexpr double kFloor = 0.1;
void multiply_phi(std::span<const float> g, double a, double beta, std::span<float> inout);

// Rows of a level expanded 2x (bilinear, cell-centred: fine row 2r is 3/4 of coarse row r and
// 1/4 of row r - 1), read in order from a store holding the coarse level.
class Expander {
 public:
  Expander(schedule::RowStore<float>& coarse, Domain domain, int coarse_width, int coarse_height, int fine_width);
  // Fine row y, in order y = 0, 1, ...
  void row(int y, std::span<float> out);

 private:
  schedule::RowStore<float>& store_;
  RowWindow window_;
  int fine_width_;
  std::vector<float> in_, mixed_;
};

}  // namespace gdp::apps::tonemap
