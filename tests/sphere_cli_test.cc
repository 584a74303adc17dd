// `gdp sphere`: round trips through the command line, and errors (one line, exit 2, no output).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <string>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "gdp/sphere.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

// Runs in a scratch directory holding a 128x64 equirectangular image, smooth on the sphere.
class SphereCli : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    Image er(128, 64, 3);
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 128; ++x)
        for (int c = 0; c < 3; ++c) {  // smooth on the sphere (continuous at the poles and the seam)
          const sphere::Vec3 d = sphere::equirect_direction(128, 64, x + 0.5, y + 0.5);
          er.at(c, x, y) = static_cast<float>(0.5 + 0.3 * d.x * (c + 1) / 3 + 0.15 * std::sin(3 * d.y) - 0.1 * d.z * d.z);
        }
    write_image(path("er.png"), er, {});
  }
};

TEST_F(SphereCli, ToPqFromPqAndToast) {
  ASSERT_EQ(gdp("sphere to-pq " + path("er.png") + " -o " + path("pq.png") + " -q").code, 0);
  const Image pq = read_image(path("pq.png")).image;
  EXPECT_EQ(pq.height, 44);  // sqrt(128 * 64 / 4) = 45.3 -> 11 * 2^2
  EXPECT_EQ(pq.width, 4 * 44);
  ASSERT_EQ(gdp("sphere from-pq " + path("pq.png") + " -o " + path("back.png") + " --format equirect --width 128 -q").code,
            0);
  const Image er = read_image(path("er.png")).image, back = read_image(path("back.png")).image;
  double err = 0.0;
  for (std::size_t k = 0; k < er.data.size(); ++k) err = std::max(err, double(std::abs(er.data[k] - back.data[k])));
  EXPECT_LT(err, 0.02);  // 8-bit files, interpolation twice
  ASSERT_EQ(gdp("sphere from-pq " + path("pq.png") + " -o " + path("cube.png") + " --format cube -q").code, 0);
  const Image cube = read_image(path("cube.png")).image;
  EXPECT_EQ(cube.height, 6 * cube.width);
  ASSERT_EQ(gdp("sphere to-pq " + path("er.png") + " -o " + path("t.png") + " --height 128 --nearest -q").code, 0);
  ASSERT_EQ(gdp("sphere toast " + path("t.png") + " -o " + path("tiles") + " -q").code, 0);
  EXPECT_TRUE(fs::exists(path("tiles/0/0/0_0.png")));
  EXPECT_TRUE(fs::exists(path("tiles/toast.wtml")));
}

TEST_F(SphereCli, ErrorsAreOneLineWithNoOutput) {
  expect_failure("sphere from-pq " + path("er.png") + " -o " + path("x.png") + " --format equirect", "er.png");
  expect_failure("sphere to-pq " + path("missing.png") + " -o " + path("x.png"), "missing.png");
  expect_failure("sphere toast " + path("er.png") + " -o " + path("tiles"), "er.png");
  EXPECT_FALSE(fs::exists(path("x.png")));
  EXPECT_FALSE(fs::exists(path("tiles")));
  EXPECT_EQ(files(), std::set<std::string>{"er.png"}) << "nothing may be left behind";
}

}  // namespace
}  // namespace gdp
