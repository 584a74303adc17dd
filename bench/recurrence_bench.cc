// The relax recurrence's block loops (window_ops.cc) on one 8192 row against restructurings of them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#if defined(__x86_64__)
#include <immintrin.h>
#endif
#include <random>
#include <vector>

#include "util/seconds.h"

// The loops are compiled for x86-64-v3 (AVX2 + FMA), like the kernels' clone that runs on this machine.
#if defined(__x86_64__)
#pragma GCC push_options
#pragma GCC target("arch=x86-64-v3")
namespace {

constexpr int kN = 8192;
constexpr float kK1 = 0.3f, kK2 = -0.05f;  // K_{-1}/K_0, K_{-2}/K_0 of a diagonally dominant interior stencil

struct Row {
  std::vector<float> t, kn, kf, B, C;
};

// dx = t - kn dx[-1] - kf dx[-2] on N rows at once, blocks of four as relax does them: each sample its
// in-block part plus B d1 + C d2 of the corrections before the block. N = 1 is relax's loop; N = 3 puts
// three independent chains (three channels) in one loop body.
template <int N>
__attribute__((noinline)) void blocks4(const Row& k, const float* const* t, float* const* out) {
  float d1[N] = {}, d2[N] = {};
  const float *kn = k.kn.data(), *kf = k.kf.data(), *B = k.B.data(), *C = k.C.data();
  for (int x = 0; x + 4 <= kN; x += 4)
    for (int c = 0; c < N; ++c) {
      const float* tc = t[c];
      const float a0 = tc[x], a1 = tc[x + 1] - kn[x + 1] * a0;
      const float a2 = tc[x + 2] - kn[x + 2] * a1 - kf[x + 2] * a0;
      const float a3 = tc[x + 3] - kn[x + 3] * a2 - kf[x + 3] * a1;
      float* o = out[c];
      o[x] += a0 + B[x] * d1[c] + C[x] * d2[c];
      o[x + 1] += a1 + B[x + 1] * d1[c] + C[x + 1] * d2[c];
      const float n2 = a2 + B[x + 2] * d1[c] + C[x + 2] * d2[c], n1 = a3 + B[x + 3] * d1[c] + C[x + 3] * d2[c];
      o[x + 2] += n2, o[x + 3] += n1;
      d2[c] = n2, d1[c] = n1;
    }
}

// The same arithmetic as three passes per chunk of 16 blocks: in-block parts (vectorised across blocks),
// the serial two-multiply-add chain, the outputs (vectorised). Bit-identical to blocks4<1>.
__attribute__((noinline)) void split(const Row& k, const float* __restrict t, float* __restrict out, float* __restrict a,
                                     float* __restrict e1, float* __restrict e2) {
  const float *__restrict kn = k.kn.data(), *__restrict kf = k.kf.data(), *__restrict B = k.B.data(),
              *__restrict C = k.C.data();
  float d1 = 0, d2 = 0;
  for (int x0 = 0; x0 < kN; x0 += 64) {
    const int x1 = std::min(kN, x0 + 64);
    for (int x = x0; x < x1; x += 4) {
      a[x] = t[x], a[x + 1] = t[x + 1] - kn[x + 1] * a[x];
      a[x + 2] = t[x + 2] - kn[x + 2] * a[x + 1] - kf[x + 2] * a[x];
      a[x + 3] = t[x + 3] - kn[x + 3] * a[x + 2] - kf[x + 3] * a[x + 1];
    }
    for (int x = x0; x < x1; x += 4) {
      for (int r = 0; r < 4; ++r) e1[x + r] = d1, e2[x + r] = d2;
      const float n2 = a[x + 2] + B[x + 2] * d1 + C[x + 2] * d2, n1 = a[x + 3] + B[x + 3] * d1 + C[x + 3] * d2;
      d2 = n2, d1 = n1;
    }
    for (int x = x0; x < x1; ++x) out[x] += a[x] + B[x] * e1[x] + C[x] * e2[x];
  }
}

// Changes the rounding: blocks of 8 with constant coefficients, the in-block part as a precomputed
// lower-triangular matrix (H[s]: its column s; 8 broadcast multiply-adds), a scalar chain on the last two
// samples, the outputs as two vector multiply-adds off the chain.
typedef float v8 __attribute__((vector_size(32)));
__attribute__((noinline)) void blocks8(const float* t, const v8* H, const v8& Bv, const v8& Cv, float* out) {
  float d1 = 0, d2 = 0;
  for (int x = 0; x + 8 <= kN; x += 8) {
    v8 A = H[0] * t[x];
    for (int s = 1; s < 8; ++s) A += H[s] * t[x + s];
    const float n1 = A[7] + Bv[7] * d1 + Cv[7] * d2, n2 = A[6] + Bv[6] * d1 + Cv[6] * d2;
    v8 o;
    std::memcpy(&o, out + x, sizeof o);
    o += A + Bv * d1 + Cv * d2;
    std::memcpy(out + x, &o, sizeof o);
    d1 = n1, d2 = n2;
  }
}

// Blocks of 8 with the chain kept in vectors: the carried lanes broadcast by a lane permute (vpermps) instead
// of two scalar multiply-adds each; the same bits as blocks8, but the permute lengthens the chain.
__attribute__((noinline)) void blocks8_vector_chain(const float* t, const v8* H, const v8& Bv, const v8& Cv,
                                                    float* out) {
  const __m256i last = _mm256_set1_epi32(7), before = _mm256_set1_epi32(6);
  v8 D1 = {}, D2 = {};
  for (int x = 0; x + 8 <= kN; x += 8) {
    v8 A = H[0] * t[x];
    for (int s = 1; s < 8; ++s) A += H[s] * t[x + s];
    const v8 n = A + Bv * D1 + Cv * D2;
    D1 = v8(_mm256_permutevar8x32_ps(__m256(n), last)), D2 = v8(_mm256_permutevar8x32_ps(__m256(n), before));
    v8 o;
    std::memcpy(&o, out + x, sizeof o);
    o += n;
    std::memcpy(out + x, &o, sizeof o);
  }
}

// Changes the rounding: blocks of 8, one chain step per two blocks (the state after the second block
// from the state before the first by the squared 2x2 step; the first block's last lanes off the chain).
__attribute__((noinline)) void blocks8_two_per_step(const float* t, const v8* H, const v8& Bv, const v8& Cv,
                                                    float* out) {
  const float b7 = Bv[7], c7 = Cv[7], b6 = Bv[6], c6 = Cv[6];
  const float m11 = b7 * b7 + c7 * b6, m12 = b7 * c7 + c7 * c6, m21 = b6 * b7 + c6 * b6, m22 = b6 * c7 + c6 * c6;
  float d1 = 0, d2 = 0;
  for (int x = 0; x + 16 <= kN; x += 16) {
    v8 A = H[0] * t[x], Z = H[0] * t[x + 8];
    for (int s = 1; s < 8; ++s) A += H[s] * t[x + s], Z += H[s] * t[x + 8 + s];
    const float k1 = Z[7] + b7 * A[7] + c7 * A[6], k2 = Z[6] + b6 * A[7] + c6 * A[6];
    const float a7 = A[7] + b7 * d1 + c7 * d2, a6 = A[6] + b6 * d1 + c6 * d2;
    v8 o, p;
    std::memcpy(&o, out + x, sizeof o), std::memcpy(&p, out + x + 8, sizeof p);
    o += A + Bv * d1 + Cv * d2, p += Z + Bv * a7 + Cv * a6;
    std::memcpy(out + x, &o, sizeof o), std::memcpy(out + x + 8, &p, sizeof p);
    const float n1 = k1 + m11 * d1 + m12 * d2, n2 = k2 + m21 * d1 + m22 * d2;
    d1 = n1, d2 = n2;
  }
}

// The responses of a block of `n` to d1 and d2 entering it (window_ops' fill()).
void responses(float* B, float* C, int n) {
  B[0] = -kK1, C[0] = -kK2, B[1] = -kK1 * B[0] - kK2, C[1] = -kK1 * C[0];
  for (int r = 2; r < n; ++r) B[r] = -kK1 * B[r - 1] - kK2 * B[r - 2], C[r] = -kK1 * C[r - 1] - kK2 * C[r - 2];
}

template <class F>
double ns_per_sample(F f, int channels) {  // minimum of 30 trials of 100 rows
  double best = 1e30;
  for (int k = 0; k < 30; ++k) {
    const double t0 = gdp::util::thread_cpu_seconds();
    for (int r = 0; r < 100; ++r) f();
    best = std::min(best, gdp::util::thread_cpu_seconds() - t0);
  }
  return best * 1e9 / (100.0 * kN * channels);
}

// Prints CPU ns per sample (per channel) of each loop, minimum of 30 trials, and the largest difference
// of each restructuring's corrections from relax's (0: bit-identical). The caller has checked for AVX2 + FMA.
void run() {
  Row k{std::vector<float>(kN), std::vector<float>(kN, kK1), std::vector<float>(kN, kK2), std::vector<float>(kN),
        std::vector<float>(kN)};
  std::vector<float> t[3], o[3], a(kN), e1(kN), e2(kN), ref(kN);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> d(-1.f, 1.f);
  for (int c = 0; c < 3; ++c) {
    t[c].resize(kN), o[c].assign(kN, 0.f);
    for (float& v : t[c]) v = d(rng);
  }
  for (int b = 0; b < kN; b += 4) responses(k.B.data() + b, k.C.data() + b, 4);
  float h[8] = {1, -kK1};
  for (int r = 2; r < 8; ++r) h[r] = -kK1 * h[r - 1] - kK2 * h[r - 2];
  v8 H[8], Bv, Cv;
  for (int s = 0; s < 8; ++s)
    for (int r = 0; r < 8; ++r) H[s][r] = r >= s ? h[r - s] : 0.f;
  float bv[8], cv[8];
  responses(bv, cv, 8);
  std::memcpy(&Bv, bv, sizeof Bv), std::memcpy(&Cv, cv, sizeof Cv);
  const float* tp[3] = {t[0].data(), t[1].data(), t[2].data()};
  float* op[3] = {o[0].data(), o[1].data(), o[2].data()};
  const auto diff_from = [&](const std::vector<float>& r, auto f) {
    std::vector<float> out(kN, 0.f);
    f(out.data());
    float m = 0;
    for (int i = 0; i < kN; ++i) m = std::max(m, std::fabs(out[i] - r[i]));
    return m;
  };
  const auto diff = [&](auto f) { return diff_from(ref, f); };
  float* rp[1] = {ref.data()};
  blocks4<1>(k, tp, rp);
  const float split_diff = diff([&](float* out) { split(k, tp[0], out, a.data(), e1.data(), e2.data()); });
  const float vec_diff = diff([&](float* out) { blocks8(tp[0], H, Bv, Cv, out); });
  std::vector<float> ref8(kN, 0.f);
  blocks8(tp[0], H, Bv, Cv, ref8.data());
  const auto diff8 = [&](auto f) { return diff_from(ref8, f); };
  std::printf("CPU ns per sample, minimum of 30 trials; max difference from relax's loop (blocks of 4 by the\n"
              "level's ends and with a per-pixel diagonal, blocks of 8 on the interior)\n");
  std::printf("blocks of 4 (relax, ends)      %.3f\n", ns_per_sample([&] { blocks4<1>(k, tp, op); }, 1));
  std::printf("three chains in one loop       %.3f  (bit-identical)\n",
              ns_per_sample([&] { blocks4<3>(k, tp, op); }, 3));
  std::printf("split passes, chunks of 16     %.3f  %.3g\n",
              ns_per_sample([&] { split(k, tp[0], op[0], a.data(), e1.data(), e2.data()); }, 1), split_diff);
  std::printf("vector blocks of 8 (interior)  %.3f  %.3g\n", ns_per_sample([&] { blocks8(tp[0], H, Bv, Cv, op[0]); }, 1),
              vec_diff);
  std::printf("  8, chain as vectors          %.3f  %.3g from blocks of 8\n",
              ns_per_sample([&] { blocks8_vector_chain(tp[0], H, Bv, Cv, op[0]); }, 1),
              diff8([&](float* out) { blocks8_vector_chain(tp[0], H, Bv, Cv, out); }));
  std::printf("  8, two blocks per chain step %.3f  %.3g from blocks of 8\n",
              ns_per_sample([&] { blocks8_two_per_step(tp[0], H, Bv, Cv, op[0]); }, 1),
              diff8([&](float* out) { blocks8_two_per_step(tp[0], H, Bv, Cv, out); }));
}

}  // namespace
#pragma GCC pop_options
#endif

// The figures where the CPU can run the loops.
int main() {
#if defined(__x86_64__)
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return run(), 0;
#endif
  std::printf("recurrence_bench: needs an x86-64 CPU with AVX2 + FMA (x86-64-v3)\n");
  return 0;
}
