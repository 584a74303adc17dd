// One axis of one multigrid level: banded 1D mass / stiffness matrices and the transfer to it.
#pragma once

#include <array>
#include <vector>

#include "fem/row_table.h"

namespace gdp::fem {

// Boundary behaviour of one axis.
enum class AxisBoundary {
  Neumann,   // half-sample reflection at both ends (planar images)
  Periodic,  // wrap-around (the horizontal axis of cylindrical and spherical images)
  // Half-sample reflection at both ends where a reflected row is also mirrored left to right
  // (the rows of the spherical PQ domain, docs/sphere-solver.md): nothing is folded, a ghost
  // neighbour keeps its own coefficient and reads the row it reflects to, mirrored (Mirror).
  Mirrored,
};

// How a neighbouring row is read: as it is, or mirrored left to right because it lies across
// the top or the bottom edge of a Mirrored axis. On a row of n samples, Top reads column
// n - 1 - i for column i, Bottom reads column (n/2 - 1 - i) mod n (NUMERICS.md §4).
enum class Mirror : unsigned char { None, Top, Bottom };

// The column that column i of a row mirrored by `m` reads (n: the row's length).
int mirror_column(Mirror m, int i, int n);

// The 1D Galerkin matrices of one axis. Row i couples sample i with sample i+d, d = -2..2,
// stored at [d + 2]. Out-of-range columns are folded into in-range ones (Neumann, so their
// coefficients are zero) or wrapped (Periodic).
struct Axis {
  int n = 0;
  AxisBoundary boundary = AxisBoundary::Neumann;
  double scale = 1.0;  // sample spacing in finest-level samples (2^level where halved)
  RowTable<std::array<double, 5>> mass;
  RowTable<std::array<double, 5>> stiffness;
  // Finest level only: coupling of B_i' with the hats on edges i-2..i+1, folded like the
  // rows above (Neumann: reflected edges change sign, boundary edges vanish).
  RowTable<std::array<double, 4>> derivative;

  // Number of edges (gradient samples) along this axis: n-1, or n when periodic.
  int edges() const { return boundary == AxisBoundary::Periodic ? n : (n > 0 ? n - 1 : 0); }
  // Column index of row i's neighbour at offset d, or -1 when the coefficient is folded away.
  int column(int i, int d) const;
  // Whether that neighbour is read mirrored (Mirrored axes only).
  Mirror mirror(int i, int d) const;
};

// Half-sample reflection of an index into [0, n) (repeated for tiny n), and wrap-around.
int reflect_index(int c, int n);
int wrap_index(int c, int n);

// Linear interpolation from a coarse axis (m samples) to a fine axis (n samples):
// fine[i] = weight[0] * coarse[index[0]] + weight[1] * coarse[index[1]].
struct ProlongationRow {
  std::array<int, 2> index;
  std::array<double, 2> weight;
  Mirror mirror = Mirror::None;  // coarse[index[1]] is read mirrored (Mirrored axes; index[0] never is)
};
struct Prolongation {
  int coarse_n = 0;
  std::vector<ProlongationRow> rows;  // one per fine sample
};

// Finest-level axis with n samples. `edge`: rows kept near each end (RowTable; tests build
// whole tables with a huge edge to check the interior really is uniform).
Axis make_fine_axis(int n, AxisBoundary boundary, int edge = RowTable<int>::kEdge);
// Prolongation from m samples to the fine axis's n samples: m == coarse_size(n) halves the
// axis (interpolating from the coarse samples reflected or wrapped at the ends), m == n is
// the identity (an axis that no longer coarsens).
Prolongation make_prolongation(const Axis& fine, int m);
// Coarse size for this axis, or n itself when it should not be halved any more. A Mirrored
// axis halves only while n is even and at least 4 (its reflections must stay on sample edges).
int next_size(const Axis& fine);
// Galerkin coarse axis P^T A P for mass and stiffness (exact B-spline refinement where the
// spaces nest, the algebraic Galerkin product elsewhere). One exception: a periodic axis of
// odd length, whose Galerkin product would leave the 5-wide band, is rediscretised (interior
// stencils at the coarse spacing), which keeps the operator symmetric and consistent. A halved
// Mirrored axis is the interior stencils at the coarse spacing, which is its exact Galerkin
// product (the B-splines nest and nothing is folded).
Axis coarsen(const Axis& fine, const Prolongation& p, int edge = RowTable<int>::kEdge);

}  // namespace gdp::fem
