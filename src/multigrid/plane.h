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
    Plane p;
    p.width = w, p.height = h;
    const std::size_t n = static_cast<std::size_t>(w) * h;
    p.data.reserve(n);
    if (n * sizeof(T) >= util::kBigBuffer) util::populate(p.data.data(), n * sizeof(T));
    p.data.resize(n, T(0));
    return p;
  }
  T* row(int j) { return data.data() + static_cast<std::size_t>(j) * width; }
  const T* row(int j) const { return data.data() + static_cast<std::size_t>(j) * width; }
  T& at(int i, int j) { return row(j)[i]; }
  T at(int i, int j) const { return row(j)[i]; }
};

}  // namespace gdp::multigrid
