// Resolution-independent scales: a preview and the full image sharpened alike (--scale-at), degrees on the sphere.
#include <gtest/gtest.h>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace gdp {
namespace {

Image halve(const Image& a) {
  Image h(a.width / 2, a.height / 2, a.channels);
  for (int c = 0; c < a.channels; ++c)
    for (int y = 0; y < h.height; ++y)
      for (int x = 0; x < h.width; ++x)
        h.at(c, x, y) = 0.25f * (a.at(c, 2 * x, 2 * y) + a.at(c, 2 * x + 1, 2 * y) + a.at(c, 2 * x, 2 * y + 1) +
                                 a.at(c, 2 * x + 1, 2 * y + 1));
  return h;
}

class ScaleUnits : public test::CliFixture {};

TEST_F(ScaleUnits, PreviewAndFullImageAgreeWithScaleAt) {
  const Image photo = read_image(GDP_TEST_DATA "/opencv/weir_1_crop.jpg").image;
  Image full(512, 384, 1);
  for (int y = 0; y < 384; ++y)
    for (int x = 0; x < 512; ++x) full.at(0, x, y) = photo.at(1, x + 50, y + 50);
  WriteOptions f;
  f.sample_type = SampleType::Float;
  write_image(path("full.exr"), full, f);
  write_image(path("preview.exr"), halve(full), f);
  // Differences between the preview's result and the full result seen at the preview's size.
  const auto mismatch = [&](const std::string& flags) {
    for (const char* name : {"full", "preview"}) {
      const test::CliRun r = gdp(std::string("sharpen ") + path(std::string(name) + ".exr") + " -o " +
                                 path(std::string(name) + "_out.exr") + " --beta 2 -q " + flags);
      EXPECT_EQ(r.code, 0) << r.err;
    }
    return test::rms_difference(halve(read_image(path("full_out.exr")).image), read_image(path("preview_out.exr")).image);
  };
  const double pixels = mismatch("--scale 8"), stated = mismatch("--scale 8 --scale-at 512");
  // Measured: rms 3.0e-2 in plain pixels, 2.6e-4 with the stated resolution.
  EXPECT_LT(stated, 0.05 * pixels) << "pixels " << pixels << " stated " << stated;
}

TEST_F(ScaleUnits, DegreesNeedASphere) {
  write_image(path("a.png"), test::random_image(32, 16, 1), {});
  expect_failure("sharpen " + path("a.png") + " -o " + path("b.png") + " --scale-deg 5", "--scale-deg");
  const test::CliRun ok = gdp("sharpen " + path("a.png") + " -o " + path("b.png") + " --scale-deg 5 --sphere -q");
  EXPECT_EQ(ok.code, 0) << ok.err;
}

}  // namespace
}  // namespace gdp
