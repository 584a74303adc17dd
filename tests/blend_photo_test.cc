// gdp blend on a real photo cut into exposure-shifted layers: seams vanish, mean guidance beats zero, schedules agree.
#include <gtest/gtest.h>

#include <cmath>

#include "gdp/blend.h"
#include "gdp/image_io.h"
#include "test_util.h"
#include "weir_layers.h"

namespace gdp {
namespace {

using Cut = test::WeirLayers;
Cut cut_photo() { return test::cut_weir(); }

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
