// Whole-plane loops over the window kernels: apply, residual, sweeps (the in-core schedule's parts).
#pragma once

#include <cmath>

#include "multigrid/hierarchy.h"
#include "multigrid/plane.h"
#include "multigrid/window_ops.h"

namespace gdp::multigrid {

// Row j's window over a level stored row by row at `u` (op.width samples a row).
template <class T>
Window<T> window(const LevelOperator<T>& op, const T* u, int j) {
  Window<T> w;
  for (int d = 0; d < 5; ++d) {
    const int r = op.row_of(j, d);
    w.rows[d] = r < 0 ? nullptr : u + static_cast<std::size_t>(r) * op.width;
  }
  return w;
}

template <class T>
Window<T> window(const LevelOperator<T>& op, const Plane<T>& u, int j) {
  return window(op, u.data.data(), j);
}

// The whole row of a level.
template <class T>
Columns whole_row(const LevelOperator<T>& op) {
  return Columns::whole(op.width, op.periodic_x);
}

// Row j of an optional per-pixel diagonal term (window_ops.h).
template <class T>
const T* diag_row(const Plane<T>* diag, int j) {
  return diag ? diag->row(j) : nullptr;
}

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

// k lexicographic Gauss-Seidel sweeps, top to bottom.
template <class T>
void relax(const LevelOperator<T>& op, Plane<T>& u, const Plane<T>& b, int sweeps, Scratch<T>& s,
           const Plane<T>* diag = nullptr) {
  for (int k = 0; k < sweeps; ++k)
    for (int j = 0; j < op.height; ++j)
      relax(op, j, window(op, u, j), whole_row(op), u.row(j), b.row(j), s, diag_row(diag, j));
}

template <class T>
double norm2(const Plane<T>& p) {
  double s = 0.0;
  for (T v : p.data) s += static_cast<double>(v) * v;
  return std::sqrt(s);
}

}  // namespace gdp::multigrid
