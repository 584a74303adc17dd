// Narrow scratch, the CLI's default: half of float's bytes, every schedule's bits, error against a converged answer.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "image_compare.h"
#include "test_util.h"

namespace gdp {
namespace {

// A 256x192 RGB composite: smooth waves with fine texture, offset per region of a three-label
// map (the seams a stitch removes).
class NarrowScratchCli : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    const int w = 256, h = 192;
    const Image noise = test::random_image(w, h, 3, 4);
    Image comp(w, h, 3), labels(w, h, 1);
    for (int c = 0; c < 3; ++c) {
      const Image wave = test::cosine_image(w, h, 2 + c, 3 - c);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const int label = x < w / 3 ? 0 : y < h / 2 ? 1 : 2;
          labels.at(0, x, y) = label / 2.0f;
          comp.at(c, x, y) = 0.45f + 0.3f * wave.at(0, x, y) + 0.05f * noise.at(c, x, y) + 0.1f * (label == 1) -
                             0.08f * (label == 2);
        }
    }
    write_image(path("comp.tif"), comp, {});
    write_image(path("labels.png"), labels, {});
  }

  // Stitches with `flags` into NAME.tif (float samples); returns the image.
  Image stitch(const std::string& name, const std::string& flags) {
    const test::CliRun r = gdp("stitch -c " + path("comp.tif") + " -l " + path("labels.png") + " -q --depth float -o " +
                               path(name + ".tif") + " --stats " + path(name + ".json") + " " + flags);
    EXPECT_EQ(r.code, 0) << r.err;
    return read_image(path(name + ".tif")).image;
  }
  // A number from NAME.json (--stats).
  double stat(const std::string& name, const std::string& key) {
    std::ifstream f(path(name + ".json"));
    const std::string json(std::istreambuf_iterator<char>(f), {});
    const std::size_t at = json.find("\"" + key + "\":");
    EXPECT_NE(at, std::string::npos) << key;
    return at == std::string::npos ? -1.0 : std::stod(json.substr(json.find(':', at) + 1));
  }
};

double rms(const Image& a, const Image& b) {
  double s = 0.0;
  for (std::size_t k = 0; k < a.data.size(); ++k) s += (double(a.data[k]) - b.data[k]) * (a.data[k] - b.data[k]);
  return std::sqrt(s / double(a.data.size()));
}

// --incore-bytes 200000 streams levels 0 and 1 (256x192, 128x96), as the default does for images
// up to about 2400x2400: u and b of both as half floats, 3 channels x 2 quantities x 2 bytes per
// pixel: 12 x (1 + 1/4) = 15 bytes, half of float's 30 (docs/how-streaming-works.md).
TEST_F(NarrowScratchCli, DefaultIsNarrowWithHalfTheScratchAndEveryScheduleAgrees) {
  const std::string levels = "--incore-bytes 200000";
  const Image narrow = stitch("narrow", levels);
  const Image in_core = stitch("in_core", levels + " --in-core");
  const Image half = stitch("half", levels + " --half-scratch");
  const Image exact = stitch("float", levels + " --scratch float");
  EXPECT_EQ(stat("narrow", "streamed_levels"), 2);
  const double narrow_bpp = stat("narrow", "scratch_bytes_per_pixel"), float_bpp = stat("float", "scratch_bytes_per_pixel");
  EXPECT_LE(narrow_bpp, 15.7);
  EXPECT_NEAR(narrow_bpp, float_bpp / 2, 0.01);
  EXPECT_TRUE(test::same_bits(narrow, in_core)) << test::max_difference(narrow, in_core);
  EXPECT_TRUE(test::same_bits(narrow, half)) << test::max_difference(narrow, half);
  EXPECT_FALSE(test::same_bits(narrow, exact));

  // Against the converged answer (double precision, float scratch, relative residual 1e-10): the
  // documented bound, narrow's rms at most 1.6x float's and its max at most 1.05x float's
  // (docs/how-streaming-works.md, "The default: narrow scratch").
  const Image truth = stitch("truth", "--double --tolerance 1e-10");
  const double range = test::range_of(truth);
  const double rms_narrow = rms(narrow, truth) / range, rms_float = rms(exact, truth) / range;
  const double max_narrow = test::max_difference(narrow, truth) / range;
  const double max_float = test::max_difference(exact, truth) / range;
  std::printf("narrow rms %.3e max %.3e, float rms %.3e max %.3e, B/pixel %.3f vs %.3f\n", rms_narrow, max_narrow,
              rms_float, max_float, narrow_bpp, float_bpp);
  EXPECT_GT(rms_float, 0.0);
  EXPECT_LE(rms_narrow, 1.6 * rms_float);
  EXPECT_LE(max_narrow, 1.05 * max_float);
}

// --half-scratch is --scratch narrow; --double asks for the exact solver.
TEST_F(NarrowScratchCli, FlagsConflictClearly) {
  const std::string run = "stitch -c " + path("comp.tif") + " -l " + path("labels.png") + " -o " + path("out.tif");
  expect_failure(run + " --half-scratch --scratch float", "--half-scratch");
  expect_failure(run + " --double --scratch narrow", "double");
  expect_failure(run + " --scratch bfloat", "--scratch");
}

}  // namespace
}  // namespace gdp
