// The V-cycle's smoother choices (InCoreVCycle::set_smoother): sweep counts before and after, row direction.
#include <gtest/gtest.h>

#include <random>

#include "gdp/errors.h"
#include "gdp/solver.h"
#include "multigrid/incore_vcycle.h"
#include "multigrid/plane_ops.h"
#include "topology/topology.h"

namespace gdp::multigrid {
namespace {

struct Problem {
  Hierarchy h;
  Operators<double> ops;
  Plane<double> b;
  Problem() : h(build_hierarchy(*topology::make_topology(Domain::Planar), 160, 96, 0.0, 8)), ops(h), b(160, 96) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> d(-1.0, 1.0);
    double mean = 0.0;
    for (double& v : b.data) mean += v = d(rng);
    mean /= static_cast<double>(b.data.size());
    for (double& v : b.data) v -= mean;  // alpha = 0: b must be orthogonal to the constants
  }
};

// The residual reduction of the third V-cycle from zero (close to the asymptotic factor).
double factor(const Problem& p, int pre, int post, SweepDirection dir) {
  InCoreVCycle<double> vc(p.ops, pre, 1e-12);
  vc.set_smoother(pre, post, dir);
  Plane<double> u(p.b.width, p.b.height), b = p.b;
  double before = 0.0;
  for (int c = 0; c < 3; ++c) {
    before = vc.residual_norm(u, b);
    vc.run(u, b);
  }
  return vc.residual_norm(u, b) / before;
}

TEST(Smoother, TheDefaultsAreTheConstructorsSweepsForward) {
  const Problem p;
  Plane<double> plain(160, 96), set(160, 96), b1 = p.b, b2 = p.b;
  InCoreVCycle<double> a(p.ops, 3, 1e-12), b(p.ops, 2, 1e-12);
  b.set_smoother(3, 3, SweepDirection::Forward);
  a.run(plain, b1);
  b.run(set, b2);
  EXPECT_EQ(plain.data, set.data);
}

TEST(Smoother, EverySweepCutsTheFactorAndOnlyTheTotalCounts) {
  const Problem p;
  double last = 1.0;
  for (int k = 1; k <= 4; ++k) {
    const double f = factor(p, k, k, SweepDirection::Forward);
    EXPECT_LT(f, 0.35 * last) << k << " sweeps each way";  // about 0.26 per sweep and way
    last = f;
  }
  // Two before and three after, or three before and two after: the same spectrum, so nearly the same factor.
  const double f23 = factor(p, 2, 3, SweepDirection::Forward), f32 = factor(p, 3, 2, SweepDirection::Forward);
  EXPECT_NEAR(f23 / f32, 1.0, 0.1);
  EXPECT_LT(f23, factor(p, 2, 2, SweepDirection::Forward));
  EXPECT_GT(f23, factor(p, 3, 3, SweepDirection::Forward));
}

TEST(Smoother, AlternatingDirectionsConvergeAsWellAsLexicographic) {
  const Problem p;
  for (int k : {1, 3}) {
    const double forward = factor(p, k, k, SweepDirection::Forward);
    EXPECT_LT(factor(p, k, k, SweepDirection::AlternateSweeps), 1.1 * forward) << k;
    EXPECT_LT(factor(p, k, k, SweepDirection::AlternateRows), 1.1 * forward) << k;
  }
}

// --iters: one count is both ways, PRE/POST splits them; anything else names the flag.
TEST(Smoother, ItersTakesOneCountOrPreSlashPost) {
  SolverOptions o;
  EXPECT_EQ(o.sweeps, o.post_sweeps);  // the default: the same count both ways
  parse_sweeps("4", o);
  EXPECT_EQ(o.sweeps, 4);
  EXPECT_EQ(o.post_sweeps, 4);
  parse_sweeps("2/3", o);
  EXPECT_EQ(o.sweeps, 2);
  EXPECT_EQ(o.post_sweeps, 3);
  parse_sweeps("0/100", o);
  EXPECT_EQ(o.sweeps, 0);
  EXPECT_EQ(o.post_sweeps, 100);
  for (const char* bad : {"", "-1", "2/", "/3", "x", "101", "2/3/4", " 3", "3.5", "1000000000000"}) {
    try {
      parse_sweeps(bad, o);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("--iters"), std::string::npos) << e.what();
    }
  }
  o.post_sweeps = -1;
  EXPECT_THROW(o.validate(), UsageError);
}

}  // namespace
}  // namespace gdp::multigrid
