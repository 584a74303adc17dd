// Whole-plane loops over the row kernels: apply, residual, sweeps (the in-core schedule's parts).
#pragma once

#include <cmath>

#include "multigrid/hierarchy.h"
#include "multigrid/plane.h"
#include "multigrid/row_ops.h"

namespace gdp::multigrid {

// Row j's window over a level stored row by row at `u` (op.width samples a row).
template <class T>
RowWindow<T> window(const LevelOperator<T>& op, const T* u, int j) {
  RowWindow<T> w{};
  for (int d = 0; d < 5; ++d) {
    const int r = op.row_of(j, d);
    w[d] = r < 0 ? nullptr : u + static_cast<std::size_t>(r) * op.width;
  }
  return w;
}

template <class T>
RowWindow<T> window(const LevelOperator<T>& op, const Plane<T>& u, int j) {
  return window(op, u.data.data(), j);
}

// Row j of an optional per-pixel diagonal term (row_ops.h).
template <class T>
const T* diag_row(const Plane<T>* diag, int j) {
  return diag ? diag->row(j) : nullptr;
}

template <class T>
void apply(const LevelOperator<T>& op, const Plane<T>& u, Plane<T>& out, RowScratch<T>& s,
           const Plane<T>* diag = nullptr) {
  for (int j = 0; j < op.height; ++j) apply_row(op, j, window(op, u, j), out.row(j), s, diag_row(diag, j));
}

template <class T>
void residual(const LevelOperator<T>& op, const Plane<T>& u, const Plane<T>& b, Plane<T>& r,
              RowScratch<T>& s, const Plane<T>* diag = nullptr) {
  for (int j = 0; j < op.height; ++j)
    residual_row(op, j, window(op, u, j), b.row(j), r.row(j), s, diag_row(diag, j));
}

// k lexicographic Gauss-Seidel sweeps, top to bottom.
template <class T>
void relax(const LevelOperator<T>& op, Plane<T>& u, const Plane<T>& b, int sweeps, RowScratch<T>& s,
           const Plane<T>* diag = nullptr) {
  for (int k = 0; k < sweeps; ++k)
    for (int j = 0; j < op.height; ++j)
      relax_row(op, j, window(op, u, j), u.row(j), b.row(j), s, diag_row(diag, j));
}

template <class T>
double norm2(const Plane<T>& p) {
  double s = 0.0;
  for (T v : p.data) s += static_cast<double>(v) * v;
  return std::sqrt(s);
}

}  // namespace gdp::multigrid
