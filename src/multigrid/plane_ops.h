// Whole-plane loops over the window kernels (apply, residual) and the windows of a plane's rows.
#pragma once

#include <cmath>

#include "multigrid/hierarchy.h"
#include "multigrid/plane.h"
#include "multigrid/window_ops.h"

namespace gdp::multigrid {

// Row j's window over a level stored row by row at `u` (op.width samples a row), or in a plane.
template <class T>
Window<T> window(const LevelOperator<T>& op, const T* u, int j) {
  Window<T> w;
  for (int d = 0; d < 5; ++d)
    if (const int r = op.row_of(j, d); r >= 0) w.rows[d] = u + static_cast<std::size_t>(r) * op.width;
  return w;
}

template <class T>
Window<T> window(const LevelOperator<T>& op, const Plane<T>& u, int j) { return window(op, u.data.data(), j); }

// The whole row of a level.
template <class T>
Columns whole_row(const LevelOperator<T>& op) { return Columns::whole(op.width, op.periodic_x); }

// Row j of an optional per-pixel diagonal term (window_ops.h).
template <class T>
const T* diag_row(const Plane<T>* diag, int j) { return diag ? diag->row(j) : nullptr; }

// The kernels on every row: out = A u, r = b - A u (A + D with a diagonal term).
template <class T>
void apply(const LevelOperator<T>& op, const Plane<T>& u, Plane<T>& out, Scratch<T>& s,
           const Plane<T>* diag = nullptr) {
  for (int j = 0; j < op.height; ++j) apply(op, j, window(op, u, j), whole_row(op), out.row(j), s, diag_row(diag, j));
}

template <class T>
void residual(const LevelOperator<T>& op, const Plane<T>& u, const Plane<T>& b, Plane<T>& r,
              Scratch<T>& s, const Plane<T>* diag = nullptr) {
  for (int j = 0; j < op.height; ++j)
    residual(op, j, window(op, u, j), whole_row(op), b.row(j), r.row(j), s, diag_row(diag, j));
}

template <class T>
double norm2(const Plane<T>& p) {
  double s = 0.0;
  for (T v : p.data) s += static_cast<double>(v) * v;
  return std::sqrt(s);
}

}  // namespace gdp::multigrid
