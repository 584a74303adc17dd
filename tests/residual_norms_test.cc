// Residual norms only when asked for: the same bits without them, and a summary that says so.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "gdp/solver.h"
#include "schedule_problems.h"
#include "test_util.h"

namespace gdp {
namespace {

// A schedule (bands: with Schedule::Bands) on a random image of a domain, alpha as given.
struct Case {
  Schedule schedule;
  int bands;
  Domain domain;
  int width, height, channels;
  double alpha;
};

class ResidualNorms : public ::testing::TestWithParam<Case> {
 protected:
  SolverOptions options() const {
    const Case k = GetParam();
    SolverOptions o;
    o.domain = k.domain;
    o.vcycles = 2;
    o.coarsest_size = 8;
    o.incore_bytes = 4096;  // several streamed (banded) levels even on small images
    o.scratch = ScratchPrecision::Narrow;
    o.schedule = k.schedule;
    o.bands = k.bands;
    return o;
  }
  Image solved(const SolverOptions& o, SolveSummary& s) const {
    const Case k = GetParam();
    const Image img = test::random_image(k.width, k.height, k.channels, 11);
    const Image start = test::with_seams(img, 0.1f, -0.07f, 0.05f);
    test::ExactGradients src(img, k.domain, k.alpha, 1.0);
    return solve(src, o, &start, &s);
  }
};

bool same_bits(const Image& a, const Image& b) {
  return a.data.size() == b.data.size() && std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0;
}

// Not measured: none in the summary, the same V-cycles and the same bits as measured.
TEST_P(ResidualNorms, MeasuringChangesNoBits) {
  SolverOptions o = options();
  SolveSummary off, on;
  const Image a = solved(o, off);
  o.residuals = true;
  const Image b = solved(o, on);
  EXPECT_TRUE(off.relative_residuals.empty());
  EXPECT_EQ(off.vcycles, 2);
  EXPECT_EQ(on.vcycles, 2);
  ASSERT_EQ(on.relative_residuals.size(), 3u);  // before, and after each V-cycle
  EXPECT_LT(on.relative_residuals[2], on.relative_residuals[1]);
  EXPECT_LT(on.relative_residuals[1], on.relative_residuals[0]);
  EXPECT_TRUE(same_bits(a, b));
}

// A log (per-level lines) and a tolerance (which reads them) measure residuals without being asked.
TEST_P(ResidualNorms, LogAndToleranceMeasureThem) {
  SolverOptions o = options();
  SolveSummary plain, logged, asked;
  const Image a = solved(o, plain);
  std::vector<std::string> lines;
  o.log = [&](const std::string& line) { lines.push_back(line); };
  const Image b = solved(o, logged);
  EXPECT_EQ(logged.relative_residuals.size(), 3u);
  EXPECT_FALSE(lines.empty());
  EXPECT_TRUE(same_bits(a, b));
  o.log = nullptr;
  o.tolerance = 1e-3;
  solved(o, asked);
  ASSERT_GE(asked.relative_residuals.size(), 2u);
  EXPECT_EQ(asked.relative_residuals.size(), static_cast<std::size_t>(asked.vcycles) + 1);
}

INSTANTIATE_TEST_SUITE_P(Schedules, ResidualNorms,
                         ::testing::Values(Case{Schedule::InCore, 1, Domain::Planar, 97, 53, 3, 0.0},
                                           Case{Schedule::Streaming, 1, Domain::Planar, 97, 53, 3, 0.0},
                                           Case{Schedule::Streaming, 1, Domain::Cylindrical, 160, 64, 1, 0.01},
                                           Case{Schedule::Bands, 3, Domain::Planar, 300, 70, 2, 0.0},
                                           Case{Schedule::Bands, 2, Domain::Spherical, 256, 64, 1, 0.0},
                                           Case{Schedule::InCore, 1, Domain::Spherical, 96, 24, 2, 0.05}));

}  // namespace
}  // namespace gdp
