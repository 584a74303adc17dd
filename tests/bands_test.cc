// The band schedule on threads: 1-4 bands agree with the streaming solver, converge, repeat exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "gdp/errors.h"
#include "gdp/solver.h"
#include "image_compare.h"
#include "schedule_problems.h"
#include "test_util.h"

namespace gdp {
namespace {

struct Case {
  Domain domain;
  int width, height, channels;
  double alpha;
  // Agreement after one V-cycle, as a fraction of the range: 1e-4 where the V-cycle itself is
  // accurate to about 1e-4; odd periodic widths (rediscretised coarse levels) leave a V-cycle
  // error 40x that, and orderings differ by a few percent of it. Bands
  // wide enough for 4-16 row groups a phase (2560 columns) reorder more (docs/how-bands-work.md,
  // "Groups, phases, regions"): 0.9-1.4e-4 measured there.
  double agree = 1e-4;
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << test::domain_name(c.domain) << c.width << "x" << c.height << "x" << c.channels << " alpha " << c.alpha;
}

// Bands relax in an ordering of their own (lanes, boustrophedon), so after one V-cycle they
// differ from other orderings by a part of the V-cycle's own error (about 1e-3 of the
// correction's size here). The problems are like stitching: the starting guess is the image
// with seams (offsets of a tenth of the range), the guidance its exact gradients, so the
// V-cycle corrects the seams and its error is small against the image's range.
Image test_image(const Case& k, unsigned seed) {
  Image img = test::random_image(k.width, k.height, k.channels, seed);
  for (int c = 0; c < k.channels; ++c)
    for (int y = 0; y < k.height; ++y)
      for (int x = 0; x < k.width; ++x) {
        const double sx = 2.0 * M_PI * x / k.width, sy = M_PI * y / k.height;
        img.at(c, x, y) = static_cast<float>(0.5 + 0.3 * std::sin(3 * sx + c) * std::cos(2 * sy) +
                                             0.1 * std::cos(11 * sx + 5 * sy) + 0.05 * img.at(c, x, y));
      }
  return img;
}

Image solve_with(const Case& k, const Image& img, Schedule schedule, int bands, int vcycles, SolveSummary* s = nullptr,
                 Precision precision = Precision::Float32, std::size_t incore_bytes = 4096) {
  SolverOptions o;
  o.domain = k.domain;
  o.vcycles = vcycles;
  o.coarsest_size = 8;
  o.incore_bytes = incore_bytes;  // several banded levels even on small images
  o.residuals = true;
  o.schedule = schedule;
  o.bands = bands;
  o.precision = precision;
  test::ExactGradients src(img, k.domain, k.alpha, 1.0);
  const Image start = test::with_seams(img, 0.1f, -0.07f, 0.05f);
  return solve(src, o, &start, s);
}

using test::range_of;

class Bands : public ::testing::TestWithParam<Case> {};

TEST_P(Bands, OneVCycleAgreesWithOneBandAndTheStreamingSolver) {
  const Case k = GetParam();
  const Image img = test_image(k, 3);
  const Image streaming = solve_with(k, img, Schedule::Streaming, 1, 1);
  const Image one = solve_with(k, img, Schedule::Bands, 1, 1);
  const double range = range_of(streaming);
  EXPECT_LE(test::max_difference(one, streaming), k.agree * range);
  for (int bands : {2, 3, 4}) {
    SolveSummary s;
    const Image out = solve_with(k, img, Schedule::Bands, bands, 1, &s);
    EXPECT_EQ(s.schedule, "bands");
    EXPECT_GE(s.streamed_levels, 1);
    EXPECT_LE(test::max_difference(out, one), k.agree * range) << bands << " bands";
    EXPECT_LE(test::max_difference(out, streaming), k.agree * range) << bands << " bands";
  }
}

// One band-schedule V-cycle is about as accurate as one streaming V-cycle.
TEST_P(Bands, OneVCycleIsAsAccurateAsTheStreamingOne) {
  const Case k = GetParam();
  const Image img = test_image(k, 6);
  const Image exact = solve_with(k, img, Schedule::Streaming, 1, 8, nullptr, Precision::Float64);
  const double streaming = test::max_difference(solve_with(k, img, Schedule::Streaming, 1, 1, nullptr, Precision::Float64), exact);
  for (int bands : {1, 2, 4}) {
    const Image out = solve_with(k, img, Schedule::Bands, bands, 1, nullptr, Precision::Float64);
    EXPECT_LE(test::max_difference(out, exact), 1.5 * streaming) << bands << " bands";
  }
}

TEST_P(Bands, ConvergesToTheSameSolution) {
  const Case k = GetParam();
  const Image img = test_image(k, 4);
  SolveSummary streaming;
  const Image ref = solve_with(k, img, Schedule::Streaming, 1, 6, &streaming, Precision::Float64);
  const double range = range_of(ref);
  for (int bands : {1, 3}) {
    SolveSummary s;
    const Image out = solve_with(k, img, Schedule::Bands, bands, 6, &s, Precision::Float64);
    EXPECT_LE(test::max_difference(out, ref), 1e-7 * range) << bands << " bands";
    ASSERT_EQ(s.relative_residuals.size(), 7u);
    EXPECT_LT(s.relative_residuals.back(), 1e-6 * s.relative_residuals.front()) << bands << " bands";
    // The initial residual the bands measure together is the streaming solver's, which sees whole
    // rows (across a sphere's folds too); after one V-cycle, orderings differ by a part of it.
    EXPECT_NEAR(s.relative_residuals[0], streaming.relative_residuals[0], 1e-9 * streaming.relative_residuals[0])
        << bands << " bands";
    EXPECT_LT(s.relative_residuals[1], 2 * streaming.relative_residuals[1]) << bands << " bands";
  }
}

TEST_P(Bands, SameConfigurationSameBits) {
  const Case k = GetParam();
  const Image img = test_image(k, 5);
  const int bands = 3;
  const Image a = solve_with(k, img, Schedule::Bands, bands, 2);
  const Image b = solve_with(k, img, Schedule::Bands, bands, 2);
  ASSERT_EQ(a.data.size(), b.data.size());
  EXPECT_EQ(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)), 0);
}

INSTANTIATE_TEST_SUITE_P(Domains, Bands,
                         ::testing::Values(Case{Domain::Planar, 300, 70, 2, 0.0}, Case{Domain::Planar, 257, 41, 1, 0.01},
                                           Case{Domain::Cylindrical, 320, 64, 1, 0.0},
                                           Case{Domain::Cylindrical, 301, 97, 1, 0.02, 5e-4},
                                           Case{Domain::Spherical, 512, 128, 1, 0.0}, Case{Domain::Spherical, 640, 160, 2, 0.01},
                                           Case{Domain::Planar, 2560, 64, 1, 0.0, 2e-4}, Case{Domain::Cylindrical, 2560, 64, 1, 0.0, 2e-4}));

// Many bands on a small image: bands too narrow for the coarser levels merge in pairs stage by stage
// (8 -> 4 -> 2 -> 1; 7 -> 3 -> 1) down to a level of 256 bytes, instead of gathering early.
TEST(BandsMerging, MergedStagesAgreeConvergeAndRepeat) {
  for (const auto& [k, bands] : {std::pair{Case{Domain::Planar, 1024, 256, 2, 0.0}, 8},
                                 std::pair{Case{Domain::Cylindrical, 1400, 256, 1, 0.01}, 7}}) {
    SCOPED_TRACE(std::to_string(bands) + " bands");
    const Image img = test_image(k, 7);
    const std::size_t incore = 256;
    SolveSummary s, streaming_summary;
    const Image streaming = solve_with(k, img, Schedule::Streaming, 1, 1, nullptr, Precision::Float32, incore);
    const Image out = solve_with(k, img, Schedule::Bands, bands, 1, &s, Precision::Float32, incore);
    EXPECT_EQ(s.streamed_levels, 6);  // 3 levels of 8 (7) bands, then merged ones
    EXPECT_LE(test::max_difference(out, streaming), 1e-4 * range_of(streaming));
    const Image again = solve_with(k, img, Schedule::Bands, bands, 1, nullptr, Precision::Float32, incore);
    EXPECT_EQ(std::memcmp(out.data.data(), again.data.data(), out.data.size() * sizeof(float)), 0);
    const Image ref = solve_with(k, img, Schedule::Streaming, 1, 6, &streaming_summary, Precision::Float64, incore);
    const Image conv = solve_with(k, img, Schedule::Bands, bands, 6, &s, Precision::Float64, incore);
    EXPECT_LE(test::max_difference(conv, ref), 1e-7 * range_of(ref));
    EXPECT_NEAR(s.relative_residuals[0], streaming_summary.relative_residuals[0],
                1e-9 * streaming_summary.relative_residuals[0]);
    EXPECT_LT(s.relative_residuals.back(), 1e-6 * s.relative_residuals.front());
  }
}

TEST(BandsOptions, TooManyBandsForTheWidthIsAUsageError) {
  const Case k{Domain::Planar, 64, 32, 1, 0.0};
  const Image img = test::random_image(k.width, k.height, 1, 1);
  EXPECT_THROW(solve_with(k, img, Schedule::Bands, 8, 1), UsageError);
}

}  // namespace
}  // namespace gdp
