// High/low compositing: gradients from one image, values from another.
#include <gtest/gtest.h>

#include "gdp/apps.h"
#include "gdp/errors.h"
#include "test_util.h"

namespace gdp {
namespace {

Image run(const Image& high, const Image& low, double alpha, double beta) {
  ImageRowReader h(high), l(low);
  Image out(high.width, high.height, high.channels);
  ImageRowWriter w(out);
  SolverOptions o;
  o.precision = Precision::Float64;
  o.tolerance = 1e-12;
  sharpen(h, l, alpha, beta, o, w);
  return out;
}

TEST(HighLow, ValuesFollowTheLowImageAndDetailTheHighOne) {
  // |grad u - grad h|^2 + alpha |u - (h + 0.1)|^2 is least at u = h + 0.1 exactly.
  const Image high = test::random_image(70, 45, 2, 3);
  Image low = high;
  for (float& v : low.data) v += 0.1f;
  EXPECT_LT(test::max_difference(run(high, low, 0.05, 1.0), low), 1e-5);
  // A flat low image and beta = 1: the high image's detail on the low image's level; its
  // mean moves to the low image's.
  const Image flat(70, 45, 2, 0.3f);
  const Image out = run(high, flat, 1e-4, 1.0);
  EXPECT_NEAR(test::mean(out), 0.3, 1e-3);
  EXPECT_LT(test::rms_difference(test::zero_mean(out), test::zero_mean(high)), 0.02);
}

TEST(HighLow, SizesMustMatch) {
  const Image a(10, 10, 1), b(10, 11, 1);
  EXPECT_THROW(run(a, b, 0.1, 1.0), InputError);
}

}  // namespace
}  // namespace gdp
