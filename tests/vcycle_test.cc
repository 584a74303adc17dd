// V-cycle convergence on manufactured solutions and agreement with a direct CG solve.
#include <gtest/gtest.h>

#include "gdp/apps.h"
#include "gdp/image_io.h"
#include "gdp/solver.h"
#include "multigrid/coarse_cg.h"
#include "multigrid/hierarchy.h"
#include "multigrid/plane_ops.h"
#include "test_util.h"
#include "topology/topology.h"

namespace gdp {
namespace {

// Reference: conjugate gradients on the whole finest level, in double precision.
Image cg_reference(const Image& img, Domain domain, double alpha) {
  const auto topo = topology::make_topology(domain);
  const multigrid::Hierarchy hier = multigrid::build_hierarchy(*topo, img.width, img.height, alpha, 1 << 20);
  const multigrid::LevelOperator<double> op(hier.levels[0], alpha);
  // Right-hand side = A p (the exact-gradient identity, tested separately).
  multigrid::Plane<double> p(img.width, img.height), b(img.width, img.height), u(img.width, img.height);
  std::copy(img.data.begin(), img.data.begin() + img.plane_size(), p.data.begin());
  multigrid::Scratch<double> s;
  multigrid::apply(op, p, b, s);
  multigrid::solve_cg(op, alpha == 0.0, b, u, 1e-14, 100000);
  Image out(img.width, img.height, 1);
  std::copy(u.data.begin(), u.data.end(), out.data.begin());
  return out;
}

SolverOptions double_options(Domain d, int vcycles) {
  SolverOptions o;
  o.domain = d;
  o.precision = Precision::Float64;
  o.vcycles = vcycles;
  o.coarsest_size = 8;
  o.residuals = true;  // the tests read the convergence factors
  return o;
}

// Four V-cycles on the image's own gradients: every one cuts the residual at least tenfold.
void expect_fast_convergence(const Image& img, Domain domain) {
  test::ExactGradients src(img, domain);
  SolveSummary sum;
  solve(src, double_options(domain, 4), nullptr, &sum);
  ASSERT_EQ(sum.relative_residuals.size(), 5u);
  EXPECT_GT(sum.levels, 3);
  for (int k = 1; k <= 4; ++k) {
    const double factor = sum.relative_residuals[k] / sum.relative_residuals[k - 1];
    EXPECT_LT(factor, 0.1) << "V-cycle " << k;
  }
}

TEST(VCycle, ConvergenceFactorOnCosineWithNeumann) {
  expect_fast_convergence(test::cosine_image(256, 192, 3, 5), Domain::Planar);
}

TEST(VCycle, ScreenedProblemConverges) {
  const Image img = test::random_image(120, 77, 1, 3);
  test::ExactGradients src(img, Domain::Planar, 0.05, 1.5);
  SolveSummary sum;
  solve(src, double_options(Domain::Planar, 5), nullptr, &sum);
  for (int k = 1; k <= 5; ++k) EXPECT_LT(sum.relative_residuals[k], 0.1 * sum.relative_residuals[k - 1]);
}

class AgainstCg : public ::testing::TestWithParam<std::tuple<Domain, int, int, double>> {};

TEST_P(AgainstCg, ManyVCyclesReachTheDirectSolution) {
  const auto [domain, w, h, alpha] = GetParam();
  const Image img = test::random_image(w, h, 1, 11);
  test::ExactGradients src(img, domain, alpha);
  SolverOptions o = double_options(domain, 1);
  o.tolerance = 1e-13;
  o.max_vcycles = 40;
  o.coarsest_size = 4;
  const Image mg = solve(src, o);
  Image ref = cg_reference(img, domain, alpha);
  const Image a = alpha == 0.0 ? test::zero_mean(mg) : mg;
  const Image b = alpha == 0.0 ? test::zero_mean(ref) : ref;
  // Both are stored as float: they may round to neighbouring floats (measured: up to 1.2e-10,
  // the spacing of floats near 0.001-0.002; 0 on most cases).
  EXPECT_LT(test::max_difference(a, b), 1e-9);
  // The exact gradients of img are integrable: the solution is img itself (up to a constant).
  EXPECT_LT(test::max_difference(a, alpha == 0.0 ? test::zero_mean(img) : img), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Sizes, AgainstCg,
                         ::testing::Values(std::make_tuple(Domain::Planar, 1, 1, 0.0),
                                           std::make_tuple(Domain::Planar, 2, 7, 0.0),
                                           std::make_tuple(Domain::Planar, 97, 53, 0.0),
                                           std::make_tuple(Domain::Planar, 97, 53, 0.1),
                                           std::make_tuple(Domain::Planar, 1, 301, 0.0),
                                           std::make_tuple(Domain::Planar, 31, 2, 0.0),
                                           std::make_tuple(Domain::Cylindrical, 64, 33, 0.0),
                                           std::make_tuple(Domain::Cylindrical, 97, 53, 0.0),
                                           std::make_tuple(Domain::Cylindrical, 45, 20, 0.2),
                                           std::make_tuple(Domain::Spherical, 8, 2, 0.0),
                                           std::make_tuple(Domain::Spherical, 96, 24, 0.0),
                                           std::make_tuple(Domain::Spherical, 160, 40, 0.1)));

// The spherical (PQ) V-cycle converges like the planar one on a smooth manufactured solution
// that is continuous across the folded top and bottom edges (a function of the sphere's
// embedding coordinates would do; a product of cosines periodic in x is simpler and, with
// columns mirrored about 0 and W/2 onto themselves, equally continuous).
TEST(VCycle, ConvergenceFactorOnTheSphere) {
  const int h = 64, w = 4 * h;
  Image img(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.at(0, x, y) = static_cast<float>(std::cos(2 * M_PI * 3 * (x + 0.5) / w) * std::cos(M_PI * 5 * (y + 0.5) / h) +
                                           0.3 * std::sin(2 * M_PI * (x + 0.5) / w));
  expect_fast_convergence(img, Domain::Spherical);
}

}  // namespace
}  // namespace gdp

namespace gdp {
namespace {

// Float32 storage must not lose the solution over several V-cycles (the stored operator keeps
// constants exactly in its null space; without that the error grew to ~6e-4 after 2 cycles).
TEST(VCycle, Float32KeepsImprovingOnARealImage) {
  const ReadResult in = read_image(GDP_TEST_DATA "/opencv/weir_1_crop.jpg");
  SolverOptions o;
  o.vcycles = 1;
  const ReconstructResult one = reconstruct(in.image, o);
  o.vcycles = 4;
  const ReconstructResult four = reconstruct(in.image, o);
  EXPECT_LT(one.rms_error, 1e-4);
  EXPECT_LT(four.rms_error, 1e-5);
  EXPECT_LT(four.max_error, 5e-5);
}

}  // namespace
}  // namespace gdp
