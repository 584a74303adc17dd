// Row kernels: each compiled for x86-64-v3 (AVX2) and the baseline, the loader picking one.
#include "multigrid/row_kernels.h"
#include "util/clones.h"

#include <cstdint>
#include <cstring>
#include <type_traits>

namespace gdp::multigrid {

// This file is compiled with -ffp-contract=off (src/CMakeLists.txt): no multiply-add is fused, so
// both clones give the bits of the plain loops.

// The masks as 64-bit integers, one per sample: with bools, the compiler packs them into bytes and
// back (twice the time).
GDP_CLONES void kept_differences(const float* from, const float* to, const unsigned char* keep, double beta,
                                   double* out, int n) {
  for (int i = 0; i < n; ++i) {
    const double d = double(to[i]) - from[i], v = beta * d;
    std::int64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    bits &= -static_cast<std::int64_t>(keep[i] != 0) & (d - d == 0.0 ? std::int64_t{-1} : 0);  // kept, finite
    std::memcpy(&out[i], &bits, sizeof bits);
  }
}

template <class T>
GDP_CLONES void scaled_rhs(const double* v, const double* add, double scale, T* out, int n) {
  if (add)
    for (int i = 0; i < n; ++i) out[i] = static_cast<T>(scale * v[i] + add[i]);
  else  // + 0.0 as the sum with a zero row: -0.0 becomes +0.0
    for (int i = 0; i < n; ++i) out[i] = static_cast<T>(scale * v[i] + 0.0);
}

template <class T>
GDP_CLONES void guess_and_weights(const float* in, std::size_t stride, int channels, const unsigned char* counted,
                                    T* u, T* w, int n) {
  using Bits = std::conditional_t<sizeof(T) == 8, std::int64_t, std::int32_t>;  // masks as wide as T (above)
  for (int i = 0; i < n; ++i) w[i] = static_cast<T>(counted[i] != 0);
  for (int c = 0; c < channels; ++c) {
    const float* inc = in + c * stride;
    T* uc = u + c * stride;
    for (int i = 0; i < n; ++i) {
      const T v = static_cast<T>(inc[i]);
      const Bits finite = v - v == T(0) ? Bits{-1} : Bits{0};
      Bits bits, weight;
      std::memcpy(&bits, &v, sizeof bits);
      std::memcpy(&weight, &w[i], sizeof weight);
      bits &= finite;
      weight &= finite;
      std::memcpy(&uc[i], &bits, sizeof bits);
      std::memcpy(&w[i], &weight, sizeof weight);
    }
  }
}

template void guess_and_weights<float>(const float*, std::size_t, int, const unsigned char*, float*, float*, int);
template void guess_and_weights<double>(const float*, std::size_t, int, const unsigned char*, double*, double*, int);
template <class T>
GDP_CLONES double row_dot(const T* w, const T* u, int n) {
  // Eight partial sums (a fixed order, so every schedule gets the same bits) let it vectorise.
  double s[8] = {};
  int i = 0;
  for (; i + 8 <= n; i += 8)
    for (int k = 0; k < 8; ++k) s[k] += static_cast<double>(w[i + k]) * u[i + k];
  for (; i < n; ++i) s[i % 8] += static_cast<double>(w[i]) * u[i];
  return ((s[0] + s[4]) + (s[1] + s[5])) + ((s[2] + s[6]) + (s[3] + s[7]));
}

// row_dot(r, r, n) with each sample converted once: the conversions, not the additions, bound row_dot (about
// 1.5x the time on this machine's Zen 4, docs/multigrid.md "Residual norms").
template <class T>
GDP_CLONES double row_squares(const T* r, int n) {
  double s[8] = {};
  int i = 0;
  for (; i + 8 <= n; i += 8)
    for (int k = 0; k < 8; ++k) {
      const double v = r[i + k];
      s[k] += v * v;
    }
  for (; i < n; ++i) {
    const double v = r[i];
    s[i % 8] += v * v;
  }
  return ((s[0] + s[4]) + (s[1] + s[5])) + ((s[2] + s[6]) + (s[3] + s[7]));
}

template double row_squares(const float*, int);
template double row_squares(const double*, int);
template double row_dot(const float*, const float*, int);
template double row_dot(const double*, const double*, int);
template void scaled_rhs<float>(const double*, const double*, double, float*, int);
template void scaled_rhs<double>(const double*, const double*, double, double*, int);

}  // namespace gdp::multigrid
