// The half-float policy of a solve and the one float <-> half conversion every schedule uses.
#include "multigrid/half_policy.h"
#include "util/clones.h"

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


template <class T>
GDP_CLONES void to_half(const T* in, _Float16* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<_Float16>(in[i]);
}
template <class T>
GDP_CLONES void from_half(const _Float16* in, T* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<T>(in[i]);
}
template <class T>
GDP_CLONES void round_to_half(T* p, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<T>(static_cast<_Float16>(p[i]));
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
