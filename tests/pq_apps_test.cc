// Applications on the spherical (PQ) domain: guidance across the folded top and bottom edges.
#include <gtest/gtest.h>

#include <cmath>

#include "gdp/apps.h"
#include "gdp/errors.h"
#include "test_util.h"

namespace gdp {
namespace {

// A smooth image that is continuous across the PQ folds: cos(2 pi k x / W) cos(pi m y / H) and
// sin(2 pi k x / W) sin(pi m y / H) with k even are unchanged by both 180-degree rotations
// (x, y) -> (W - x, -y) and (W/2 - x, 2H - y), sampled at pixel centres.
Image symmetric_image(int h) {
  const int w = 4 * h;
  Image img(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double px = 2 * M_PI * (x + 0.5) / w, py = M_PI * (y + 0.5) / h;
      img.at(0, x, y) = static_cast<float>(0.5 + 0.2 * std::cos(2 * px) * std::cos(3 * py) + 0.15 * std::sin(4 * px) * std::sin(py));
    }
  return img;
}

// Differences across the folds: (i, 0) with (W-1-i, 0), and (i, H-1) with (W/2-1-i mod W, H-1).
double max_fold_jump(const Image& img) {
  const int w = img.width, h = img.height;
  double m = 0.0;
  for (int i = 0; i < w; ++i) {
    m = std::max(m, std::abs(double(img.at(0, i, 0)) - img.at(0, w - 1 - i, 0)));
    m = std::max(m, std::abs(double(img.at(0, i, h - 1)) - img.at(0, ((w / 2 - 1 - i) % w + w) % w, h - 1)));
  }
  return m;
}

TEST(PqApps, ReconstructionFromOwnGradientsIsExact) {
  // Exact only if the gradients across both folds are taken and assembled right.
  const Image img = test::random_image(96, 24, 2, 4);
  SolverOptions o;
  o.domain = Domain::Spherical;
  o.precision = Precision::Float64;
  o.tolerance = 1e-12;
  o.coarsest_size = 8;
  const ReconstructResult r = reconstruct(img, o);
  EXPECT_LT(r.max_error, 1e-6);
}

TEST(PqApps, StitchingRemovesOffsetsAcrossTheFolds) {
  const int h = 48, w = 4 * h;
  const Image original = symmetric_image(h);
  ASSERT_LT(max_fold_jump(original), 0.02);
  // Regions: four sectors of columns, and a cap along the top edge whose halves meet across
  // the fold; each with its own offset.
  Image composite = original, labels(w, h, 1);
  const double offset[5] = {0.1, -0.08, 0.05, 0.12, -0.1};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int r = y < 6 ? 4 : (x + 20) % w / (w / 4);
      composite.at(0, x, y) += static_cast<float>(offset[r]);
      labels.at(0, x, y) = static_cast<float>(r) / 8.0f;
    }
  EXPECT_GT(max_fold_jump(composite), 0.15);
  SolverOptions o;
  o.domain = Domain::Spherical;
  o.coarsest_size = 8;
  const Image one = stitch(composite, labels, {}, o);
  o.precision = Precision::Float64;
  o.tolerance = 1e-10;
  const Image converged = stitch(composite, labels, {}, o);
  EXPECT_LT(test::rms_difference(one, converged), 5e-4);
  // Offsets gone (up to a constant), folds as continuous as in the original.
  EXPECT_LT(test::rms_difference(test::zero_mean(converged), test::zero_mean(original)), 0.01);
  EXPECT_LT(max_fold_jump(converged), max_fold_jump(original) + 0.01);
}

TEST(PqApps, SizesThatAreNotPqAreRejected) {
  const Image img = test::random_image(100, 24, 1);
  SolverOptions o;
  o.domain = Domain::Spherical;
  EXPECT_THROW(reconstruct(img, o), UsageError);
  const Image odd = test::random_image(60, 15, 1);
  EXPECT_THROW(reconstruct(odd, o), UsageError);
}

}  // namespace
}  // namespace gdp
