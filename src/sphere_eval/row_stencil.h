// A symmetric operator on a periodic-in-x grid with one 5x5 stencil per row, and its Galerkin coarsening.
#pragma once

#include <span>
#include <vector>

#include "sphere_eval/equirect_operator.h"

namespace gdp::sphere_eval {

// A stencil entry: (L u)_ij includes c * u(i + dx mod W, j + dy); j + dy is always a row of the grid.
struct Tap {
  int dx, dy;
  double c;
};

// The multigrid levels of the equirectangular solver: the finest level is the finite-volume
// operator (five taps), coarser ones its Galerkin products Pᵀ L P, which reach two rows and
// columns each way. Rows differ; columns of a row do not (the metric depends on latitude only).
class RowStencilOperator {
 public:
  static RowStencilOperator from(const EquirectOperator& op);
  // Pᵀ L P on the (W/2) x (H/2) grid, P as in prolong_add. Throws UsageError unless W and H are
  // even and W/2 >= 5 (so that a stencil's columns are distinct).
  static RowStencilOperator galerkin(const RowStencilOperator& fine);

  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t size() const { return static_cast<std::size_t>(width_) * height_; }
  bool singular() const { return singular_; }  // the constants are in the null space
  double diagonal(int j) const { return diagonal_[j]; }
  const std::vector<Tap>& taps(int j) const { return taps_[j]; }  // off-diagonal entries of row j

  void apply(std::span<const double> u, std::span<double> out) const;
  // `sweeps` lexicographic Gauss-Seidel sweeps (rows top to bottom, columns left to right).
  void relax(std::span<double> u, std::span<const double> b, int sweeps) const;

 private:
  int width_ = 0, height_ = 0;
  bool singular_ = false;
  std::vector<double> diagonal_;
  std::vector<std::vector<Tap>> taps_;
};

// Coarse to fine: fine += P coarse, and its transpose, coarse += Pᵀ fine. The fine grid is
// 2Wc x 2Hc; P is the cell-centred two-scale relation (1/4, 3/4, 3/4, 1/4) per axis, periodic in
// longitude and reflected at the poles (fine row -1 reads coarse row 0), so P 1 = 1.
void prolong_add(int coarse_width, int coarse_height, std::span<const double> coarse, std::span<double> fine);
void restrict_add(int coarse_width, int coarse_height, std::span<const double> fine, std::span<double> coarse);

}  // namespace gdp::sphere_eval
