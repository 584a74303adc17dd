// gdp blend against mathematics: one layer, agreeing layers, constant offsets, the seam rule, anchor, correction, seam files, bands, wraps.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "blend/seam_files.h"
#include "blend/seams.h"
#include "gdp/blend.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace gdp {
namespace {

// A smooth textured scene, values in about [0.2, 0.8].
Image scene(int w, int h, int channels = 1) {
  Image img(w, h, channels);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        img.at(c, x, y) = static_cast<float>(0.5 + 0.2 * std::sin(0.21 * x + c) * std::cos(0.13 * y) +
                                             0.1 * std::sin(0.05 * (x + 2 * y)));
  return img;
}

// The part [x0, x0 + w) x [y0, y0 + h) of `img`, plus `offset`.
Image crop(const Image& img, int x0, int y0, int w, int h, float offset = 0.0f) {
  Image out(w, h, img.channels);
  for (int c = 0; c < img.channels; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) out.at(c, x, y) = img.at(c, x0 + x, y0 + y) + offset;
  return out;
}

SolverOptions accurate() {
  SolverOptions o;
  o.precision = Precision::Float64;
  o.tolerance = 1e-10;
  return o;
}

TEST(BlendMath, OneLayerIsThatLayer) {
  const Image img = scene(70, 50, 3);
  Image masked = img;
  masked.channels = 4;
  masked.data.resize(masked.plane_size() * 4, 1.0f);
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 70; ++x)
      if ((x - 35) * (x - 35) + (y - 25) * (y - 25) > 24 * 24) masked.at(3, x, y) = 0.0f;  // a disc is covered
  const Image out = blend({ImageLayer{&masked, nullptr, 5, 7}}, {}, accurate());
  ASSERT_EQ(out.width, 70);
  ASSERT_EQ(out.channels, 4);
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 70; ++x) {
      const bool in = masked.at(3, x, y) == 1.0f;
      EXPECT_EQ(out.at(3, x, y), in ? 1.0f : 0.0f);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(out.at(c, x, y), in ? img.at(c, x, y) : 0.0f, 1e-5) << x << "," << y;
    }
}

TEST(BlendMath, AgreeingLayersGiveTheImage) {
  const Image img = scene(100, 60);
  const Image a = crop(img, 0, 0, 60, 60), b = crop(img, 40, 0, 60, 60);
  const Image out = blend({ImageLayer{&a, nullptr, 0, 0}, ImageLayer{&b, nullptr, 40, 0}}, {}, accurate());
  ASSERT_EQ(out.width, 100);
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 100; ++x) EXPECT_NEAR(out.at(0, x, y), img.at(0, x, y), 1e-5);
}

// Layers that differ by a constant blend without a seam, to the level the labelled areas weigh.
TEST(BlendMath, ConstantOffsetsBlendToTheWeightedMeanLevel) {
  const Image img = scene(100, 60);
  const Image a = crop(img, 0, 0, 60, 60), b = crop(img, 40, 0, 60, 60, 0.1f);
  for (const SeamGuidance g : {SeamGuidance::Zero, SeamGuidance::Mean}) {
    BlendOptions options;
    options.seam_guidance = g;
    const Image out = blend({ImageLayer{&a, nullptr, 0, 0}, ImageLayer{&b, nullptr, 40, 0}}, options, accurate());
    // Depth seams put x < 50 in a and x >= 50 in b: half the pixels carry +0.1.
    double worst = 0.0;
    for (int y = 0; y < 60; ++y)
      for (int x = 0; x < 100; ++x) worst = std::max(worst, std::abs(out.at(0, x, y) - img.at(0, x, y) - 0.05));
    EXPECT_LT(worst, g == SeamGuidance::Mean ? 1e-5 : 0.02) << (g == SeamGuidance::Mean ? "mean" : "zero");
  }
}

// --anchor: the anchor layer's pixels keep their values, the other layer levels to it.
TEST(BlendMath, AnchorKeepsOneLayerAndLevelsTheRest) {
  const Image img = scene(100, 60);
  const Image a = crop(img, 0, 0, 60, 60, 0.1f), b = crop(img, 40, 0, 60, 60);
  BlendOptions options;
  options.anchor = 0;
  const Image out = blend({ImageLayer{&a, nullptr, 0, 0}, ImageLayer{&b, nullptr, 40, 0}}, options, accurate());
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 100; ++x) EXPECT_NEAR(out.at(0, x, y), img.at(0, x, y) + 0.1f, 1e-4) << x << "," << y;
}

// --pin by layer: pinned layers keep their values exactly, the free layer between them is levelled
// to its neighbours (not to its own offset).
TEST(BlendMath, PinnedLayersKeepTheirValues) {
  const Image img = scene(150, 40);
  const Image a = crop(img, 0, 0, 60, 40), b = crop(img, 45, 0, 60, 40, 0.3f), c = crop(img, 90, 0, 60, 40, 0.1f);
  BlendOptions options;
  options.pinned = {0, 2};
  SolverOptions solver = accurate();
  const Image out = blend({ImageLayer{&a, nullptr, 0, 0}, ImageLayer{&b, nullptr, 45, 0}, ImageLayer{&c, nullptr, 90, 0}},
                          options, solver);
  // Depth seams: x < 52 takes a (its offset 0), x >= 98 takes c (0.1); b's pixels in between.
  double pinned = 0.0, free = 0.0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 150; ++x) {
      const double d = out.at(0, x, y) - img.at(0, x, y);
      if (x < 52) pinned = std::max(pinned, std::abs(d));
      if (x >= 98) pinned = std::max(pinned, std::abs(d - 0.1));
      if (x >= 53 && x < 97) free = std::max(free, std::abs(d - 0.3));
    }
  EXPECT_LT(pinned, 1e-5);
  EXPECT_GT(free, 0.15);  // b lost its own +0.3: levelled between 0 and 0.1
  EXPECT_THROW(blend({ImageLayer{&a, nullptr, 0, 0}}, options, solver), UsageError);  // layer 3 of 1
}

// --weights by layer: layers differing by constants level to the fidelity-weighted mean of their
// offsets, sum(w_k N_k o_k) / sum(w_k N_k) (N_k: the pixels taking layer k), as the weights go to
// 0 (w L^2 << 1 for a canvas L pixels across; larger weights hold each layer near its own values
// over about 1/sqrt(w) pixels from a seam); a weight image of the same weights gives the same result.
TEST(BlendMath, WeightedLayersLevelToTheWeightedMean) {
  const Image img = scene(100, 60);
  const Image a = crop(img, 0, 0, 60, 60), b = crop(img, 40, 0, 60, 60, 0.1f);
  const std::vector<ImageLayer> layers{{&a, nullptr, 0, 0}, {&b, nullptr, 40, 0}};
  for (const auto& [wa, wb] : {std::pair{1.0, 3.0}, std::pair{1.0, 0.0}, std::pair{2.0, 1.0}}) {
    BlendOptions options;
    options.weights = {1e-7 * wa, 1e-7 * wb};
    const Image out = blend(layers, options, accurate());
    const double level = 0.1 * wb / (wa + wb);  // x < 50 takes a, x >= 50 takes b: N_a = N_b
    double worst = 0.0;
    for (int y = 0; y < 60; ++y)
      for (int x = 0; x < 100; ++x) worst = std::max(worst, std::abs(out.at(0, x, y) - img.at(0, x, y) - level));
    EXPECT_LT(worst, 3e-5) << wa << ", " << wb;
  }
  Image weights(100, 60, 1);
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 100; ++x) weights.at(0, x, y) = x < 50 ? 1e-7f : 3e-7f;
  ImageRowReader weight_rows(weights);
  BlendOptions by_image, by_layer;
  by_image.fidelity.weights = &weight_rows;
  by_layer.weights = {1e-7, 3e-7};
  EXPECT_LT(test::max_difference(blend(layers, by_image, accurate()), blend(layers, by_layer, accurate())), 1e-6);
  by_layer.weights = {1.0};
  EXPECT_THROW(blend(layers, by_layer, accurate()), UsageError);
  by_layer.weights = {1.0, -1.0};
  EXPECT_THROW(blend(layers, by_layer, accurate()), UsageError);
}

// --correction: output minus the composite; here the offsets' removal, -0.05 and +0.05.
TEST(BlendMath, CorrectionIsOutputMinusLayers) {
  const Image img = scene(100, 60);
  const Image a = crop(img, 0, 0, 60, 60), b = crop(img, 40, 0, 60, 60, 0.1f);
  Image correction(100, 60, 1);
  ImageRowWriter correction_rows(correction);
  BlendOptions options;
  options.correction = &correction_rows;
  const Image out = blend({ImageLayer{&a, nullptr, 0, 0}, ImageLayer{&b, nullptr, 40, 0}}, options, accurate());
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 100; ++x) EXPECT_NEAR(correction.at(0, x, y), x < 50 ? 0.05 : -0.05, 1e-5) << x << "," << y;
}

// Seams saved, edited and loaded: a pixel takes the layer the file names where that layer covers it.
TEST(BlendMath, SeamsSavedAndLoaded) {
  const Image a(60, 40, 1, 0.2f), b(60, 40, 1, 0.7f);
  const std::vector<ImageLayer> layers{{&a, nullptr, 0, 0}, {&b, nullptr, 40, 0}};
  const std::string file = (std::filesystem::temp_directory_path() / ("gdp_seams_" + std::to_string(::getpid()) + ".tif")).string();  // gdp's label map (.png: multiblend's)
  BlendOptions save;
  save.save_seams = file;
  blend(layers, save, {});
  Image seams = read_image(file).image;
  EXPECT_NEAR(seams.at(0, 45, 10) * 255.0f, 1.0f, 1e-3);  // depth: a
  EXPECT_NEAR(seams.at(0, 55, 10) * 255.0f, 2.0f, 1e-3);  // depth: b
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 100; ++x) seams.at(0, x, y) = (x < 42 ? 1.0f : 2.0f) / 255.0f;  // the seam moved to 42
  seams.at(0, 70, 5) = 1.0f / 255.0f;  // a does not cover (70, 5): b, the first that does
  WriteOptions png;
  png.sample_type = SampleType::UInt8;
  write_image(file, seams, png);
  BlendOptions load;
  load.load_seams = file;
  const BlendPlan plan = plan_blend(layers, load);
  const auto loaded = blending::load_seams(plan, file, {});
  std::vector<blending::Label> row(100);
  loaded.labels->read_row(5, row);
  EXPECT_EQ(row[41], 1);
  EXPECT_EQ(row[42], 2);
  EXPECT_EQ(row[70], 2);
  std::filesystem::remove(file);
}

TEST(BlendMath, APixelTakesTheLayerItLiesDeepestInside) {
  const Image a(60, 40, 1, 0.2f), b(60, 40, 1, 0.7f);
  const BlendPlan plan = plan_blend({ImageLayer{&a, nullptr, 0, 0}, ImageLayer{&b, nullptr, 40, 0}}, {});
  const auto seams = blending::compute_seams(plan, false, {}, nullptr);
  std::vector<blending::Label> row(100);
  for (int y : {0, 20, 39}) {
    seams.labels->read_row(y, row);
    for (int x = 0; x < 100; ++x) {
      // Depth in a: 60 - x (the canvas edges do not count); in b: x - 39.
      const int want = x < 40 ? 1 : x >= 60 ? 2 : (60 - x > x - 39 ? 1 : 2);
      EXPECT_EQ(row[x], want) << x << "," << y;
    }
  }
  EXPECT_TRUE(seams.overlaps[0] && seams.overlaps[1]);
}

TEST(BlendMath, UncoveredPixelsAndIsolatedLayers) {
  const Image a(30, 20, 1, 0.2f), b(30, 20, 1, 0.7f);
  BlendReport report;
  const Image out = blend({ImageLayer{&a, nullptr, 0, 0}, ImageLayer{&b, nullptr, 50, 10}}, {}, accurate(), &report);
  ASSERT_EQ(out.width, 80);
  ASSERT_EQ(out.height, 30);
  EXPECT_EQ(report.isolated.size(), 2u);
  EXPECT_EQ(out.at(1, 40, 5), 0.0f);  // alpha: nothing covers it
  EXPECT_EQ(out.at(0, 40, 5), 0.0f);
  EXPECT_EQ(out.at(1, 10, 5), 1.0f);
  // Each keeps its level, up to the shared correction that keeps the mean.
  EXPECT_NEAR(out.at(0, 60, 20) - out.at(0, 10, 5), 0.5, 1e-4);
}

TEST(BlendMath, TwoBandsAgreeWithOne) {
  const Image img = scene(160, 96, 3);
  const Image a = crop(img, 0, 0, 100, 70, 0.05f), b = crop(img, 60, 20, 100, 76, -0.05f);
  const std::vector<ImageLayer> layers{{&a, nullptr, 0, 0}, {&b, nullptr, 60, 20}};
  SolverOptions one;
  const Image reference = blend(layers, {}, one);
  SolverOptions bands = one;
  bands.schedule = Schedule::Bands;
  bands.bands = 2;
  EXPECT_LT(test::max_difference(blend(layers, {}, bands), reference), 1e-4);
}

// A 360-degree panorama: two layers that meet only across the 0/360 edge are levelled to each
// other there with --wrap horizontal, and keep their own levels without it.
TEST(BlendMath, HorizontalWrapJoinsTheEdges) {
  const int w = 120, h = 40;
  Image img(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(0, x, y) = static_cast<float>(0.5 + 0.2 * std::cos(2 * M_PI * x / w) + 0.002 * y);
  const Image a = crop(img, 0, 0, 40, h), b = crop(img, 80, 0, 40, h, 0.1f);
  const std::vector<ImageLayer> layers{{&a, nullptr, 0, 0}, {&b, nullptr, 80, 0}};
  const auto jump = [&](const Image& out) {  // across the 0/360 edge, against the scene's own step
    double s = 0.0;
    for (int y = 0; y < h; ++y) s += std::abs((out.at(0, 0, y) - out.at(0, w - 1, y)) - (img.at(0, 0, y) - img.at(0, w - 1, y)));
    return s / h;
  };
  BlendOptions wrap;
  wrap.wrap = Wrap::Horizontal;
  EXPECT_LT(jump(blend(layers, wrap, accurate())), 0.002);
  EXPECT_NEAR(jump(blend(layers, {}, accurate())), 0.1, 0.002);
}

// A full sphere (2:1, --wrap both): solved on the PQ domain and resampled back.
TEST(BlendMath, FullSphereBlends) {
  const int w = 128, h = 64;
  const Image img = scene(w, h);
  const Image a = crop(img, 0, 0, 72, h), b = crop(img, 56, 0, 72, h, 0.1f);
  BlendOptions sphere;
  sphere.wrap = Wrap::Both;
  const Image out = blend({{&a, nullptr, 0, 0}, {&b, nullptr, 56, 0}}, sphere, {});
  ASSERT_EQ(out.width, w);
  double step = 0.0;  // across the seam at x = 64, against the scene's own step
  for (int y = 8; y < h - 8; ++y) step += std::abs((out.at(0, 64, y) - out.at(0, 63, y)) - (img.at(0, 64, y) - img.at(0, 63, y)));
  EXPECT_LT(step / (h - 16), 0.02);
  EXPECT_EQ(out.at(1, 10, 10), 1.0f);
}

}  // namespace
}  // namespace gdp
