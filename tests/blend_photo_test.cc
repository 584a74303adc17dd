// gdp blend on a real photo cut into exposure-shifted layers: seams vanish, mean guidance beats zero, schedules agree.
#include <gtest/gtest.h>

#include <cmath>

#include "gdp/blend.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace gdp {
namespace {

struct Cut {
  Image photo;
  std::vector<Image> layers;
  std::vector<ImageLayer> placed;
};

// weir_1_crop.jpg (640x480) as 3x2 layers of 260x280 with 70-80 px overlaps, each shifted by its
// own exposure offset (float layers: nothing clips).
Cut cut_photo() {
  Cut c;
  c.photo = read_image(GDP_TEST_DATA "/opencv/weir_1_crop.jpg").image;
  const float offsets[6] = {0.12f, -0.10f, 0.05f, -0.15f, 0.08f, 0.0f};
  for (int r = 0; r < 2; ++r)
    for (int k = 0; k < 3; ++k) {
      const int x0 = k * 190, y0 = r * 200, w = 260, h = 280;
      Image l(w, h, 3);
      for (int ch = 0; ch < 3; ++ch)
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) l.at(ch, x, y) = c.photo.at(ch, x0 + x, y0 + y) + offsets[r * 3 + k];
      c.layers.push_back(std::move(l));
    }
  for (int n = 0; n < 6; ++n) c.placed.push_back({&c.layers[n], nullptr, (n % 3) * 190, (n / 3) * 200});
  return c;
}

double error(const Image& out, const Image& truth) { return test::rms_difference_mean_removed(out, truth); }

TEST(BlendPhoto, MeanGuidanceAcrossSeamsBeatsZero) {
  const Cut c = cut_photo();
  SolverOptions solver;
  solver.tolerance = 1e-6;
  BlendOptions zero;
  zero.seam_guidance = SeamGuidance::Zero;
  const double e_mean = error(blend(c.placed, {}, solver), c.photo);
  const double e_zero = error(blend(c.placed, zero, solver), c.photo);
  // Offsets alone: both layers' gradients are the photo's, so the mean is exact but where three
  // layers meet (there, zero).
  EXPECT_LT(e_mean, 1e-3);
  EXPECT_GT(e_zero, 10 * e_mean);
  EXPECT_LT(e_zero, 0.03);  // zero guidance removes the 0.1-0.27 steps too, leaving a faint trace
}

TEST(BlendPhoto, SchedulesAgree) {
  const Cut c = cut_photo();
  SolverOptions streaming;
  streaming.vcycles = 2;
  const Image reference = blend(c.placed, {}, streaming);
  SolverOptions in_core = streaming;
  in_core.schedule = Schedule::InCore;
  EXPECT_EQ(test::max_difference(blend(c.placed, {}, in_core), reference), 0.0);
  for (int bands : {2, 3}) {
    SolverOptions banded = streaming;
    banded.schedule = Schedule::Bands;
    banded.bands = bands;
    EXPECT_LT(test::max_difference(blend(c.placed, {}, banded), reference), 1e-4) << bands << " bands";
  }
}

}  // namespace
}  // namespace gdp
