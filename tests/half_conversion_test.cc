// to_half, from_half and round_to_half (multigrid/half_policy.h) give the plain casts' bits, at every length.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "multigrid/half_policy.h"

namespace gdp::multigrid {
namespace {

std::uint16_t bits(_Float16 h) {
  std::uint16_t b;
  std::memcpy(&b, &h, sizeof b);
  return b;
}

// Floats at and beside every rounding boundary of the half floats (each half value, the midpoints
// between neighbours and one float ulp either side of them), beyond their range and below their
// subnormals, signed zeros, infinities; then random floats of every exponent.
std::vector<float> boundary_floats() {
  std::vector<float> v;
  for (std::uint32_t b = 0; b < 0x7c00; ++b) {
    _Float16 h, next;
    const std::uint16_t lo = static_cast<std::uint16_t>(b), hi = static_cast<std::uint16_t>(b + 1);
    std::memcpy(&h, &lo, sizeof h);
    std::memcpy(&next, &hi, sizeof next);
    const float mid = (static_cast<float>(h) + static_cast<float>(next)) / 2;
    for (float x : {static_cast<float>(h), mid, std::nextafter(mid, 0.0f), std::nextafter(mid, 1e30f)})
      v.insert(v.end(), {x, -x});
  }
  v.insert(v.end(), {70000.0f, -70000.0f, 1e-9f, -1e-9f, std::numeric_limits<float>::infinity(),
                     -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::max()});
  std::mt19937 rng(17);
  for (int i = 0; i < 100000; ++i) {
    const std::uint32_t b = rng() & 0xff7fffffu;  // no NaNs (their payloads are not compared)
    float x;
    std::memcpy(&x, &b, sizeof x);
    v.push_back(x);
  }
  return v;
}

TEST(HalfConversion, FloatsRoundAsTheCast) {
  const std::vector<float> in = boundary_floats();
  std::vector<_Float16> out(in.size());
  to_half(in.data(), out.data(), in.size());
  std::vector<float> round = in;
  round_to_half(round.data(), round.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    const _Float16 cast = static_cast<_Float16>(in[i]);
    ASSERT_EQ(bits(out[i]), bits(cast)) << "float " << in[i] << " at " << i;
    const float back = static_cast<float>(cast);
    ASSERT_EQ(std::memcmp(&round[i], &back, sizeof back), 0) << "float " << in[i] << " at " << i;
  }
}

TEST(HalfConversion, EveryHalfWidensAsTheCast) {
  std::vector<_Float16> in(65536);
  for (std::uint32_t b = 0; b < in.size(); ++b) {
    const std::uint16_t h = static_cast<std::uint16_t>(b);
    std::memcpy(&in[b], &h, sizeof h);
  }
  std::vector<float> f(in.size());
  std::vector<double> d(in.size());
  from_half(in.data(), f.data(), in.size());
  from_half(in.data(), d.data(), in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    const float cf = static_cast<float>(in[i]);
    const double cd = static_cast<double>(in[i]);
    if (std::isnan(cf)) {
      EXPECT_TRUE(std::isnan(f[i]) && std::isnan(d[i])) << i;
      continue;
    }
    ASSERT_EQ(std::memcmp(&f[i], &cf, sizeof cf), 0) << "half bits " << i;
    ASSERT_EQ(std::memcmp(&d[i], &cd, sizeof cd), 0) << "half bits " << i;
  }
}

// Lengths around the eight-sample blocks, from unaligned starts: every sample converted, none beyond.
TEST(HalfConversion, EveryLengthAndOffset) {
  std::vector<float> in(64);
  for (std::size_t i = 0; i < in.size(); ++i) in[i] = 0.1f * static_cast<float>(i) - 3.0f;
  for (std::size_t off = 0; off < 3; ++off)
    for (std::size_t n = 0; n + off <= 40; ++n) {
      std::vector<_Float16> half(in.size(), static_cast<_Float16>(-7.0f));
      std::vector<float> back(in.size(), 99.0f);
      to_half(in.data() + off, half.data() + off, n);
      from_half(half.data() + off, back.data() + off, n);
      for (std::size_t i = 0; i < in.size(); ++i) {
        const bool inside = i >= off && i < off + n;
        EXPECT_EQ(bits(half[i]), bits(inside ? static_cast<_Float16>(in[i]) : static_cast<_Float16>(-7.0f))) << off << " " << n << " " << i;
        EXPECT_EQ(back[i], inside ? static_cast<float>(static_cast<_Float16>(in[i])) : 99.0f) << off << " " << n << " " << i;
      }
    }
}

}  // namespace
}  // namespace gdp::multigrid
