// gdp blend's parallel paths give the one-thread result: seams on several workers, the canvas sweep on its own thread.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include <unistd.h>

#include "blend/across_label.h"
#include "blend/canvas_rows.h"
#include "blend/graphcut_seams.h"
#include "blend/seams.h"
#include "gdp/blend.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace gdp {
namespace {

// Layers of random sizes at random places, each with alpha: a disc of holes (alpha 0) and a
// few NaN pixels (not covered either), so that depths are irregular and ties happen.
std::vector<Image> random_layers(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<Image> images;
  for (int k = 0; k < count; ++k) {
    const int w = 30 + static_cast<int>(rng() % 70), h = 40 + static_cast<int>(rng() % 120);
    Image img(w, h, 2, 0.1f + 0.05f * k);
    const int cx = static_cast<int>(rng() % w), cy = static_cast<int>(rng() % h), r = 3 + static_cast<int>(rng() % 8);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        img.at(0, x, y) += 0.001f * static_cast<float>((x * 7 + y * 3) % 11);
        img.at(1, x, y) = (x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r ? 0.0f : 1.0f;
      }
    for (int n = 0; n < 5; ++n)
      img.at(0, static_cast<int>(rng() % w), static_cast<int>(rng() % h)) = std::numeric_limits<float>::quiet_NaN();
    images.push_back(std::move(img));
  }
  return images;
}

std::vector<ImageLayer> placed(const std::vector<Image>& images, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<ImageLayer> layers;
  for (const Image& img : images)
    layers.push_back({&img, nullptr, static_cast<long long>(rng() % 150), static_cast<long long>(rng() % 200)});
  return layers;
}

std::vector<blending::Label> all_labels(const blending::LabelPlane& plane) {
  std::vector<blending::Label> all(static_cast<std::size_t>(plane.width()) * plane.height());
  for (int y = 0; y < plane.height(); ++y)
    plane.read_row(y, std::span<blending::Label>(all.data() + static_cast<std::size_t>(y) * plane.width(),
                                                 plane.width()));
  return all;
}

// The depth seams computed on whole planes, as docs/blend.md defines them (two chamfer passes
// per layer over its footprint, the canvas's edges not counting, the deepest layer per pixel,
// ties to the earlier layer): a reference for the streamed, blocked passes (no wrap).
std::vector<blending::Label> whole_plane_labels(const BlendPlan& plan, const std::vector<Image>& images,
                                                const std::vector<ImageLayer>& layers) {
  constexpr float kInf = 1e30f, kA = 1.0f, kB = 1.41421356f, kC = 2.23606798f;
  const int W = plan.canvas.width, H = plan.canvas.height;
  std::vector<float> best(static_cast<std::size_t>(W) * H, 0.0f);
  std::vector<blending::Label> label(best.size(), 0);
  for (std::size_t k = 0; k < images.size(); ++k) {
    const Image& img = images[k];
    const int x0 = static_cast<int>(layers[k].x - plan.canvas.x), y0 = static_cast<int>(layers[k].y - plan.canvas.y);
    const int w = img.width, h = img.height;
    const float left = x0 > 0 ? 0.0f : kInf, right = x0 + w < W ? 0.0f : kInf;
    const float above = y0 > 0 ? 0.0f : kInf, below = y0 + h < H ? 0.0f : kInf;
    std::vector<float> d(static_cast<std::size_t>(w) * h);
    // Distance at (x, y), beyond the layer's rows: `outside`; beyond its columns: left or right.
    const auto at = [&](int x, int y, float outside) {
      if (y < 0 || y >= h) return outside;
      return x < 0 ? left : x >= w ? right : d[static_cast<std::size_t>(y) * w + x];
    };
    for (const int dir : {1, -1}) {
      const float outside = dir > 0 ? above : below;
      for (int i = 0; i < h; ++i) {
        const int y = dir > 0 ? i : h - 1 - i;
        for (int j = 0; j < w; ++j) {
          const int x = dir > 0 ? j : w - 1 - j;
          float& v = d[static_cast<std::size_t>(y) * w + x];
          const bool covered = img.at(1, x, y) >= 0.5f && std::isfinite(img.at(0, x, y));
          if (dir > 0) v = covered ? kInf : 0.0f;
          if (v <= 0.0f) continue;
          const int n = y - dir, f = y - 2 * dir;
          v = std::min({v, at(x - dir, y, outside) + kA, at(x, n, outside) + kA, at(x - 1, n, outside) + kB,
                        at(x + 1, n, outside) + kB, at(x - 2, n, outside) + kC, at(x + 2, n, outside) + kC,
                        at(x - 1, f, outside) + kC, at(x + 1, f, outside) + kC});
        }
      }
    }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y0 + y) * W + x0 + x;
        if (d[static_cast<std::size_t>(y) * w + x] > best[i]) {
          best[i] = d[static_cast<std::size_t>(y) * w + x];
          label[i] = static_cast<blending::Label>(k + 1);
        }
      }
  }
  return label;
}

// Several rows blocks tall (the backward pass works in blocks of up to 64 rows), plain and
// wrapped: every worker count gives one thread's labels and overlaps, bit for bit.
TEST(BlendParallel, SeamsOnSeveralWorkersAreTheOneThreadLabels) {
  const std::vector<Image> images = random_layers(14, 5);
  const std::vector<ImageLayer> layers = placed(images, 9);
  const BlendPlan plan = plan_blend(layers, {});
  ASSERT_GT(plan.canvas.height, 3 * 64);
  for (const bool wrap : {false, true}) {
    const auto one = blending::compute_seams(plan, wrap, {}, nullptr, 1);
    const std::vector<blending::Label> want = all_labels(*one.labels);
    if (!wrap) {
      EXPECT_EQ(want, whole_plane_labels(plan, images, layers));
    }
    int labelled = 0;
    for (const auto l : want) labelled += l != 0;
    ASSERT_GT(labelled, static_cast<int>(want.size()) / 2);
    for (const int threads : {2, 3, 8}) {
      const auto many = blending::compute_seams(plan, wrap, {}, nullptr, threads);
      EXPECT_EQ(all_labels(*many.labels), want) << threads << " workers, wrap " << wrap;
      EXPECT_EQ(many.overlaps, one.overlaps) << threads << " workers, wrap " << wrap;
    }
  }
}

// Graph-cut seams start from the depth seams on its workers: the same cut on any number.
TEST(BlendParallel, GraphcutSeamsOnSeveralWorkersAreTheOneThreadCut) {
  const std::vector<Image> images = random_layers(8, 21);
  const BlendPlan plan = plan_blend(placed(images, 4), {});
  const auto one = blending::compute_graphcut_seams(plan, false, {}, nullptr, {.scale = 2, .threads = 1});
  const auto many = blending::compute_graphcut_seams(plan, false, {}, nullptr, {.scale = 2, .threads = 3});
  EXPECT_EQ(all_labels(*many.labels), all_labels(*one.labels));
  EXPECT_EQ(many.overlaps, one.overlaps);
  EXPECT_EQ(many.cost, one.cost);
  EXPECT_EQ(many.depth_cost, one.depth_cost);
}

// Columns only (a rank of mpirun): the same on several workers, and within the columns as the
// whole canvas's labels.
TEST(BlendParallel, SeamColumnsOnSeveralWorkers) {
  const std::vector<Image> images = random_layers(10, 11);
  const BlendPlan plan = plan_blend(placed(images, 3), {});
  const int W = plan.canvas.width, H = plan.canvas.height, begin = W / 3, end = W / 2;
  const auto whole = blending::compute_seams(plan, false, {}, nullptr, 1);
  std::vector<blending::Label> want(W), got(W);
  for (const int threads : {1, 3}) {
    blending::LabelPlane labels({}, W, H);
    std::vector<signed char> overlaps;
    blending::compute_seam_columns(plan, false, {}, nullptr, begin, end, labels, overlaps, threads);
    for (int y = 0; y < H; ++y) {
      whole.labels->read_row(y, want);
      labels.read_row(y, got);
      for (int x = begin; x < end; ++x) ASSERT_EQ(got[x], want[x]) << x << "," << y << ", " << threads << " workers";
    }
  }
}

// The sweep runs ahead on its own thread: each composite pixel is its labelled layer's, rows
// asked for again (an earlier row) restart it with the same values, and a blend on several
// threads is the one-thread blend exactly.
TEST(BlendParallel, TheSweepAheadGivesEachPixelItsLayer) {
  const std::vector<Image> images = random_layers(8, 21);
  const std::vector<ImageLayer> layers = placed(images, 4);
  const BlendPlan plan = plan_blend(layers, {});
  const auto seams = blending::compute_seams(plan, false, {}, nullptr, 2);
  blending::CanvasSweep sweep(plan, *seams.labels, false, true);
  const int W = plan.canvas.width, H = plan.canvas.height;
  std::vector<blending::Label> label(W);
  std::vector<float> first;
  for (int y = 0; y < H; ++y) {
    const auto row = sweep.composite(y);
    seams.labels->read_row(y, label);
    for (int x = 0; x < W; ++x) {
      const int l = label[x];
      const float want = l == 0 ? 0.0f
                                : images[l - 1].at(0, x - static_cast<int>(layers[l - 1].x - plan.canvas.x),
                                                   y - static_cast<int>(layers[l - 1].y - plan.canvas.y));
      ASSERT_EQ(row[x], want) << x << "," << y;
    }
    if (y == 5) first.assign(row.begin(), row.end());
  }
  const auto again = sweep.composite(5);
  EXPECT_EQ(std::vector<float>(again.begin(), again.end()), first);

  SolverOptions one, many;
  one.threads = 1;
  many.threads = 4;
  EXPECT_EQ(test::max_difference(blend(layers, {}, one), blend(layers, {}, many)), 0.0);
}

// The sweep's across values, row after row through its ring (whose rows keep the values they were
// given only until they are reset), are those the whole label plane defines: at a pixel of layer a,
// per direction, the value of the one other layer its two neighbours carry (across_label) where
// that layer covers the pixel; NaN everywhere else.
TEST(BlendParallel, TheSweepsAcrossValuesAreThoseOfTheWholeLabelPlane) {
  const std::vector<Image> images = random_layers(8, 33);
  const std::vector<ImageLayer> layers = placed(images, 9);
  const BlendPlan plan = plan_blend(layers, {});
  const auto seams = blending::compute_seams(plan, false, {}, nullptr, 2);
  const std::vector<blending::Label> all = all_labels(*seams.labels);
  const int W = plan.canvas.width, H = plan.canvas.height;
  const auto label = [&](int x, int y) -> blending::Label {
    return x < 0 || x >= W || y < 0 || y >= H ? 0 : all[static_cast<std::size_t>(y) * W + x];
  };
  const auto value = [&](int l, int x, int y) {  // layer l's grey at canvas (x, y), NaN where it does not cover it
    const Image& img = images[l - 1];
    const int lx = x - static_cast<int>(layers[l - 1].x - plan.canvas.x), ly = y - static_cast<int>(layers[l - 1].y - plan.canvas.y);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    if (lx < 0 || lx >= img.width || ly < 0 || ly >= img.height || !(img.at(1, lx, ly) >= 0.5f)) return nan;
    return img.at(0, lx, ly);
  };
  blending::CanvasSweep sweep(plan, *seams.labels, false, true);
  int seam_values = 0;
  for (int y = 0; y < H; ++y) {
    const auto row = sweep.across(y);
    for (int x = 0; x < W; ++x) {
      const blending::Label a = label(x, y);
      const blending::Label across[2] = {blending::across_label(a, label(x - 1, y), label(x + 1, y), blending::Label{0}),
                                         blending::across_label(a, label(x, y - 1), label(x, y + 1), blending::Label{0})};
      for (int k = 0; k < 2; ++k) {
        const float want = a != 0 && across[k] != 0 ? value(across[k], x, y) : std::numeric_limits<float>::quiet_NaN();
        const float got = row[static_cast<std::size_t>(k) * W + x];
        seam_values += std::isfinite(want);
        if (std::isnan(want)) ASSERT_TRUE(std::isnan(got)) << x << "," << y << " plane " << k << ": " << got;
        else ASSERT_EQ(got, want) << x << "," << y << " plane " << k;
      }
    }
  }
  EXPECT_GT(seam_values, 100);  // seams in both directions
}

// A layer that fails mid-run while only the sweep reads it (seams loaded from a file): the
// error reaches the solve's reader, naming the layer.
TEST(BlendParallel, ASweepErrorReachesTheReader) {
  const auto dir = std::filesystem::temp_directory_path() / ("gdp_blend_parallel_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  write_image(dir / "a.png", test::random_image(120, 200, 1), {});
  std::filesystem::copy_file(dir / "a.png", dir / "cut.png");
  std::filesystem::resize_file(dir / "cut.png", std::filesystem::file_size(dir / "cut.png") / 2);
  LayerSource a{(dir / "a.png").string()}, cut{(dir / "cut.png").string()};
  cut.placed = true;
  cut.x = 60;
  const BlendPlan plan = plan_blend({a, cut}, {});
  blending::LabelPlane labels(dir, plan.canvas.width, plan.canvas.height);
  std::vector<blending::Label> row(plan.canvas.width);
  for (int x = 0; x < plan.canvas.width; ++x) row[x] = x < 90 ? 1 : 2;
  for (int y = 0; y < plan.canvas.height; ++y) labels.write_row(y, row);
  try {
    blending::CanvasSweep sweep(plan, labels, false, false);
    for (int y = 0; y < plan.canvas.height; ++y) sweep.composite(y);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cut.png"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace gdp
