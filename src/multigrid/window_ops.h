// The multigrid kernels on a column window of one row: operator, residual, relaxation, transfers
// (docs/multigrid.md). Every schedule calls them, on whole rows or on a band's columns.
#pragma once

#include <algorithm>
#include <array>
#include <vector>

#include "fem/axis.h"
#include "multigrid/hierarchy.h"

namespace gdp::multigrid {

// Columns [begin, end) of a level n columns wide (on periodic levels they may leave [0, n)). Beyond their
// ends: nothing at a non-periodic level's ends (read as zeros); the row's other end on a whole periodic row
// (`wrap`: relax closes the ring as a whole-row sweep does); else more of the row, held by the window (a
// neighbour band's columns; on periodic levels unwrapped, holding the wrapped values).
struct Columns {
  int begin = 0, end = 0;
  bool periodic = false, wrap = false, forward = true;  // forward: relax left to right, else right to left
  static Columns whole(int n, bool periodic) { return {0, n, periodic, periodic, true}; }
  // [begin, end), clipped to [0, n) on a non-periodic level.
  static Columns range(int n, bool periodic, int begin, int end, bool forward = true) {
    return {periodic ? begin : std::max(begin, 0), periodic ? end : std::min(end, n), periodic, false, forward};
  }
};

// Rows j-2 .. j+2 of one channel: rows[d][i - origin[d]] is column i of row j + d - 2, null where
// the operator has no coupling (row_of); a row read mirrored (mirror_of) is held whole, [0, n).
// The kernels read columns [begin - 2, end + 2) (within non-periodic levels); the row's own
// arrays (u, b, out, diag) are indexed like rows[2]: x[i - origin[2]].
template <class T>
struct Window { std::array<const T*, 5> rows{}; std::array<int, 5> origin{}; };

// Temporary rows, one set per thread, grown to the widest call and reused (kn, kf: relax's per-column terms).
template <class T>
struct Scratch {
  std::vector<T> a, c, q, line, kn, kf;
  std::array<std::vector<T>, 5> mirrored;
};

// apply: out = (A u) on row j; residual: r = b - (A u). `diag`: an optional per-pixel diagonal term
// (row j of D, the lumped fidelity weights scaled like A, docs/weights.md): the operator is A + D.
template <class T>
void apply(const LevelOperator<T>& op, int j, const Window<T>& w, Columns cols, T* out, Scratch<T>& s,
           const T* diag = nullptr);
template <class T>
void residual(const LevelOperator<T>& op, int j, const Window<T>& w, Columns cols, const T* b, T* r,
              Scratch<T>& s, const T* diag = nullptr);

// One Gauss-Seidel sweep over the columns of row j in cols.forward's direction: u (rows[2]) is
// updated in place from the newest values of the row itself and whatever the window holds.
template <class T>
void relax(const LevelOperator<T>& op, int j, const Window<T>& w, Columns cols, T* u, const T* b, Scratch<T>& s,
           const T* diag = nullptr);

// Restriction (P^T) of a fine row into coarse columns `cols` of the coarse rows py.index[0] and [1]
// (coarse_k[J - origin[k]]; the second mirrored where py.mirror says so, then held whole). fine[i -
// fine_origin] holds fine columns [2 begin - 1, 2 end + 1) (within non-periodic levels; whole where cols wrap).
template <class T>
void restrict_rows(const fem::Prolongation& px, const fem::ProlongationRow& py, const T* fine, int fine_origin,
                   Columns cols, T* coarse0, T* coarse1, std::array<int, 2> origin, Scratch<T>& s);

// Prolongation (P) added into fine columns `cols` (fine[i - fine_origin]) from the coarse rows py.index[0]
// and [1]: with `coarse_whole` they hold [0, m) (origins 0; periodic columns wrap into them), else the
// columns the fine ones read, like the fine row's halo.
template <class T>
void prolong_rows(const fem::Prolongation& px, const fem::ProlongationRow& py, const T* coarse0, const T* coarse1,
                  std::array<int, 2> origin, bool coarse_whole, Columns cols, T* fine, int fine_origin,
                  Scratch<T>& s);

}  // namespace gdp::multigrid
