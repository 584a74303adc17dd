// The half-float policy of a solve and the one float <-> half conversion every schedule uses.
#include "multigrid/half_policy.h"
#include "util/clones.h"

#include <immintrin.h>

#include <type_traits>

#include <fmt/format.h>

namespace gdp::multigrid {

bool HalfPolicy::rounds(const std::string& name) const {
  std::size_t best = 0;
  bool chosen = all;
  for (const auto& [key, value] : named) {
    const bool ends = name.size() >= key.size() && name.compare(name.size() - key.size(), key.size(), key) == 0;
    const bool whole = ends && (name.size() == key.size() || name[name.size() - key.size() - 1] == '-');
    if (whole && key.size() > best) best = key.size(), chosen = value;
  }
  return chosen;
}

bool HalfPolicy::rounds(int level, const char* q) const { return rounds(fmt::format("level{}-{}", level, q)); }

bool HalfPolicy::any() const {
  if (all) return true;
  for (const auto& kv : named)
    if (kv.second) return true;
  return false;
}

HalfPolicy half_policy(const SolverOptions& opt, bool diagonal) {
  HalfPolicy p;
  if (opt.scratch == ScratchPrecision::Narrow) {
    p.all = true;
    // The finest b is the problem's data, kept for later V-cycles: as half floats it moves their
    // answer by 2e-3 of the range (100x one V-cycle's error; docs/how-streaming-works.md).
    // The finest u as half floats caps later cycles' error at about one cycle's (2.5e-5 of the
    // range against 6e-6) and stalls --tolerance near a relative residual of 2e-5: more V-cycles
    // are asked for accuracy, so both stay float then.
    if (opt.cycle_cap() > 1) p.named["level0-b"] = p.named["level0-u"] = false;
    // Iterating to a tolerance, the carried result is the answer when the next cycle is not run.
    if (opt.tolerance > 0.0) p.named["result"] = false;
    if (diagonal) p.named["b"] = p.named["level0-b"] = false;
  }
  for (const std::string& q : opt.half_quantities) p.named[q] = true;
  // The diagonal never: a pinned pixel's entry (kPinnedDiagonal) is beyond a half float's range.
  std::erase_if(p.named, [](const auto& kv) { return kv.first == "d" || kv.first.ends_with("-d"); });
  p.named["d"] = false;
  return p;
}


namespace {

// The plain casts (the loader picks the x86-64-v3 clone, F16C's conversions one sample at a time:
// GCC vectorises no _Float16 conversion).
template <class T>
GDP_CLONES void cast_to_half(const T* in, _Float16* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<_Float16>(in[i]);
}
template <class T>
GDP_CLONES void cast_from_half(const _Float16* in, T* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<T>(in[i]);
}
template <class T>
GDP_CLONES void cast_round(T* p, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<T>(static_cast<_Float16>(p[i]));
}

// Floats eight at a time with F16C: the instructions the casts use (vcvtps2ph in the current
// rounding mode, nearest even; vcvtph2ps exact), so the same bits.
[[gnu::target("avx,f16c")]] void f16c_to_half(const float* in, _Float16* out, std::size_t n) {
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8)
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), _mm256_cvtps_ph(_mm256_loadu_ps(in + i), _MM_FROUND_CUR_DIRECTION));
  for (; i < n; ++i) out[i] = static_cast<_Float16>(in[i]);
}
[[gnu::target("avx,f16c")]] void f16c_from_half(const _Float16* in, float* out, std::size_t n) {
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8)
    _mm256_storeu_ps(out + i, _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in + i))));
  for (; i < n; ++i) out[i] = static_cast<float>(in[i]);
}
[[gnu::target("avx,f16c")]] void f16c_round(float* p, std::size_t n) {
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8)
    _mm256_storeu_ps(p + i, _mm256_cvtph_ps(_mm256_cvtps_ph(_mm256_loadu_ps(p + i), _MM_FROUND_CUR_DIRECTION)));
  for (; i < n; ++i) p[i] = static_cast<float>(static_cast<_Float16>(p[i]));
}

bool has_f16c() {
  static const bool yes = (__builtin_cpu_init(), __builtin_cpu_supports("f16c"));
  return yes;
}

}  // namespace

template <class T>
void to_half(const T* in, _Float16* out, std::size_t n) {
  if constexpr (std::is_same_v<T, float>)
    if (has_f16c()) return f16c_to_half(in, out, n);
  cast_to_half(in, out, n);
}
template <class T>
void from_half(const _Float16* in, T* out, std::size_t n) {
  if constexpr (std::is_same_v<T, float>)
    if (has_f16c()) return f16c_from_half(in, out, n);
  cast_from_half(in, out, n);
}
template <class T>
void round_to_half(T* p, std::size_t n) {
  if constexpr (std::is_same_v<T, float>)
    if (has_f16c()) return f16c_round(p, n);
  cast_round(p, n);
}

template void to_half(const float*, _Float16*, std::size_t);
template void to_half(const double*, _Float16*, std::size_t);
template void to_half(const unsigned char*, _Float16*, std::size_t);  // flag stores (never half in practice)
template void from_half(const _Float16*, float*, std::size_t);
template void from_half(const _Float16*, double*, std::size_t);
template void from_half(const _Float16*, unsigned char*, std::size_t);
template void round_to_half(float*, std::size_t);
template void round_to_half(double*, std::size_t);

}  // namespace gdp::multigrid
