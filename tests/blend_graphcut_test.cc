// Graph-cut seams: never costlier than the depth seams, in the agreeing band when there is one, around a ghost end to end.
#include <gtest/gtest.h>

#include <cmath>

#include "blend/graphcut_seams.h"
#include "blend/layer_rows.h"
#include "cli_fixture.h"
#include "gdp/blend.h"
#include "gdp/image_io.h"
#include "nona_tiff.h"
#include "test_util.h"

namespace gdp {
namespace {

// Deterministic values in [0, 1).
float hash01(int x, int y, int salt) {
  unsigned h = static_cast<unsigned>(x) * 73856093u ^ static_cast<unsigned>(y) * 19349663u ^ static_cast<unsigned>(salt) * 83492791u;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return static_cast<float>(h & 0xffffff) / 16777216.0f;
}

std::vector<std::vector<blending::Label>> rows_of(const blending::LabelPlane& p) {
  std::vector<std::vector<blending::Label>> rows(p.height(), std::vector<blending::Label>(p.width()));
  for (int y = 0; y < p.height(); ++y) p.read_row(y, rows[y]);
  return rows;
}

// Every pixel takes a layer that covers it, and a pixel only one layer covers takes that one.
void expect_valid(const BlendPlan& plan, const blending::LabelPlane& labels) {
  const auto rows = rows_of(labels);
  for (int y = 0; y < plan.canvas.height; ++y)
    for (int x = 0; x < plan.canvas.width; ++x) {
      int covering = 0, only = 0;
      for (int k = 0; k < static_cast<int>(plan.layers.size()); ++k) {
        const blending::Footprint f = blending::footprint(plan, k);
        const bool in = x >= f.x0 && x < f.x1 && y >= f.y0 && y < f.y1;
        covering += in;
        if (in) only = k + 1;
        if (rows[y][x] == k + 1) {
          ASSERT_TRUE(in) << x << "," << y;
        }
      }
      if (covering == 1) {
        ASSERT_EQ(rows[y][x], only) << x << "," << y;
      }
      if (covering == 0) {
        ASSERT_EQ(rows[y][x], 0) << x << "," << y;
      }
    }
}

// Two layers of one noisy image overlapping in canvas columns [40, 100); they agree exactly in
// [80, 86) only (elsewhere the second is 0.2-0.5 brighter): the cheapest seam lies in that band.
TEST(GraphcutSeams, CutLiesWhereTheLayersAgree) {
  Image a(100, 60, 3), b(100, 60, 3);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < 60; ++y)
      for (int x = 0; x < 100; ++x) {
        a.at(c, x, y) = hash01(x, y, c);
        const int cx = x + 40;
        b.at(c, x, y) = hash01(cx, y, c) + (cx >= 80 && cx < 86 ? 0.0f : 0.2f + 0.3f * hash01(cx, y, 7 + c));
      }
  const BlendPlan plan = plan_blend({ImageLayer{&a, nullptr, 0, 0}, ImageLayer{&b, nullptr, 40, 0}}, {});
  for (int scale : {1, 4}) {
    blending::GraphcutOptions options;
    options.scale = scale;
    const auto seams = blending::compute_graphcut_seams(plan, false, {}, nullptr, options);
    EXPECT_GT(seams.depth_cost, 10.0);
    EXPECT_NEAR(seams.cost, 0.0, 1e-9) << "scale " << scale;
    const auto rows = rows_of(*seams.labels);
    for (int y = 0; y < 60; ++y)
      for (int x = 0; x < 140; ++x) {
        if (x < 80 || x >= 86) {
          ASSERT_EQ(rows[y][x], x < 80 ? 1 : 2) << x << "," << y << " scale " << scale;
        }
      }
    const auto check = blending::seam_costs(plan, {seams.labels.get()}, false);
    EXPECT_NEAR(check[0], seams.cost, 1e-9);
    expect_valid(plan, *seams.labels);
  }
}

// A real photo (tests/data) cut into 3x2 overlapping layers, each with its own exposure offset,
// grain, and a moving object (a disc) somewhere in its overlaps.
struct Layers {
  std::vector<Image> images;
  std::vector<ImageLayer> placed;
};

Layers photo_layers(float grain) {
  const Image photo = read_image(GDP_TEST_DATA "/opencv/weir_1_crop.jpg").image;
  const float offsets[6] = {0.12f, -0.10f, 0.05f, -0.15f, 0.08f, 0.0f};
  Layers l;
  for (int n = 0; n < 6; ++n) {
    const int x0 = (n % 3) * 190, y0 = (n / 3) * 200, w = 260, h = 280;
    const int gx = 200 + 37 * n % 60, gy = 190 + 23 * n % 80;  // the disc, in canvas pixels
    Image img(w, h, 3);
    for (int c = 0; c < 3; ++c)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const int cx = x0 + x, cy = y0 + y;
          const bool disc = (cx - gx) * (cx - gx) + (cy - gy) * (cy - gy) < 400;
          img.at(c, x, y) = disc ? 0.9f - 0.3f * c : photo.at(c, cx, cy) + offsets[n] + grain * hash01(cx, cy, n * 3 + c);
        }
    l.images.push_back(std::move(img));
  }
  for (int n = 0; n < 6; ++n) l.placed.push_back({&l.images[n], nullptr, (n % 3) * 190, (n / 3) * 200});
  return l;
}

TEST(GraphcutSeams, NeverCostlierThanDepthSeamsOnAPhoto) {
  {
    const float grain = 0.1f;
    const Layers l = photo_layers(grain);
    const BlendPlan plan = plan_blend(l.placed, {});
    const auto depth = blending::compute_seams(plan, false, {}, nullptr);
    for (int scale : {0, 8}) {  // 0: min(W, H) / 128 = 3
      blending::GraphcutOptions options;
      options.scale = scale;
      const auto cut = blending::compute_graphcut_seams(plan, false, {}, nullptr, options);
      const auto costs = blending::seam_costs(plan, {depth.labels.get(), cut.labels.get()}, false);
      EXPECT_NEAR(costs[0], cut.depth_cost, 1e-6 * costs[0]);
      EXPECT_NEAR(costs[1], cut.cost, 1e-6 * costs[0]);
      EXPECT_LE(costs[1], costs[0]) << "grain " << grain << " scale " << scale;
      EXPECT_LT(costs[1], 0.95 * costs[0]) << "grain " << grain << " scale " << scale;  // it does move the seams
      expect_valid(plan, *cut.labels);
    }
    // With the canvas's left and right edges joined the labels stay valid and no costlier.
    const auto wrapped = blending::compute_graphcut_seams(plan, true, {}, nullptr);
    EXPECT_LE(wrapped.cost, wrapped.depth_cost);
    expect_valid(plan, *wrapped.labels);
  }
}

double error(const Image& out, const Image& truth) { return test::rms_difference_mean_removed(out, truth); }

class GraphcutCli : public test::CliFixture {};

// Two nona layers of a photo (0.9 x its values), exposures 0.1 apart; a magenta object entering
// the second layer at its left edge (columns 260-344 of the canvas): the depth seam (column 320)
// cuts it and shows its left part. The seam cost keeps seams from cutting through the object, and
// the only way around it is to its right: graph-cut seams leave it out.
TEST_F(GraphcutCli, GhostInTheOverlapIsLeftOut) {
  const Image photo = read_image(GDP_TEST_DATA "/opencv/weir_1_crop.jpg").image;
  Image a(380, 480, 4, 1.0f), b(380, 480, 4, 1.0f);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < 480; ++y)
      for (int x = 0; x < 380; ++x) {
        a.at(c, x, y) = 0.9f * photo.at(c, x, y);
        const int bx = x + 260;
        const bool ghost = bx < 345 && y >= 200 && y < 250;
        b.at(c, x, y) = ghost ? (c == 1 ? 0.0f : 1.0f) : 0.1f + 0.9f * photo.at(c, bx, y);
      }
  test::write_nona_tiff(path("a.tif"), {{&a, 0, 0, 16}}, 640, 480);
  test::write_nona_tiff(path("b.tif"), {{&b, 260, 0, 16}}, 640, 480);
  double e[2];
  const char* methods[2] = {"depth", "graphcut"};
  for (int m = 0; m < 2; ++m) {
    const std::string out = path(std::string("out_") + methods[m] + ".tif");
    const auto r = gdp(std::string("blend --seams ") + methods[m] + " --tolerance 1e-5 -o " + out + " " + path("a.tif") +
                       " " + path("b.tif"));
    ASSERT_EQ(r.code, 0) << r.err;
    Image truth(640, 480, 3);
    for (int c = 0; c < 3; ++c)
      for (int y = 0; y < 480; ++y)
        for (int x = 0; x < 640; ++x) truth.at(c, x, y) = 0.9f * photo.at(c, x, y);
    e[m] = error(read_image(out).image, truth);
  }
  EXPECT_LE(e[1], e[0]);
  EXPECT_LT(e[1], 0.2 * e[0]) << "depth " << e[0] << ", graphcut " << e[1];
}

}  // namespace
}  // namespace gdp
