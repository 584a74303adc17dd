// --weights and --pin on the command line: pinned pixels hold the input, bad images are named.
#include <gtest/gtest.h>

#include <cmath>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace gdp {
namespace {

class FidelityCli : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    // A composite of two halves 0.2 apart (one seam), float so nothing is quantised.
    composite_ = test::cosine_image(96, 64, 2, 1);
    Image labels(96, 64, 1);
    pins_ = Image(96, 64, 1);
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 96; ++x) {
        labels.at(0, x, y) = x < 48 ? 0.2f : 0.6f;
        if (x >= 48) composite_.at(0, x, y) += 0.2f;
        pins_.at(0, x, y) = (x > 60 && y < 30) || x < 8 ? 1.0f : 0.0f;  // a block and a strip
      }
    WriteOptions f;
    f.sample_type = SampleType::Float;
    write_image(path("c.exr"), composite_, f);
    write_image(path("l.png"), labels, {});
    write_image(path("pins.png"), pins_, {});
  }
  Image composite_, pins_;
};

TEST_F(FidelityCli, PinnedPixelsKeepTheirValues) {
  const test::CliRun r = gdp("stitch -c " + path("c.exr") + " -l " + path("l.png") + " --pin " + path("pins.png") +
                             " -o " + path("out.exr") + " --depth float -q");
  ASSERT_EQ(r.code, 0) << r.err;
  const Image out = read_image(path("out.exr")).image;
  double worst = 0.0, seam = 0.0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 96; ++x)
      if (pins_.at(0, x, y) > 0.5f) worst = std::max(worst, std::abs(double(out.at(0, x, y)) - composite_.at(0, x, y)));
    seam = std::max(seam, std::abs(double(out.at(0, 48, y)) - out.at(0, 47, y)));
  }
  EXPECT_LT(worst, 1e-4);
  EXPECT_LT(seam, 0.05);  // the 0.2 step is gone even though both sides hold pinned pixels
}

TEST_F(FidelityCli, WeightsPullTowardsTheInput) {
  // Weight 1 everywhere with sharpen's gradients: still a valid run; a weight image of the wrong
  // size or with negative weights is refused, naming the file.
  Image ones(96, 64, 1), negative(96, 64, 1), small(10, 10, 1);
  for (float& v : ones.data) v = 1.0f;
  for (float& v : negative.data) v = -1.0f;
  WriteOptions f;
  f.sample_type = SampleType::Float;
  write_image(path("ones.exr"), ones, f);
  write_image(path("neg.exr"), negative, f);
  write_image(path("small.exr"), small, f);
  const test::CliRun ok = gdp("sharpen " + path("c.exr") + " --weights " + path("ones.exr") + " -o " +
                              path("s.exr") + " -q");
  EXPECT_EQ(ok.code, 0) << ok.err;
  expect_failure("sharpen " + path("c.exr") + " --weights " + path("neg.exr") + " -o " + path("bad.exr"), "neg.exr");
  expect_failure("stitch -c " + path("c.exr") + " -l " + path("l.png") + " --weights " + path("small.exr") + " -o " +
                     path("bad.exr"),
                 "small.exr");
}

}  // namespace
}  // namespace gdp
