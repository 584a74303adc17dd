// gdp blend's default sweeps follow the output's sample type, and its 8-bit output stays at a converged solve's rounding.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>

#include "cli_fixture.h"
#include "gdp/blend.h"
#include "gdp/image_io.h"
#include "nona_tiff.h"
#include "weir_layers.h"

namespace gdp {
namespace {

// The "sweeps" a --stats file names ("PRE/POST"), empty when absent.
std::string sweeps_of(const std::string& file) {
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string key = "\"sweeps\": \"";
  const auto at = text.find(key);
  return at == std::string::npos ? "" : text.substr(at + key.size(), text.find('"', at + key.size()) - at - key.size());
}

// An 8-bit blend against a converged one (float samples, clipped to 0..1 as 8 bits are), over the
// colour of covered pixels: the largest difference in 8-bit levels and the fraction of samples
// whose 8-bit value is not the converged value rounded.
struct Against {
  double largest = 0.0, changed = 0.0;
};
Against against(const Image& out, const Image& converged) {
  Against a;
  double n = 0.0;
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      if (out.at(3, x, y) < 0.5f) continue;
      for (int c = 0; c < 3; ++c) {
        const double v = std::clamp(255.0 * out.at(c, x, y), 0.0, 255.0), r = std::clamp(255.0 * converged.at(c, x, y), 0.0, 255.0);
        a.largest = std::max(a.largest, std::abs(v - r));
        a.changed += std::lround(v) != std::lround(r) ? 1.0 : 0.0;
        n += 1.0;
      }
    }
  a.changed /= n;
  return a;
}

class BlendSweeps : public test::CliFixture {
 protected:
  // weir_1_crop.jpg cut into its six exposure-shifted, vignetted layers, written as nona's 8-bit RGBA TIFFs.
  std::string write_layers() {
    const test::WeirLayers cut = test::cut_weir(0.3);
    std::string names;
    for (int k = 0; k < test::kWeirLayers; ++k) {
      const Image& l = cut.layers[k];
      Image rgba(l.width, l.height, 4, 1.0f);
      for (int c = 0; c < 3; ++c)
        for (int y = 0; y < l.height; ++y)
          for (int x = 0; x < l.width; ++x) rgba.at(c, x, y) = std::clamp(l.at(c, x, y), 0.0f, 1.0f);
      const std::string name = path("weir" + std::to_string(k) + ".tif");
      test::write_nona_tiff(name, {{&rgba, static_cast<int>(cut.placed[k].x), static_cast<int>(cut.placed[k].y), 8}}, 640, 480);
      names += " " + name;
    }
    return names;
  }

  // gdp blend with `flags` into `out`, its --stats beside it; the sweeps it ran.
  std::string run(const std::string& flags, const std::string& out, const std::string& layers) {
    const test::CliRun r = gdp("blend -q " + flags + " --stats " + path(out + ".json") + " -o " + path(out) + layers);
    EXPECT_EQ(r.code, 0) << flags << "\n" << r.err;
    return sweeps_of(path(out + ".json"));
  }
};

TEST_F(BlendSweeps, DefaultFollowsTheOutputAndIters) {
  const std::string layers = write_layers();
  EXPECT_EQ(run("", "eight.tif", layers), "2/3");
  EXPECT_EQ(run("", "eight.jpg", layers), "2/3");
  EXPECT_EQ(run("--depth 16", "sixteen.tif", layers), "3/3");
  EXPECT_EQ(run("--depth float", "float.tif", layers), "3/3");
  EXPECT_EQ(run("--correction " + path("correction.tif"), "corrected.tif", layers), "3/3");  // a float output too
  EXPECT_EQ(run("--vcycles 2", "cycles.tif", layers), "3/3");  // 3/3 gains more per CPU second over cycles
  EXPECT_EQ(run("--tolerance 1e-4", "tolerance.tif", layers), "3/3");
  EXPECT_EQ(run("--anchor 2", "anchor.tif", layers), "3/3");  // pinned, weighted: not measured
  EXPECT_EQ(run("--weights 1,2,1,1,1,1", "weights.tif", layers), "3/3");
  EXPECT_EQ(run("-k 3", "three.tif", layers), "3/3");  // the user's count always wins
  EXPECT_EQ(run("--iters 1/2 --depth 16", "onetwo.tif", layers), "1/2");
}

// The 8-bit default against a converged solve (double, 8 V-cycles): within rounding and the solve's
// own error, 0.21 levels at most here for 2/3 (3/3: 0.10, 2/2: 0.47, 1/2: 1.14), so every value within
// 0.8 levels of the converged one (measured 0.69; 2/2 0.84, 1/2 1.54), and almost every value the
// converged value rounded (not: 3/3 0.47 %, 2/3 0.50 %, 2/2 0.55 %, 1/2 0.89 %, 1/1 2.1 %).
TEST_F(BlendSweeps, EightBitDefaultStaysAtTheConvergedRounding) {
  const std::string layers = write_layers();
  ASSERT_EQ(run("", "default.tif", layers), "2/3");
  run("-k 3 --double --vcycles 8 --depth float", "converged.tif", layers);
  const Image out = read_image(path("default.tif")).image, converged = read_image(path("converged.tif")).image;
  ASSERT_EQ(out.width, converged.width);
  ASSERT_EQ(out.channels, 4);
  const Against a = against(out, converged);
  EXPECT_LT(a.largest, 0.8) << "8-bit levels";
  EXPECT_LT(a.changed, 0.0075);
}

// --correction with the defaults (narrow scratch, 3/3): a finite field near a converged solve's
// (measured 4.0e-4 at most); with --anchor (a diagonal term: no level's b in half, half_policy)
// still finite, and the anchored layer's pixels take no correction at all (17.5 % of the covered
// pixels here; none without it). Before the pins fix (92f273e) an anchored field was mostly NaN
// (three crops of weir_1, --anchor 1: 86,800 of 96,000 pixels).
TEST_F(BlendSweeps, CorrectionUnderNarrowScratchIsFiniteAndNearTheConvergedOne) {
  const std::string layers = write_layers();
  const auto corrected = [&](const std::string& flags, const std::string& name) {
    run(flags + " --correction " + path(name + ".tif"), name + "_out.tif", layers);
    return read_image(path(name + ".tif")).image;
  };
  const Image plain = corrected("", "plain"), converged = corrected("-k 3 --double --vcycles 8 --scratch float", "converged");
  const Image anchored = corrected("--anchor 3", "anchored");
  const Image cover = read_image(path("plain_out.tif")).image;
  ASSERT_EQ(plain.channels, 3);
  double worst = 0.0, largest = 0.0;
  long covered = 0, plain_zero = 0, anchored_zero = 0;
  for (int y = 0; y < plain.height; ++y)
    for (int x = 0; x < plain.width; ++x) {
      if (cover.at(3, x, y) < 0.5f) continue;
      ++covered;
      bool plain_none = true, anchored_none = true;
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(plain.at(c, x, y)) && std::isfinite(anchored.at(c, x, y))) << x << "," << y;
        worst = std::max(worst, double(std::abs(plain.at(c, x, y) - converged.at(c, x, y))));
        largest = std::max(largest, double(std::abs(anchored.at(c, x, y))));
        plain_none = plain_none && plain.at(c, x, y) == 0.0f;
        anchored_none = anchored_none && anchored.at(c, x, y) == 0.0f;
      }
      plain_zero += plain_none;
      anchored_zero += anchored_none;
    }
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(largest, 0.5);  // the layers' offsets are 0.05 to 0.15 (weir_layers.h)
  EXPECT_LT(plain_zero, covered / 100);
  EXPECT_GT(anchored_zero, covered / 10);  // one layer of six holds still
}

}  // namespace
}  // namespace gdp
