// The multigrid kernels on a range of columns of a row (a band's part), for the band schedule.
//
// Like row_ops.h, but a row is held only in part: rows[d][i - origin[d]] is column i of row
// j + d - 2 (global column numbers; on periodic levels i may lie outside [0, width) and the
// caller stores the wrapped values there). A mirrored row (LevelOperator::mirror_of) is read
// at mirror_column(wrap(i)), so its storage must hold those columns. Kernels read columns
// [i0 - 2, i1 + 2) of the window and touch only [i0, i1) of their output.
#pragma once

#include <array>
#include <vector>

#include "multigrid/hierarchy.h"

namespace gdp::multigrid {

template <class T>
struct BandWindow {
  std::array<const T*, 5> rows{};  // null where the operator has no coupling
  std::array<int, 5> origin{};     // the global column of rows[d][0]
};

// Temporary rows and per-column recurrence coefficients (one per thread).
template <class T>
struct BandScratch {
  std::vector<T> a, c, q, dx, t, zero;
  std::vector<T> sums;  // restrict_columns' coarse sums
  struct Coefficients {  // per global column, for one level and one (m0, c0) pair
    const void* op = nullptr;
    T m0{}, c0{};
    std::vector<T> inv, k[5];  // k[d][i] = K_{d-2}(i) / K_0(i)
    // The recurrence four samples at a time over blocks [4q, 4q + 3] (as relax_row): the terms
    // multiplying the two corrections carried into a block, forward and backward.
    std::vector<T> fb, fc, bb, bc;
  };
  std::vector<Coefficients> cached;  // a few, most recent last
  const Coefficients& coefficients(const LevelOperator<T>& op, T m0, T c0);
};

// out[i - out_origin] = (b - A u)[i] on row j for i in [i0, i1); b is read at b[i - out_origin].
// `diag` (optional, indexed like b) is row_ops.h's per-pixel diagonal term.
template <class T>
void residual_columns(const LevelOperator<T>& op, int j, const BandWindow<T>& w, const T* b, T* out,
                      int out_origin, int i0, int i1, BandScratch<T>& s, const T* diag = nullptr);

// One Gauss-Seidel sweep over columns [i0, i1) of row j, left to right (forward) or right to
// left: u is row j itself (u[i - origin[2]]), updated in place; b is read like u.
template <class T>
void relax_columns(const LevelOperator<T>& op, int j, const BandWindow<T>& w, T* u, const T* b, int i0,
                   int i1, bool forward, BandScratch<T>& s, const T* diag = nullptr);

// Restriction of fine row j, known at fine columns [f0, f1) (fine[i - fine_origin]), into
// coarse columns [c0, c1) of the coarse rows py.index[0] and [1] (coarse_k[i - coarse_origin[k]];
// the second mirrored where py.mirror says so, in which case coarse1 must hold the mirrored
// columns, e.g. a whole row with origin 0). Only contributions from the given fine columns are added.
template <class T>
void restrict_columns(const fem::Prolongation& px, const fem::ProlongationRow& py, bool periodic,
                      const T* fine, int fine_origin, int f0, int f1, T* coarse0, T* coarse1,
                      std::array<int, 2> coarse_origin, int c0, int c1, BandScratch<T>& s);

// Prolongation added into fine row j at columns [f0, f1) from the coarse rows py.index[0] and
// [1], each held at coarse[J - coarse_origin[k]] for the columns the fine ones read. With
// `coarse_whole` the coarse rows are whole rows [0, m) (origins 0) and periodic columns wrap
// into them; otherwise they hold a band's columns with halo, periodic ones unwrapped.
template <class T>
void prolong_columns(const fem::Prolongation& px, const fem::ProlongationRow& py, bool periodic,
                     const T* coarse0, const T* coarse1, std::array<int, 2> coarse_origin, bool coarse_whole,
                     T* fine, int fine_origin, int f0, int f1);

}  // namespace gdp::multigrid
