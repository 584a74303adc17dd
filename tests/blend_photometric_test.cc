// gdp blend --photometric: exposure and vignetting fitted to the overlaps of a real photo's layers, and applied.
#include <gtest/gtest.h>

#include <cmath>

#include "blend/photometric.h"
#include "blend/photometric_fit.h"
#include "cli_fixture.h"
#include "gdp/blend.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "test_util.h"
#include "weir_layers.h"

namespace gdp {
namespace {

using Cut = test::WeirLayers;
constexpr int kLayers = test::kWeirLayers;

// The layers with vignetting v and gains `gain` (weir_layers.h).
Cut cut_photo(double v, const double* gain) { return test::cut_weir(v, gain); }

const double kGains[kLayers] = {1.06, 0.95, 1.0, 1.1, 0.92, 0.97};
const double kUnity[kLayers] = {1, 1, 1, 1, 1, 1};

BlendOptions photometric(int terms = 3) {
  BlendOptions o;
  o.photometric.enabled = true;
  o.photometric.vignetting_terms = terms;
  return o;
}

SolverOptions solver() {
  SolverOptions s;
  s.tolerance = 1e-6;
  return s;
}

// The largest difference of the fitted falloff from 1 - v t over t in [0, 1].
double falloff_error(const Photometry& p, double v) {
  double worst = 0.0;
  for (double t = 0.0; t <= 1.0; t += 0.05)
    worst = std::max(worst, std::fabs(blending::vignetting_gain(p.vignetting, t) - (1.0 - v * t)));
  return worst;
}

TEST(BlendPhotometric, FitRecoversVignettingAndGains) {
  const Cut c = cut_photo(0.3, kGains);
  double mean = 0.0;
  for (const double g : kGains) mean += g / kLayers;
  for (const int terms : {1, 3}) {
    BlendReport r;
    const BlendPlan plan = plan_blend(c.placed, photometric(terms));
    const Photometry p = blending::calibrate(plan, photometric(terms).photometric, &r);
    ASSERT_EQ(p.layers.size(), static_cast<std::size_t>(kLayers));
    ASSERT_EQ(p.vignetting.size(), static_cast<std::size_t>(terms));
    // The falloff within 0.02 of the truth over the whole radius (one term: its coefficient).
    EXPECT_LT(falloff_error(p, 0.3), 0.02) << terms << " terms";
    if (terms == 1) {
      EXPECT_NEAR(p.vignetting[0], -0.3, 0.02);
    }
    // The gains up to their common scale (the gauge: mean 1).
    for (int k = 0; k < kLayers; ++k) EXPECT_NEAR(p.layers[k].gain, kGains[k] / mean, 0.01) << "layer " << k;
    EXPECT_LT(r.photometric_rms_after, 0.2 * r.photometric_rms_before);
    EXPECT_GT(r.photometric_points, 1000);
  }
}

// Overlaps seen only at the layers' centres (t = 0) say nothing of the falloff: without its ridge
// the normal equations are singular, and the fit says so rather than guessing; with it, it is 0.
TEST(BlendPhotometric, UndeterminedFalloffIsAnErrorWithoutItsRidge) {
  blending::OverlapSamples s;
  s.layers = 2;
  s.channels = 1;
  for (int p = 0; p < 50; ++p) {
    for (int k = 0; k < 2; ++k) s.obs.push_back({k, 0.0f, {(0.2f + 0.01f * p) * (k ? 1.1f : 1.0f), 0.0f, 0.0f}});
    s.start.push_back(static_cast<std::uint32_t>(s.obs.size()));
  }
  blending::PhotometricFit f;
  f.vignetting_prior = 0.0;
  EXPECT_THROW(blending::fit_photometry(s, 1, f), Error);
  f.vignetting_prior = 1e-7;
  const blending::PhotometricResult r = blending::fit_photometry(s, 1, f);
  EXPECT_EQ(r.vignetting[0], 0.0);
  EXPECT_NEAR(r.gains[1] / r.gains[0], 1.1, 1e-3);
}

TEST(BlendPhotometric, CalibratedBlendIsNearerThePhoto) {
  const Cut c = cut_photo(0.3, kGains);
  const double plain = test::rms_difference_mean_removed(blend(c.placed, {}, solver()), c.photo);
  BlendReport r;
  const Image calibrated = blend(c.placed, photometric(), solver(), &r);
  // The calibrated blend is the photo up to the fitted gains' common scale: compare it scaled.
  const double e = test::rms_difference_mean_removed(calibrated, c.photo);
  EXPECT_LT(e, 0.25 * plain) << "plain " << plain << ", calibrated " << e;
  EXPECT_FALSE(r.photometry.layers.empty());
}

TEST(BlendPhotometric, NoVignettingNoChange) {
  const Cut c = cut_photo(0.0, kUnity);
  BlendReport r;
  const Image calibrated = blend(c.placed, photometric(), solver(), &r);
  EXPECT_LT(falloff_error(r.photometry, 0.0), 0.01);
  for (const LayerPhotometry& l : r.photometry.layers) EXPECT_NEAR(l.gain, 1.0, 0.01);
  const Image plain = blend(c.placed, {}, solver());
  EXPECT_LT(test::rms_difference_mean_removed(calibrated, plain), 2e-3);
}

TEST(BlendPhotometric, CentresAreChecked) {
  const Cut c = cut_photo(0.0, kUnity);
  BlendOptions o = photometric();
  o.photometric.centres.resize(2);
  EXPECT_THROW(blend(c.placed, o, solver()), UsageError);
  o = photometric(4);
  EXPECT_THROW(blend(c.placed, o, solver()), UsageError);
  // Stated centres: the layers' own, given explicitly, fit as the default does.
  o = photometric(1);
  for (int k = 0; k < kLayers; ++k) o.photometric.centres.push_back({129.5, 139.5, 0.0});
  const Cut v = cut_photo(0.3, kUnity);
  BlendReport r;
  blend(v.placed, o, solver(), &r);
  EXPECT_NEAR(r.photometry.vignetting[0], -0.3, 0.02);
}

// More layers than one dense fit takes: refused before any layer is sampled.
TEST(BlendPhotometric, TooManyLayersAreRefused) {
  const Image tile(4, 4, 3, 0.5f);
  std::vector<ImageLayer> tiles;
  for (std::size_t n = 0; n <= blending::kMaxPhotometricLayers; ++n)
    tiles.push_back({&tile, nullptr, static_cast<int>(n % 40) * 3, static_cast<int>(n / 40) * 3});
  EXPECT_THROW(blend(tiles, photometric(), solver()), UsageError);
  tiles.resize(blending::kMaxPhotometricLayers);
  EXPECT_NO_THROW(blending::calibrate(plan_blend(tiles, photometric()), photometric().photometric));
}

class BlendPhotometricCli : public test::CliFixture {};

TEST_F(BlendPhotometricCli, BadOptionsAreOneLine) {
  Image a(40, 30, 3, 0.5f);
  write_image(path("a.tif"), a, {});
  write_image(path("b.tif"), a, {});
  const std::string layers = " -o " + path("o.tif") + " " + path("a.tif") + " " + path("b.tif");
  expect_failure("blend --photometric --vignetting-terms 5" + layers, "--vignetting-terms 5");
  expect_failure("blend --vignetting-terms 2" + layers, "--photometric");
  expect_failure("blend --photometric --vignetting-centres " + path("none.txt") + layers, "none.txt");
  std::ofstream(path("c.txt")) << "10 10\n";
  expect_failure("blend --photometric --vignetting-centres " + path("c.txt") + layers, "1 given for 2 layers");
  std::ofstream(path("d.txt")) << "10 ten\n";
  expect_failure("blend --photometric --vignetting-centres " + path("d.txt") + layers, "d.txt:1");
  std::ofstream(path("e.txt")) << "# x y\n10 10\n1,2 3\n";  // one number each, not a list
  expect_failure("blend --photometric --vignetting-centres " + path("e.txt") + layers, "e.txt:3");
  const test::CliRun ok = gdp("blend --photometric" + layers);
  EXPECT_EQ(ok.code, 0) << ok.err;
}

}  // namespace
}  // namespace gdp
