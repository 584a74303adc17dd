// TOAST tile pyramids: the layout (copies and rotations of PQ blocks), and a comparison with the
// tiles WorldWideTelescope's toasty made from a plate carree sky map.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/sphere.h"

namespace fs = std::filesystem;

namespace gdp::sphere {
namespace {

fs::path temp_dir(const std::string& name) {
  return fs::temp_directory_path() / ("gdp_sphere_" + std::to_string(::getpid()) + "_" + name);
}

// Level n tiles are the PQ image's 256 x 256 blocks, copied (bottom half of the square) or
// rotated by 180 degrees (top half); level n-1 averages 2x2.
TEST(SphereToast, TilesAreCopiesAndRotationsOfPqBlocks) {
  Image pq(1024, 256, 1);
  for (std::size_t k = 0; k < pq.data.size(); ++k) pq.data[k] = float((k * 37 % 251)) / 255.0f;
  const fs::path dir = temp_dir("layout");
  fs::remove_all(dir);
  ToastPyramidOptions o;
  o.write.sample_type = SampleType::UInt8;
  write_toast_pyramid(pq, dir, o);
  auto tile = [&](int level, int x, int y) {
    return read_image(dir / std::to_string(level) / std::to_string(y) / (std::to_string(y) + "_" + std::to_string(x) + ".png"))
        .image;
  };
  const float q = 1.0f / 255.0f;
  const Image t10 = tile(1, 0, 1), t01 = tile(1, 1, 0);
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x) {
      EXPECT_NEAR(t10.at(0, x, y), pq.at(0, x, y), q);              // bottom-left: PQ block 0, copied
      EXPECT_NEAR(t01.at(0, x, y), pq.at(0, 1023 - x - 256, 255 - y), q);  // top-right: block 2, rotated
    }
  const Image t0 = tile(0, 0, 0);
  const Image t00 = tile(1, 0, 0);
  EXPECT_NEAR(t0.at(0, 10, 20), 0.25f * (t00.at(0, 20, 40) + t00.at(0, 21, 40) + t00.at(0, 20, 41) + t00.at(0, 21, 41)),
              2.5f * q);
  std::ifstream wtml(dir / "toast.wtml");
  const std::string text((std::istreambuf_iterator<char>(wtml)), {});
  EXPECT_NE(text.find("Projection=\"Toast\""), std::string::npos);
  EXPECT_NE(text.find("{1}/{3}/{3}_{2}.png"), std::string::npos);
  EXPECT_THROW(write_toast_pyramid(pq, dir, o), UsageError);  // not empty
  fs::remove_all(dir);
  EXPECT_THROW(write_toast_pyramid(Image(800, 200, 1), dir, o), UsageError);  // not 128 * 2^n
  EXPECT_FALSE(fs::exists(dir));
}

// The pyramid from square rows (read once, top to bottom, strips of 256 rows per level) with fewer
// levels than the PQ height reaches: the one tile of level 0 is the mean of the square's 2 x 2
// blocks (level 1, the square itself, is not written), and every square row is asked for once, in order.
TEST(SphereToast, ThePyramidFromRowsAveragesTheSquare) {
  Image pq(1024, 256, 3);  // top level 1; written: level 0 only
  for (std::size_t k = 0; k < pq.data.size(); ++k) pq.data[k] = float((k * 53 % 241)) / 241.0f;
  const Image square = pq_to_square(pq);
  const fs::path dir = temp_dir("rows");
  fs::remove_all(dir);
  ToastPyramidOptions o;
  o.levels = 0;
  o.write.sample_type = SampleType::UInt16;
  int next = 0;
  write_toast_pyramid(
      256, 3,
      [&](int y, std::span<float> row) {
        EXPECT_EQ(y, next++);
        for (int c = 0; c < 3; ++c)
          square_row_from_pq(256, y, pq.row(c, square_row_source(256, y)), row.subspan(c * 512, 512));
      },
      dir, o);
  EXPECT_EQ(next, 512);
  EXPECT_FALSE(fs::exists(dir / "1"));
  const Image t = read_image(dir / "0" / "0" / "0_0.png").image;
  ASSERT_EQ(t.channels, 3);
  double worst = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < 256; ++y)
      for (int x = 0; x < 256; ++x) {
        double mean = 0.0;
        for (int j = 0; j < 2; ++j)
          for (int i = 0; i < 2; ++i) mean += square.at(c, 2 * x + i, 2 * y + j) / 4.0;
        worst = std::max(worst, std::abs(t.at(c, x, y) - mean));
      }
  EXPECT_LT(worst, 1.0 / 65535.0) << "16-bit tiles: half a step of rounding";
  fs::remove_all(dir);
}

struct Diff {
  double mean = 0, max = 0, psnr = 0;
};

Diff compare(const Image& a, const Image& b) {
  Diff d;
  double se = 0.0;
  for (std::size_t k = 0; k < a.data.size(); ++k) {
    const double e = std::abs(double(a.data[k]) - b.data[k]) * 255.0;
    d.mean += e;
    d.max = std::max(d.max, e);
    se += e * e;
  }
  d.mean /= a.data.size();
  d.psnr = 10.0 * std::log10(255.0 * 255.0 / (se / a.data.size()));
  return d;
}

// tess_platecarree_ecliptic_512.jpg is a sky map in ecliptic coordinates, longitude increasing to
// the left from 0 at the right edge (toasty's plate_carree_ecliptic_sampler); TOAST tiles are
// equatorial. Rotation from equatorial to that image's frame: to ecliptic (obliquity J2000), then
// half a turn about the pole.
TEST(SphereToast, MatchesToastyTiles) {
  const std::string data = GDP_TEST_DATA "/toasty/";
  const Image src = read_image(data + "tess_platecarree_ecliptic_512.jpg").image;
  const double eps = 23.4392911 * std::numbers::pi / 180.0, c = std::cos(eps), s = std::sin(eps);
  for (bool nearest : {true, false}) {
    ResampleOptions o;
    o.nearest = nearest;  // toasty samples the nearest pixel
    o.rotation = {-1, 0, 0, 0, -c, -s, 0, -s, c};
    const Image pq = resample(src, {Layout::Equirect, SquareMap::Toast, true}, {Layout::Pq}, 1024, 256, o);
    const fs::path dir = temp_dir(nearest ? "tess_nearest" : "tess");
    fs::remove_all(dir);
    ToastPyramidOptions t;
    t.write.sample_type = SampleType::UInt8;
    write_toast_pyramid(pq, dir, t);
    for (const char* tile : {"1/0/0_0.png", "1/0/0_1.png", "1/1/1_0.png", "1/1/1_1.png", "0/0/0_0.png"}) {
      const Image expected = read_image(data + "tess_toast_expected/" + tile).image;
      const Image ours = read_image(dir / tile).image;
      ASSERT_EQ(ours.width, expected.width);
      const Diff d = compare(ours, expected);
      std::printf("%s %s: mean |diff| %.2f, max %.0f (of 255), PSNR %.1f dB\n", nearest ? "nearest" : "lanczos", tile,
                  d.mean, d.max, d.psnr);
      // Nearest: the same pixels but where a centre falls within rounding of a pixel edge (mean
      // 0.1-0.5 of 255). Lanczos: interpolated values differ at the grid lines' sharp edges.
      EXPECT_LT(d.mean, nearest ? 1.0 : 6.0) << tile;
      EXPECT_GT(d.psnr, nearest ? 38.0 : 28.0) << tile;
    }
    fs::remove_all(dir);
  }
  // Without the change of frame the same comparison fails by far: the test can tell.
  ResampleOptions o;
  o.nearest = true;
  const Image pq = resample(src, {Layout::Equirect, SquareMap::Toast, true}, {Layout::Pq}, 1024, 256, o);
  const Image expected = read_image(data + "tess_toast_expected/1/0/0_0.png").image;
  const Image square = pq_to_square(pq);
  Image tile(256, 256, 3);
  for (int ch = 0; ch < 3; ++ch)
    for (int y = 0; y < 256; ++y)
      for (int x = 0; x < 256; ++x) tile.at(ch, x, y) = square.at(ch, x, y);
  EXPECT_GT(compare(tile, expected).mean, 10.0);
}

}  // namespace
}  // namespace gdp::sphere
