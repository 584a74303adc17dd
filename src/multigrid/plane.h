// A single-channel 2D array of samples, the unit the solver works on per level.
#pragma once

#include <cstddef>
#include <vector>

#include "util/big_pages.h"

namespace gdp::multigrid {

template <class T>
struct Plane {
  int width = 0;
  int height = 0;
  util::BigVector<T> data;  // a large plane in huge pages (util/big_pages.h)
  // Where not empty: row j's samples are row rows_of[j] of `data` (equal rows held once; `height` counts
  // the rows held; multigrid::restrict_weights, read through weight_row()).
  std::vector<int> rows_of;

  Plane() = default;
  Plane(int w, int h) : width(w), height(h), data(static_cast<std::size_t>(w) * h, T(0)) {}
  // The same, a large plane's pages all mapped in one call before the zero fill touches them
  // (util::populate; docs/multigrid.md, "In-core allocation").
  static Plane mapped(int w, int h) {
    Plane p = reserved(w, h);
    p.make_rows(h);
    return p;
  }
  // Room for a w x h plane, nothing touched yet: make_rows() makes its rows, in order, so that
  // another thread may fill the rows made meanwhile (row() of a row made stays where it is).
  static Plane reserved(int w, int h) {
    Plane p;
    p.width = w, p.height = h;
    p.data.reserve(static_cast<std::size_t>(w) * h);
    return p;
  }
  // Rows [0, rows) made: those not made yet mapped in one call (a large plane's) and zeroed.
  void make_rows(int rows) {
    const std::size_t n = static_cast<std::size_t>(rows) * width, made = data.size();
    if (n <= made) return;
    if (data.capacity() * sizeof(T) >= util::kBigBuffer) util::populate(data.data() + made, (n - made) * sizeof(T));
    data.resize(n, T(0));  // (within the capacity reserved: no reallocation)
  }
  T* row(int j) { return data.data() + static_cast<std::size_t>(j) * width; }
  const T* row(int j) const { return data.data() + static_cast<std::size_t>(j) * width; }
  T& at(int i, int j) { return row(j)[i]; }
  T at(int i, int j) const { return row(j)[i]; }
};

}  // namespace gdp::multigrid
