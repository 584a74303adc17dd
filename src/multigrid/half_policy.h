// Which of a V-cycle's stored quantities are rounded to 16-bit floats: part of the numerics, applied alike by every schedule.
#pragma once

#include <cstddef>
#include <map>
#include <string>

#include "gdp/solver.h"

namespace gdp::multigrid {

// A quantity is named as its store is: "level3-u", "level0-b", "level0-w", or "result" (the
// answer carried from one V-cycle to the next). Keys name a quantity by its last parts: "u"
// (every level's u), "level0-u" (the finest only); the longest key that matches wins, else `all`.
// The in-core V-cycle rounds a level's u and b in place after its restriction (where the
// streamed V-cycle stores them), so every schedule rounds the same values at the same points
// and they agree bit for bit (docs/how-streaming-works.md, "Which quantities can be half floats").
struct HalfPolicy {
  bool all = false;
  std::map<std::string, bool> named;

  bool rounds(const std::string& name) const;
  // Level l's quantity q ("u", "b", "w").
  bool rounds(int level, const char* q) const;
  bool any() const;
};

// The policy `opt` asks for: ScratchPrecision::Narrow is every quantity but the finest b and u
// when more than one V-cycle may run (later cycles would solve a rounded problem, and be no more
// accurate than one) and the carried result when iterating to a tolerance (then it may be the
// answer); half_quantities add to it. With a per-pixel diagonal term (`diagonal`: weights or pins)
// no level's b is rounded (nor, ever, the diagonal d itself): a pinned pixel's entry (kPinnedDiagonal times its value, and the
// residuals restricted from it) is far beyond a half float's range.
HalfPolicy half_policy(const SolverOptions& opt, bool diagonal);

// Samples to and from 16-bit floats (round to nearest even) and both in place: the one
// conversion that stores and the in-core V-cycle share.
template <class T>
void to_half(const T* in, _Float16* out, std::size_t n);
template <class T>
void from_half(const _Float16* in, T* out, std::size_t n);
template <class T>
void round_to_half(T* p, std::size_t n);

}  // namespace gdp::multigrid
