// Per-pixel weights and pinned pixels: fixed points, pins held, the direct solution, every schedule.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>

#include "gdp/solver.h"
#include "multigrid/coarse_cg.h"
#include "multigrid/hierarchy.h"
#include "multigrid/input_rows.h"
#include "test_util.h"
#include "topology/topology.h"

namespace gdp {
namespace {

using WeightFn = std::function<double(int i, int j)>;

// Exact gradients of `shape` and values of `values`, with a weight per pixel.
class WeightedGuidance : public GuidanceSource {
 public:
  WeightedGuidance(const Image& shape, const Image& values, WeightFn weight)
      : grad_(shape, Domain::Planar), values_(values), weight_(std::move(weight)) {}
  int width() const override { return values_.width; }
  int height() const override { return values_.height; }
  int channels() const override { return values_.channels; }
  bool has_weights() const override { return true; }
  void read_row(int j, GuidanceRow& out) override {
    grad_.read_row(j, out);
    for (int c = 0; c < values_.channels; ++c)
      for (int i = 0; i < values_.width; ++i) out.value[c * values_.width + i] = values_.at(c, i, j);
    for (int i = 0; i < values_.width; ++i) out.weight[i] = weight_(i, j);
  }

 private:
  test::ExactGradients grad_;
  const Image& values_;
  WeightFn weight_;
};

// Pixels pinned in a block and on a scattered lattice; the rest weighted 0 .. 2 (some exactly 0).
double mixed_weight(int i, int j) {
  if ((i > 5 && i < 15 && j > 3 && j < 12) || (i * 7 + j * 3) % 23 == 0) return kPinned;
  return ((i * 13 + j * 5) % 5) * 0.5;
}

TEST(Weights, ExactDataIsAFixedPoint) {
  // Gradients and values of the same image: that image satisfies every term, whatever the weights.
  const Image f = test::random_image(61, 47, 2, 3);
  WeightedGuidance src(f, f, mixed_weight);
  SolverOptions o;
  o.vcycles = 8;
  o.coarsest_size = 8;
  const Image u = solve(src, o);
  EXPECT_LT(test::max_difference(u, f), 2e-5);
}

TEST(Weights, PinnedPixelsHoldTheirValuesAfterOneVCycle) {
  const Image f = test::random_image(80, 60, 3, 4), g = test::random_image(80, 60, 3, 5);
  // Half-float scratch (the CLI's default) too: b's pinned entries must not be rounded to half.
  for (auto [schedule, scratch] : {std::pair{Schedule::InCore, ScratchPrecision::Float},
                                   std::pair{Schedule::Streaming, ScratchPrecision::Float},
                                   std::pair{Schedule::InCore, ScratchPrecision::Narrow},
                                   std::pair{Schedule::Streaming, ScratchPrecision::Narrow}}) {
    WeightedGuidance src(f, g, mixed_weight);
    SolverOptions o;
    o.schedule = schedule;
    o.scratch = scratch;
    o.incore_bytes = 0;
    o.coarsest_size = 8;
    const Image u = solve(src, o);
    double worst = 0.0;
    int pinned = 0;
    for (int c = 0; c < 3; ++c)
      for (int j = 0; j < u.height; ++j)
        for (int i = 0; i < u.width; ++i)
          if (mixed_weight(i, j) == kPinned) {
            worst = std::max(worst, std::abs(double(u.at(c, i, j)) - g.at(c, i, j)));
            ++pinned;
          }
    EXPECT_GT(pinned, 300);
    EXPECT_LT(worst, 1e-4) << "scratch " << int(scratch);
    int not_finite = 0;
    for (float v : u.data) not_finite += !std::isfinite(v);
    EXPECT_EQ(not_finite, 0) << "scratch " << int(scratch);
  }
}

TEST(Weights, MultigridReachesTheDirectSolution) {
  // The weighted problem solved by conjugate gradients on the finest level alone (no multigrid)
  // against V-cycles: the diagonal term must enter relaxation, residuals and coarse levels alike.
  const int w = 37, h = 29;
  const Image f = test::random_image(w, h, 1, 6), g = test::random_image(w, h, 1, 7);
  WeightedGuidance src(f, g, mixed_weight);
  SolverOptions o;
  o.precision = Precision::Float64;
  o.coarsest_size = 4;
  o.tolerance = 1e-13;
  SolveSummary summary;
  const Image u = solve(src, o, nullptr, &summary);
  ASSERT_GE(summary.relative_residuals.size(), 3u);
  EXPECT_LT(summary.relative_residuals.back(), 1e-13);
  // At most 25 cycles: pins slow multigrid down, but not to a crawl.
  EXPECT_LE(summary.vcycles, 25);

  const auto topo = topology::make_topology(Domain::Planar);
  const multigrid::Hierarchy hier = multigrid::build_hierarchy(*topo, w, h, 0.0, 1 << 20);
  const multigrid::LevelOperator<double> op(hier.levels[0], 0.0);
  WeightedGuidance src2(f, g, mixed_weight);
  multigrid::InputRows<double> rows(src2, hier);
  multigrid::Plane<double> b(w, h), x(w, h), d(w, h), wt(w, h);
  std::vector<double> start(w);
  for (int j = 0; j < h; ++j)
    rows.next(start, {b.row(j), std::size_t(w)}, {wt.row(j), std::size_t(w)}, {d.row(j), std::size_t(w)});
  multigrid::solve_cg(op, false, b, x, 1e-15, 100000, &d);
  double worst = 0.0;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) worst = std::max(worst, std::abs(x.at(i, j) - u.at(0, i, j)));
  EXPECT_LT(worst, 2e-7);
}

TEST(Weights, StreamingIsBitIdenticalToInCore) {
  for (Domain domain : {Domain::Planar, Domain::Cylindrical, Domain::Spherical}) {
    const int w = domain == Domain::Spherical ? 96 : 70, h = domain == Domain::Spherical ? 24 : 45;
    const Image f = test::random_image(w, h, 2, 8), g = test::random_image(w, h, 2, 9);
    SolverOptions o;
    o.domain = domain;
    o.vcycles = 3;
    o.coarsest_size = 5;
    o.incore_bytes = 0;
    o.schedule = Schedule::InCore;
    // Spherical exact gradients need the fold edges: ExactGradients knows them, and only the
    // values and weights change here.
    WeightedGuidance a_src(f, g, mixed_weight);
    const Image a = solve(a_src, o);
    o.schedule = Schedule::Streaming;
    WeightedGuidance b_src(f, g, mixed_weight);
    const Image b = solve(b_src, o);
    EXPECT_EQ(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)), 0)
        << "domain " << int(domain) << ": max difference " << test::max_difference(a, b);
    // Half-float scratch: the diagonal is kept exact (pinned entries exceed half's range).
    o.scratch = ScratchPrecision::Narrow;
    WeightedGuidance c_src(f, g, mixed_weight);
    const Image c = solve(c_src, o);
    EXPECT_LT(test::max_difference(a, c), 2e-3);
  }
}

TEST(Weights, BandsHoldPinsAndReachTheSameSolution) {
  // The band schedule carries the diagonal like b: pins held after one V-cycle, and iterated
  // to convergence it reaches the streaming schedule's solution.
  for (Domain domain : {Domain::Planar, Domain::Cylindrical}) {
    const Image f = test::random_image(130, 40, 2, 3), g = test::random_image(130, 40, 2, 4);
    SolverOptions o;
    o.domain = domain;
    o.coarsest_size = 8;
    o.schedule = Schedule::Bands;
    for (int bands : {2, 3}) {
      o.bands = bands;
      o.precision = Precision::Float32;
      o.vcycles = 1;
      WeightedGuidance src(f, g, mixed_weight);
      const Image one = solve(src, o);
      double worst = 0.0;
      for (int c = 0; c < 2; ++c)
        for (int j = 0; j < 40; ++j)
          for (int i = 0; i < 130; ++i)
            if (mixed_weight(i, j) == kPinned) worst = std::max(worst, std::abs(double(one.at(c, i, j)) - g.at(c, i, j)));
      EXPECT_LT(worst, 1e-4) << bands << " bands";
      o.precision = Precision::Float64;
      o.vcycles = 12;
      WeightedGuidance a_src(f, g, mixed_weight), b_src(f, g, mixed_weight);
      const Image banded = solve(a_src, o);
      SolverOptions streaming = o;
      streaming.schedule = Schedule::Streaming;
      EXPECT_LT(test::max_difference(banded, solve(b_src, streaming)), 1e-6) << bands << " bands";
    }
  }
}

TEST(Weights, UniformWeightsActLikeScreening) {
  // A weight of 0.3 everywhere is the screened problem with a lumped mass: close to alpha = 0.3
  // (consistent mass) on a smooth image, and exactly as unique (no mean to keep).
  const Image f = test::cosine_image(64, 48, 3, 2);
  Image g = f;
  for (float& v : g.data) v += 0.25f;  // values disagree with the gradients by a constant
  WeightedGuidance src(f, g, [](int, int) { return 0.3; });
  SolverOptions o;
  o.vcycles = 6;
  const Image u = solve(src, o);
  // Gradients say f, values say f + 0.25: the minimiser is f + 0.25 exactly.
  EXPECT_LT(test::max_difference(u, g), 1e-4);
}

}  // namespace
}  // namespace gdp
