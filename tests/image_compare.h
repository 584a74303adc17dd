// Comparisons of solved images shared by the schedule tests: same bits, value range.
#pragma once

#include <algorithm>
#include <cstring>

#include "gdp/image.h"

namespace gdp::test {

inline bool same_bits(const Image& a, const Image& b) {
  return a.data.size() == b.data.size() &&
         std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0;
}

inline double range_of(const Image& img) {
  const auto [lo, hi] = std::minmax_element(img.data.begin(), img.data.end());
  return double(*hi) - *lo;
}

}  // namespace gdp::test
