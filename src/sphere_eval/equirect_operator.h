// The intrinsic Laplace-Beltrami operator on an equirectangular grid: one finite-volume stencil per row.
#pragma once

#include <span>
#include <vector>

namespace gdp::sphere_eval {

// Screened Laplace-Beltrami operator  L u = -∫_cell Δu + α ∫_cell u  on the unit sphere, sampled on a
// cell-centred equirectangular grid of W x H cells (W = 2H): row j spans latitudes
// 90° - j·180°/H .. 90° - (j+1)·180°/H, column i spans longitudes i·360°/W .. (i+1)·360°/W, periodic in
// longitude. Values are stored row-major, u[j * W + i].
//
// Finite volumes: each cell exchanges flux with its four neighbours through the edge between them,
// with weight (edge length) / (distance between the cell centres):
//   east-west, in row j:            wx[j] = Δθ / (cos φ_j Δλ)
//   north-south, rows j-1 and j:    wy[j] = cos φ_{j-1/2} Δλ / Δθ   (wy[0] = wy[H] = 0: the poles)
// and (L u)_ij = Σ_neighbours w (u_ij - u_n) + α area[j] u_ij. The weights depend only on the row, so
// the matrix is symmetric and, with α = 0, its null space is the constants.
struct EquirectOperator {
  int width = 0, height = 0;
  double alpha = 0.0;
  std::vector<double> wx;    // per row (H)
  std::vector<double> wy;    // per boundary between rows (H + 1), wy[j] couples rows j-1 and j
  std::vector<double> area;  // per row (H): the area of one cell; they sum to 4π over the grid

  // Throws UsageError unless width == 2 * height >= 2 and alpha >= 0.
  static EquirectOperator make(int width, int height, double alpha = 0.0);

  std::size_t size() const { return static_cast<std::size_t>(width) * height; }
  double diagonal(int j) const { return 2.0 * wx[j] + wy[j] + wy[j + 1] + alpha * area[j]; }
  double row_latitude(int j) const;  // radians, of the cell centres of row j
  double dx(int j) const;            // arc length between horizontal neighbours' centres in row j
  double dy() const;                 // arc length between vertical neighbours' centres

  void apply(std::span<const double> u, std::span<double> out) const;
};

// A gradient field given on the grid's edges, in value per unit arc length on the sphere:
// gx[j * W + i] on the edge between (i, j) and (i + 1 mod W, j), pointing east;
// gy[j * W + i] (rows 0 .. H-2) on the edge between (i, j) and (i, j + 1), pointing south.
struct EdgeGradients {
  std::vector<double> gx, gy;
};

// The spherical gradients of samples p: neighbour differences divided by the centres' distance.
EdgeGradients spherical_gradients(const EquirectOperator& op, std::span<const double> p);

// The right-hand side of the gradient fit: b_ij = -(flux of g out of the cell), i.e. minus the
// integrated divergence. For g = spherical_gradients(p), b = L p (with α = 0) to rounding.
std::vector<double> divergence_rhs(const EquirectOperator& op, const EdgeGradients& g);

// Adds the value term α ∫_cell w of the screened equation to b.
void add_value_term(const EquirectOperator& op, std::span<const double> w, std::span<double> b);

}  // namespace gdp::sphere_eval
