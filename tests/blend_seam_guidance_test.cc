// Mean guidance across seams where one layer does not reach across: seams ending at uncovered canvas, triple junctions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

// Three layers meeting: a pixel beside two other layers has no across value (one value a pixel
// cannot be both layers'), and the value known at the edge's other end supplies the gradient.
// Only edges whose two ends both see two other layers, at the junction itself, keep zero: the
// error left is a few times smaller than zero guidance's along every seam.
TEST(BlendSeamGuidance, TripleJunctionsKeepMostOfTheScenesGradients) {
  const std::vector<Rect> three = {{0, 0, 40, 40}, {28, 0, 36, 40}, {10, 28, 44, 30}};
  const double mean = blend_error(three, SeamGuidance::Mean), zero = blend_error(three, SeamGuidance::Zero);
  EXPECT_LT(mean, 0.5 * zero);
  EXPECT_LT(mean, 5e-3);
}

}  // namespace
}  // namespace gdp
