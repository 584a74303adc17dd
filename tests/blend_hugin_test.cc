// Hugin's own stitcher (hugin_executor) runs with gdp-blend named as its blender (skipped without hugin-tools).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>

#include "cli_fixture.h"
#include "gdp/image_io.h"

namespace gdp {
namespace {

class BlendHugin : public test::CliFixture {};

// A scene seen by a camera at `yaw` degrees (rectilinear, 50 degrees wide): stripes whose
// brightness follows the direction, so that both photos see the same scene.
Image photo(double yaw, float gain) {
  const int n = 160;
  Image img(n, n, 3);
  const double f = (n / 2.0) / std::tan(25.0 * M_PI / 180.0);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double lon = yaw * M_PI / 180.0 + std::atan2(x + 0.5 - n / 2.0, f);
      const double lat = std::atan2(n / 2.0 - y - 0.5, std::hypot(f, x + 0.5 - n / 2.0));
      for (int c = 0; c < 3; ++c)
        img.at(c, x, y) = gain * static_cast<float>(0.5 + 0.2 * std::sin(9 * lon + c) * std::cos(7 * lat));
    }
  return img;
}

TEST_F(BlendHugin, HuginExecutorStitchesWithGdpBlend) {
  if (std::system("command -v hugin_executor > /dev/null 2>&1") != 0) GTEST_SKIP() << "hugin-tools not installed";
  write_image(path("a.png"), photo(-15, 1.0f), {});
  write_image(path("b.png"), photo(15, 1.1f), {});
  std::ofstream(path("p.pto")) << "p f1 w360 h160 v80 E0 R0 S0,360,0,160 n\"TIFF_m c:LZW r:CROP\"\n"
                                  "m i0\n"
                                  "i w160 h160 f0 v50 Ra0 Rb0 Rc0 Rd0 Re0 Eev0 Er1 Eb1 r0 p0 y-15 TrX0 TrY0 TrZ0 "
                                  "j0 a0 b0 c0 d0 e0 g0 t0 Va1 Vb0 Vc0 Vd0 Vx0 Vy0 Vm5 n\"a.png\"\n"
                                  "i w160 h160 f0 v50 Ra0 Rb0 Rc0 Rd0 Re0 Eev0 Er1 Eb1 r0 p0 y15 TrX0 TrY0 TrZ0 "
                                  "j0 a0 b0 c0 d0 e0 g0 t0 Va1 Vb0 Vc0 Vd0 Vx0 Vy0 Vm5 n\"b.png\"\n";
  const std::string blender = std::filesystem::path(GDP_CLI_PATH).parent_path() / "gdp-blend";
  std::filesystem::create_directories(path("home/.config"));
  std::ofstream(path("home/.config/hugin.conf")) << "[Enblend]\nCustom=1\nExe=" << blender << "\n";
  const std::string cmd = "cd " + path("") + " && HOME=" + path("home") +
                          " hugin_executor --stitching --prefix=pano p.pto > hugin.log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream log(path("hugin.log"));
  const std::string text((std::istreambuf_iterator<char>(log)), {});
  EXPECT_NE(text.find("blend: 2 layer(s)"), std::string::npos) << text;  // gdp blend did the blending
  const ReadResult out = read_image(path("pano.tif"));
  EXPECT_EQ(out.image.width, 360);
  ASSERT_EQ(out.image.channels, 4);
  EXPECT_EQ(out.image.at(3, 180, 80), 1.0f);  // the middle, where the photos overlap
  // No seam in the middle row: neighbouring columns differ as little as the scene's own stripes allow.
  double worst = 0.0;
  for (int x = 100; x < 260; ++x) worst = std::max(worst, double(std::abs(out.image.at(1, x + 1, 80) - out.image.at(1, x, 80))));
  EXPECT_LT(worst, 0.02) << "a gain of 1.1 left unblended would step by about 0.05";
}

}  // namespace
}  // namespace gdp
