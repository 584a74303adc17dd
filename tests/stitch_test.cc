// Stitching a real photo split into regions with exposure offsets.
#include <gtest/gtest.h>

#include <cmath>

#include "gdp/apps.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace gdp {
namespace {

// Regions: a 3x2 grid with wavy boundaries; labels are distinct grey-ish colours.
int region_of(int x, int y, int w, int h) {
  const double wx = x + 12.0 * std::sin(y * 0.05), wy = y + 9.0 * std::cos(x * 0.04);
  return (wx < w / 3.0 ? 0 : wx < 2.0 * w / 3.0 ? 1 : 2) + 3 * (wy < h / 2.0 ? 0 : 1);
}

struct Split {
  Image original, composite, labels;
};

Split split_real_image() {
  Split s;
  s.original = read_image(GDP_TEST_DATA "/opencv/weir_1_crop.jpg").image;
  const int w = s.original.width, h = s.original.height;
  s.composite = s.original;
  s.labels = Image(w, h, 3);
  const double offset[6] = {0.12, -0.10, 0.05, -0.04, 0.15, 0.0};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int r = region_of(x, y, w, h);
      for (int c = 0; c < 3; ++c) {
        s.composite.at(c, x, y) += static_cast<float>(offset[r]);
        s.labels.at(c, x, y) = static_cast<float>((r * 37 + c * 11) % 200) / 255.0f;
      }
    }
  return s;
}

// Mean absolute jump across vertical edges where the label changes.
double seam_jump(const Image& img, const Image& labels) {
  double s = 0.0, n = 0.0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x + 1 < img.width; ++x)
      if (labels.at(0, x, y) != labels.at(0, x + 1, y)) {
        s += std::abs(double(img.at(1, x + 1, y)) - img.at(1, x, y));
        n += 1.0;
      }
  return s / n;
}

TEST(Stitch, RemovesExposureSeamsOnARealPhoto) {
  const Split s = split_real_image();
  SolverOptions o;
  const Image one = stitch(s.composite, s.labels, {}, o);
  o.precision = Precision::Float64;
  o.tolerance = 1e-9;
  const Image converged = stitch(s.composite, s.labels, {}, o);
  const double before = seam_jump(s.composite, s.labels), after = seam_jump(converged, s.labels),
               natural = seam_jump(s.original, s.labels);
  EXPECT_GT(before, 0.08);
  EXPECT_LT(after, natural + 0.02) << "seams must be no stronger than the photo's own edges there";
  // Closer to the original photo (up to a constant) than the composite was.
  const double err_composite = test::rms_difference(test::zero_mean(s.composite), test::zero_mean(s.original), 1);
  const double err_stitched = test::rms_difference(test::zero_mean(converged), test::zero_mean(s.original), 1);
  EXPECT_LT(err_stitched, 0.5 * err_composite);
  // One V-cycle is already close to the converged result (values in [0, 1]).
  EXPECT_LT(test::rms_difference(one, converged, 1), 1e-3);
  // The mean over known pixels matches the composite's.
  EXPECT_NEAR(test::mean(converged, 1), test::mean(s.composite, 1), 1e-5);
}

TEST(Stitch, UnknownPixelsAreFilledOrBlackened) {
  Split s = split_real_image();
  for (int y = 100; y < 160; ++y)
    for (int x = 200; x < 300; ++x)
      for (int c = 0; c < 3; ++c) s.labels.at(c, x, y) = 1.0f;  // white: unknown
  SolverOptions o;
  StitchOptions black;
  black.unknown = UnknownMode::Black;
  const Image b = stitch(s.composite, s.labels, black, o);
  EXPECT_EQ(b.at(0, 250, 130), 0.0f);
  StitchOptions harmonic;
  const Image h = stitch(s.composite, s.labels, harmonic, o);
  EXPECT_GT(h.at(0, 250, 130), 0.05f);
  // A harmonic fill has no interior extrema: the hole's values stay within its border's range.
  float lo = 1e9f, hi = -1e9f;
  for (int x = 199; x <= 300; ++x)
    for (int y : {99, 160}) lo = std::min(lo, h.at(0, x, y)), hi = std::max(hi, h.at(0, x, y));
  for (int y = 99; y <= 160; ++y)
    for (int x : {199, 300}) lo = std::min(lo, h.at(0, x, y)), hi = std::max(hi, h.at(0, x, y));
  for (int y = 105; y < 155; ++y)
    for (int x = 205; x < 295; ++x) {
      EXPECT_GE(h.at(0, x, y), lo - 0.02f);
      EXPECT_LE(h.at(0, x, y), hi + 0.02f);
    }
}

TEST(Stitch, DerampRemovesALinearRampPerLabel) {
  // Two labels, the right one carrying a horizontal ramp: deramping flattens it.
  Image comp(64, 32, 1), labels(64, 32, 1);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      labels.at(0, x, y) = x < 32 ? 0.2f : 0.4f;
      comp.at(0, x, y) = x < 32 ? 0.5f : 0.5f + 0.01f * (x - 32);
    }
  SolverOptions o;
  o.tolerance = 1e-8;
  StitchOptions d;
  d.deramp = true;
  const Image out = stitch(comp, labels, d, o);
  EXPECT_LT(test::max_difference(out, Image(64, 32, 1, 0.5f + float(test::mean(out) - 0.5))), 1e-4);
}

TEST(Stitch, SizeMismatchIsAnInputError) {
  EXPECT_THROW(stitch(Image(10, 10, 3), Image(10, 11, 3), {}, {}), InputError);
}

}  // namespace
}  // namespace gdp

namespace gdp {
namespace {

// NaN blanks (as in FITS) give no guidance, do not spread, and come back unchanged.
TEST(NonFinite, BlanksAreKeptAndDoNotSpread) {
  Image img = test::cosine_image(64, 48, 2, 1);
  for (int y = 10; y < 20; ++y)
    for (int x = 5; x < 15; ++x) img.at(0, x, y) = std::nanf("");
  SolverOptions o;
  o.vcycles = 3;
  const ReconstructResult r = reconstruct(img, o);
  EXPECT_TRUE(std::isnan(r.image.at(0, 7, 12)));
  for (int y = 0; y < 48; ++y)
    for (int x = 30; x < 64; ++x) ASSERT_TRUE(std::isfinite(r.image.at(0, x, y)));
  // The blank region is filled smoothly for the solve and pulls a little on its surroundings
  // (its edges ask for zero gradient), so the error is small but not zero.
  EXPECT_LT(r.rms_error, 0.1);
  const Image s = sharpen(img, 0.01, 2.0, o);
  EXPECT_TRUE(std::isnan(s.at(0, 7, 12)));
  EXPECT_TRUE(std::isfinite(s.at(0, 40, 40)));
}

}  // namespace
}  // namespace gdp
