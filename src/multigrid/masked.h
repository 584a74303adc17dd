// A branch-free select of a floating-point value or +0, which loops vectorise.
#pragma once

#include <cstdint>
#include <cstring>
#include <type_traits>

namespace gdp::multigrid {

// v where ok, else +0 (the same bits as `ok ? v : T(0)`), without a branch: the compiler
// vectorises loops of it, where a conditional on a floating-point test is left scalar under
// -ftrapping-math. With `finite(v)` (v - v == 0 exactly when v is finite) it replaces the
// std::isfinite tests that keep a loop scalar.
template <class T>
inline T masked(T v, bool ok) {
  using Bits = std::conditional_t<sizeof(T) == 8, std::uint64_t, std::uint32_t>;
  Bits bits;
  std::memcpy(&bits, &v, sizeof bits);
  bits &= -static_cast<Bits>(ok);
  std::memcpy(&v, &bits, sizeof bits);
  return v;
}

template <class T>
inline bool finite(T v) {
  return v - v == T(0);
}

// f(x) for each x in [begin, end) where flags[x] is set, skipping eight clear flags at a time
// (flags that are mostly clear: seams, marked edges).
template <class F>
inline void for_each_set(const unsigned char* flags, int begin, int end, F&& f) {
  for (int x = begin; x < end; ++x) {
    if (x % 8 == 0 && x + 8 <= end) {
      std::uint64_t any;
      std::memcpy(&any, flags + x, sizeof any);
      if (any == 0) {
        x += 7;
        continue;
      }
    }
    if (flags[x]) f(x);
  }
}

}  // namespace gdp::multigrid
