// The multigrid hierarchy: per-level axes, transfers, and operator coefficients.
#pragma once

#include <array>
#include <vector>

#include "fem/axis.h"
#include "topology/topology.h"

namespace gdp::multigrid {

// One level's geometry. px / py interpolate from this level to the next finer one
// (empty on the finest level).
struct LevelGeometry {
  fem::Axis x, y;
  fem::Prolongation px, py;
  int width() const { return x.n; }
  int height() const { return y.n; }
};

struct Hierarchy {
  std::vector<LevelGeometry> levels;  // [0] is the finest
  double alpha = 0.0;                 // screening weight (same at every level; the mass carries the scale)
};

// Halves both axes (each while it can) until neither side exceeds coarsest_size. UsageError
// (Topology::validate_size) for a size the domain does not admit, e.g. a PQ image that is not 4H x H.
Hierarchy build_hierarchy(const topology::Topology& topo, int width, int height, double alpha,
                          int coarsest_size);

// A level's operator A = Sx (x) My + Mx (x) (Sy + alpha My), in kernel precision T, stored
// multiplied by kScale = 720: the stiffness by 6 and the mass by 120, which makes every
// coefficient (folded, Galerkin, any level) a dyadic integer exactly representable in float.
// Rows of the stored stiffness then sum to exactly zero, so constants stay exactly in the
// null space in float32 too; right-hand sides must be multiplied by kScale to match.
// Per column: sx[d + 2][i], mx[d + 2][i]; per row: my[j][d + 2], cy[j][d + 2] (row tables:
// memory independent of the height).
template <class T>
struct LevelOperator {
  static constexpr double kScale = 720.0;
  // The per-pixel diagonal term standing for a pinned pixel (GuidanceRow::weight == kPinned):
  // about 1e6 times the largest finest-level diagonal, so a pinned pixel moves by less than 1e-6
  // of the neighbouring differences, while D u and D value stay far from float's range.
  static constexpr double kPinnedDiagonal = 1073741824.0;  // 2^30

  int width = 0, height = 0;
  bool periodic_x = false;
  std::array<std::vector<T>, 5> sx, mx;
  fem::RowTable<std::array<T, 5>> my, cy;
  // Row j's neighbour at offset d - 2 (d = 0..4), or -1 where the operator has no coupling.
  int row_of(int j, int d) const {
    const int r = offsets_[j][d];
    return r == kNone ? -1 : j + r;
  }
  // Whether that row is read mirrored left to right (the top and bottom rows of a spherical
  // domain); the kernels handle it, schedules just hand over row_of's rows.
  fem::Mirror mirror_of(int j, int d) const { return mirrors_[j][d]; }
  const std::array<fem::Mirror, 5>& mirrors(int j) const { return mirrors_[j]; }
  // Columns [interior_begin, interior_end) share one symmetric x stencil (sx_in, mx_in), so
  // the kernels may use a constant-coefficient loop there.
  int interior_begin = 0, interior_end = 0;
  std::array<T, 3> sx_in{}, mx_in{};  // centre, +-1, +-2

  LevelOperator(const LevelGeometry& g, double alpha);

 private:
  static constexpr int kNone = 1 << 30;
  fem::RowTable<std::array<int, 5>> offsets_;  // row_of(j, d) - j, or kNone
  fem::RowTable<std::array<fem::Mirror, 5>> mirrors_;
};

}  // namespace gdp::multigrid
