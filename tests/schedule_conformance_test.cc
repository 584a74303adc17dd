// Every schedule against the in-core reference: {in-core, streamed} x bands x channel groups x domain x precision.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>

#include "gdp/solver.h"
#include "image_compare.h"
#include "schedule_problems.h"
#include "test_util.h"

namespace gdp {
namespace {

// One problem per domain, small enough that the whole matrix runs in seconds, wide enough for 4
// bands of at least 28 columns (3 sweeps), with 3 channels so that they split into 3 groups.
struct Conformance {
  Domain domain;
  int width, height;
  Precision precision;
  ScratchPrecision scratch = ScratchPrecision::Float;  // Narrow: half floats rounded alike by every schedule
  int pre = 3, post = 3;  // sweeps before restriction and after prolongation (--iters PRE/POST)
};

void PrintTo(const Conformance& k, std::ostream* os) {
  *os << test::domain_name(k.domain) << k.width << "x" << k.height
      << (k.precision == Precision::Float64 ? " double" : " float")
      << (k.scratch == ScratchPrecision::Narrow ? " narrow scratch" : "") << " " << k.pre << "/" << k.post
      << " sweeps";
}

constexpr int kChannels = 3;

// Smooth content (a different wave per channel) with some noise; the guidance is its exact
// gradients and the starting guess the same image with offsets between regions (seams to correct).
Image content(const Conformance& k) {
  const Image noise = test::random_image(k.width, k.height, kChannels, 11);
  Image img(k.width, k.height, kChannels);
  for (int c = 0; c < kChannels; ++c) {
    const Image wave = test::cosine_image(k.width, k.height, 2 + c, 1 + c);
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x)
        img.at(c, x, y) = 0.5f + 0.3f * wave.at(0, x, y) + 0.05f * noise.at(c, x, y);
  }
  return img;
}

// Bands 1 is plain streaming (the one-band plan); `groups` channel groups take 2 + bands * groups
// threads on the streamed schedules (src/bands/solve_streamed.cc), `groups` threads in-core.
struct Config {
  bool in_core;
  int bands, groups;
};

std::string name_of(const Config& r) {
  return (r.in_core ? std::string("in-core") : std::to_string(r.bands) + " band(s)") + ", " +
         std::to_string(r.groups) + " channel group(s)";
}

Image solve_as(const Conformance& k, const Image& img, const Config& r, SolveSummary* s) {
  SolverOptions o;
  o.domain = k.domain;
  o.precision = k.precision;
  o.scratch = k.scratch;
  o.vcycles = 2;
  o.sweeps = k.pre;
  o.post_sweeps = k.post;
  o.coarsest_size = 8;
  o.incore_bytes = 4096;  // several streamed levels even on these small images
  o.schedule = r.in_core ? Schedule::InCore : r.bands == 1 ? Schedule::Streaming : Schedule::Bands;
  o.bands = r.bands;
  o.threads = r.in_core ? r.groups : r.groups == 1 ? 1 : 2 + r.bands * r.groups;
  test::ExactGradients src(img, k.domain, 0.0, 1.0);
  const Image start = test::with_seams(img, 0.08f, -0.06f, 0.03f);
  return solve(src, o, &start, s);
}

using test::range_of;
using test::same_bits;

class ScheduleConformance : public ::testing::TestWithParam<Conformance> {};

// One band (streaming) gives the in-core bits; N bands (their own Gauss-Seidel ordering) agree
// with it to 1e-4 of the range; channel groups (threads) and a second run change no bit.
TEST_P(ScheduleConformance, EveryScheduleAgreesWithInCore) {
  const Conformance k = GetParam();
  const Image img = content(k);
  const Image reference = solve_as(k, img, {true, 1, 1}, nullptr);
  const double range = range_of(reference);
  ASSERT_GT(range, 0.5);
  if (k.pre != k.post) {  // the split reaches the solve (and is not the same count both ways)
    Conformance same = k;
    same.pre = same.post = k.post;
    EXPECT_FALSE(same_bits(reference, solve_as(same, img, {true, 1, 1}, nullptr)));
  }
  Image one_group;  // the previous run's result: the same bands in one channel group
  for (const Config& r : {Config{true, 1, 3}, Config{false, 1, 1}, Config{false, 1, 3}, Config{false, 2, 1}, Config{false, 2, 3},
                       Config{false, 4, 1}, Config{false, 4, 3}}) {
    SCOPED_TRACE(name_of(r));
    SolveSummary s;
    const Image out = solve_as(k, img, r, &s);
    ASSERT_EQ(out.data.size(), reference.data.size());
    if (!r.in_core) {
      EXPECT_GE(s.streamed_levels, 1);
    }
    if (r.bands == 1) {
      EXPECT_TRUE(same_bits(out, reference)) << "differs from in-core by " << test::max_difference(out, reference);
    } else {
      EXPECT_LE(test::max_difference(out, reference), 1e-4 * range);
    }
    if (r.groups == 1) {
      one_group = out;
    } else if (!r.in_core) {
      EXPECT_TRUE(same_bits(out, one_group)) << "groups change bits by " << test::max_difference(out, one_group);
    }
    const Image again = solve_as(k, img, r, nullptr);
    EXPECT_TRUE(same_bits(out, again)) << "run to run: " << test::max_difference(out, again);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Matrix, ScheduleConformance,
    ::testing::Values(Conformance{Domain::Planar, 150, 70, Precision::Float32},
                      Conformance{Domain::Planar, 150, 70, Precision::Float64},
                      Conformance{Domain::Cylindrical, 160, 64, Precision::Float32},
                      Conformance{Domain::Cylindrical, 160, 64, Precision::Float64},
                      Conformance{Domain::Spherical, 256, 64, Precision::Float32},
                      Conformance{Domain::Spherical, 256, 64, Precision::Float64},
                      Conformance{Domain::Planar, 150, 70, Precision::Float32, ScratchPrecision::Narrow},
                      Conformance{Domain::Cylindrical, 160, 64, Precision::Float32, ScratchPrecision::Narrow},
                      Conformance{Domain::Spherical, 256, 64, Precision::Float32, ScratchPrecision::Narrow},
                      // Uneven splits: each pass plans its own sweeps inside bands sized for the larger.
                      Conformance{Domain::Planar, 150, 70, Precision::Float32, ScratchPrecision::Float, 2, 3},
                      Conformance{Domain::Cylindrical, 160, 64, Precision::Float64, ScratchPrecision::Float, 3, 1},
                      Conformance{Domain::Spherical, 256, 64, Precision::Float32, ScratchPrecision::Narrow, 2, 3}));

}  // namespace
}  // namespace gdp
