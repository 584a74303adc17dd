// Mean guidance across seams where one layer does not reach across: seams ending at uncovered canvas, triple junctions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "gdp/blend.h"

namespace gdp {
namespace {

// A scene with strong gradients everywhere (about 0.04 a pixel), values in [0.2, 0.8].
float scene(int c, int x, int y) {
  return static_cast<float>(0.5 + 0.2 * std::sin(0.21 * x + c) * std::cos(0.13 * y) + 0.1 * std::sin(0.05 * (x + 2 * y)));
}

struct Rect {
  int x0, y0, w, h;
};

// The scene over `r`, one channel.
Image layer_of(const Rect& r) {
  Image img(r.w, r.h, 1);
  for (int y = 0; y < r.h; ++y)
    for (int x = 0; x < r.w; ++x) img.at(0, x, y) = scene(0, r.x0 + x, r.y0 + y);
  return img;
}

// Blends the scene's layers over `rects` (all agreeing: every gradient the guidance needs is the
// scene's) and returns the largest difference from the scene over covered pixels, mean removed.
double blend_error(const std::vector<Rect>& rects, SeamGuidance guidance) {
  std::vector<Image> images;
  for (const Rect& r : rects) images.push_back(layer_of(r));
  std::vector<ImageLayer> layers;
  for (std::size_t k = 0; k < rects.size(); ++k) layers.push_back(ImageLayer{&images[k], nullptr, rects[k].x0, rects[k].y0});
  BlendOptions options;
  options.seam_guidance = guidance;
  SolverOptions solver;
  solver.precision = Precision::Float64;
  solver.tolerance = 1e-10;
  const Image out = blend(layers, options, solver);
  std::vector<double> d;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      if (out.at(1, x, y) > 0.5f) d.push_back(double(out.at(0, x, y)) - scene(0, x, y));
  EXPECT_GT(d.size(), 0u);
  double mean = 0.0;
  for (const double v : d) mean += v / d.size();
  double worst = 0.0;
  for (const double v : d) worst = std::max(worst, std::abs(v - mean));
  return worst;
}

// A layer's corner beside another's edge: uncovered canvas at the top right, where the depth seam
// through the overlap ends. The layer across the seam's last pixels does not cover both ends of
// their edges, so the mean of both layers' gradients is not there; the one layer's that is (it
// covers both pixels) is the scene's, and agreeing layers give the scene exactly.
TEST(BlendSeamGuidance, SeamEndingAtUncoveredCanvasKeepsTheKnownGradient) {
  const std::vector<Rect> corner = {{0, 0, 40, 48}, {24, 20, 40, 28}};
  EXPECT_LT(blend_error(corner, SeamGuidance::Mean), 1e-5);
  // Zero guidance across the seam loses the scene's gradients there (the control: an error to fix).
  EXPECT_GT(blend_error(corner, SeamGuidance::Zero), 1e-3);
}

// Three layers meeting: a pixel beside two other layers has two across values, one for the layer
// beside it (left or right) and one for the layer above or below it, so every seam edge finds the
// layer across it and agreeing layers give the scene as along a plain seam. (With one across
// value a pixel, the edges at the junction whose two ends both saw two other layers kept zero:
// 2.8e-3 here.)
TEST(BlendSeamGuidance, TripleJunctionsTakeBothLayersGradients) {
  const std::vector<Rect> three = {{0, 0, 40, 40}, {28, 0, 36, 40}, {10, 28, 44, 30}};
  const double mean = blend_error(three, SeamGuidance::Mean), zero = blend_error(three, SeamGuidance::Zero);
  std::printf("triple junction: worst error %.3g with mean guidance, %.3g with zero\n", mean, zero);
  EXPECT_LT(mean, 1e-5);
  EXPECT_GT(zero, 1e-3);
}

// Four layers on a 2x2 grid with overlaps (every corner of a grid of photos): the seams cross at
// one point, where pixels see two other layers, and the blend is the scene.
TEST(BlendSeamGuidance, FourLayersMeetingAtAPointGiveTheScene) {
  const std::vector<Rect> four = {{0, 0, 36, 36}, {24, 0, 36, 36}, {0, 24, 36, 36}, {24, 24, 36, 36}};
  const double mean = blend_error(four, SeamGuidance::Mean);
  std::printf("four layers at a point: worst error %.3g with mean guidance\n", mean);
  EXPECT_LT(mean, 1e-5);
}

}  // namespace
}  // namespace gdp
