// Input-pass row kernels: each compiled for x86-64-v3 (AVX2) and the baseline, the loader picking one.
#include "multigrid/input_kernels.h"

#include <cstdint>
#include <cstring>

namespace gdp::multigrid {

// This file is compiled with -ffp-contract=off (src/CMakeLists.txt): no multiply-add is fused, so
// both clones give the bits of the plain loops.
#define GDP_INPUT_KERNEL __attribute__((target_clones("arch=x86-64-v3", "default")))

// The masks as 64-bit integers, one per sample: with bools, the compiler packs them into bytes and
// back (twice the time).
GDP_INPUT_KERNEL void kept_differences(const float* from, const float* to, const unsigned char* keep, double beta,
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
GDP_INPUT_KERNEL void scaled_rhs(const double* v, const double* add, double scale, T* out, int n) {
  if (add)
    for (int i = 0; i < n; ++i) out[i] = static_cast<T>(scale * v[i] + add[i]);
  else  // + 0.0 as the sum with a zero row: -0.0 becomes +0.0
    for (int i = 0; i < n; ++i) out[i] = static_cast<T>(scale * v[i] + 0.0);
}

template void scaled_rhs<float>(const double*, const double*, double, float*, int);
template void scaled_rhs<double>(const double*, const double*, double, double*, int);

}  // namespace gdp::multigrid
