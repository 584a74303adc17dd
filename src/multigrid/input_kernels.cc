// Input-pass row kernels: each compiled for x86-64-v3 (AVX2) and the baseline, the loader picking one.
#include "multigrid/input_kernels.h"

#include "multigrid/masked.h"

namespace gdp::multigrid {

// This file is compiled with -ffp-contract=off (src/CMakeLists.txt): no multiply-add is fused, so
// both clones give the bits of the plain loops.
#define GDP_INPUT_KERNEL __attribute__((target_clones("arch=x86-64-v3", "default")))

GDP_INPUT_KERNEL void kept_differences(const float* from, const float* to, const unsigned char* keep, double beta,
                                       double* out, int n) {
  for (int i = 0; i < n; ++i) {
    const double d = double(to[i]) - from[i];
    out[i] = masked(beta * d, finite(d) & (keep[i] != 0));
  }
}

}  // namespace gdp::multigrid
