// Blending spaces for stitching: Lab conversions, and log blending removing exposure gains exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "apps/colour_space.h"
#include "gdp/apps.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace gdp {
namespace {

std::vector<float> lab_of(float r, float g, float b, bool srgb) {
  std::vector<float> row{r, g, b};
  BlendSpace s;
  s.kind = BlendSpace::Kind::Lab;
  s.srgb_encoded = srgb;
  apps::to_space(s, row, 1, 3);
  return row;
}

TEST(BlendSpace, LabOfKnownColours) {
  // CIE L*a*b* (D65) of sRGB white, black, red and mid grey.
  const auto white = lab_of(1, 1, 1, true), black = lab_of(0, 0, 0, true), red = lab_of(1, 0, 0, true);
  EXPECT_NEAR(white[0], 100.0, 1e-3);
  EXPECT_NEAR(white[1], 0.0, 1e-2);
  EXPECT_NEAR(white[2], 0.0, 1e-2);
  EXPECT_NEAR(black[0], 0.0, 1e-4);
  EXPECT_NEAR(red[0], 53.24, 0.01);
  EXPECT_NEAR(red[1], 80.09, 0.02);
  EXPECT_NEAR(red[2], 67.20, 0.02);
  EXPECT_NEAR(lab_of(0.5f, 0.5f, 0.5f, true)[0], 53.39, 0.01);   // sRGB 0.5 is 21.4% linear
  EXPECT_NEAR(lab_of(0.5f, 0.5f, 0.5f, false)[0], 76.07, 0.01);  // linear 0.5
}

TEST(BlendSpace, RoundTripsAreExact) {
  const Image img = test::random_image(50, 4, 4, 2);  // a fourth channel passes through
  for (auto kind : {BlendSpace::Kind::Log, BlendSpace::Kind::Lab})
    for (bool srgb : {false, true}) {
      BlendSpace s;
      s.kind = kind;
      s.srgb_encoded = srgb;
      for (int y = 0; y < img.height; ++y) {
        std::vector<float> row(4 * 50);
        ImageRowReader(img).read_row(y, row);
        const std::vector<float> before = row;
        apps::to_space(s, row, 50, 4);
        apps::from_space(s, row, 50, 4);
        for (std::size_t k = 0; k < row.size(); ++k) EXPECT_NEAR(row[k], before[k], 2e-5);
      }
    }
}

TEST(BlendSpace, LogBlendingRemovesExposureGainsExactly) {
  // Regions of a real photo under different exposure gains: in log space a gain is an offset,
  // which stitching removes exactly: the result is the photo times one gain. Blending the
  // values themselves leaves the gains in the gradients.
  const Image photo = read_image(GDP_TEST_DATA "/opencv/weir_1_crop.jpg").image;
  const int w = 240, h = 180;
  Image original(w, h, 3), composite(w, h, 3), labels(w, h, 1);
  const double gain[4] = {1.0, 1.6, 0.7, 1.25};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int r = (x < w / 2 ? 0 : 1) + (y < h / 2 ? 0 : 2);
      labels.at(0, x, y) = r / 4.0f;
      for (int c = 0; c < 3; ++c) {
        original.at(c, x, y) = photo.at(c, x + 100, y + 100) + 0.05f;  // no zeros: log's offset stays small
        composite.at(c, x, y) = static_cast<float>(original.at(c, x, y) * gain[r]);
      }
    }
  // How far the result is from the photo times one gain: |u - c o| / |u|, c the best gain.
  const auto spread = [&](const Image& u) {
    double uo = 0.0, oo = 0.0, uu = 0.0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double a = u.at(1, x, y), b = original.at(1, x, y);
        uo += a * b;
        oo += b * b;
        uu += a * a;
      }
    return std::sqrt(std::max(0.0, uu - uo * uo / oo) / uu);
  };
  SolverOptions o;
  o.tolerance = 1e-6;
  StitchOptions st;
  st.space.kind = BlendSpace::Kind::Log;
  st.space.log_offset = 1e-6;
  const double log_spread = spread(stitch(composite, labels, st, o));
  st.space.kind = BlendSpace::Kind::Values;
  const double value_spread = spread(stitch(composite, labels, st, o));
  // Stitching drops the photo's own gradients across the seams: the ungained photo stitched in
  // log space shows that floor. With gains, log blending stays at it; value blending does not.
  st.space.kind = BlendSpace::Kind::Log;
  const double floor = spread(stitch(original, labels, st, o));
  EXPECT_NEAR(log_spread, floor, 1e-3 * floor);  // measured: 0.0060690 vs 0.0060688
  EXPECT_GT(value_spread, 2 * log_spread);         // measured: 0.107
}

}  // namespace
}  // namespace gdp
