// gdp sky --seams graphcut: no costlier than the distance seams, off a disagreement; one plate's pixels keep it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "gdp/image_io.h"
#include "gdp/sky.h"
#include "image_stream_util.h"
#include "sky/plate.h"
#include "sky_test_util.h"

namespace gdp {
namespace {

// Two plates side by side along the equator of RA 100 overlapping by 3 degrees (15 pixels); the
// second carries a narrow ridge (not a plane: the background fit cannot take it off) along the
// middle of the overlap (x = 32.5: RA grows to the left), where the distance seams run, and an
// offset.
class SkyGraphcut : public test::TempDirTest {
 protected:
  static constexpr int kSize = 40;
  static constexpr double kScale = 0.2;

  std::vector<std::string> write_pair() {
    const auto sky = [](const sphere::Vec3& d) { return 1.0 + 0.3 * d.x + 0.2 * d.z; };
    const auto ridge = [](double x, double) { return 0.5 * std::exp(-(x - 32.5) * (x - 32.5) / (2.0 * 1.5 * 1.5)); };
    return {test::write_plate(dir_, "a.fits", 100.0, 0.0, kSize, kScale, sky, 0.0),
            test::write_plate(dir_, "b.fits", 105.0, 0.0, kSize, kScale, sky, 0.2, ridge)};
  }

  // The seamed mosaic (no solve) with `graphcut` seams, on a grid holding both plates.
  Image mosaic(const std::vector<std::string>& plates, bool graphcut, SkySummary& summary) {
    SkyOptions options;
    options.target = {{}, 102.5, 0.0, 70, 50, kScale, "TAN"};
    options.blend = false;
    options.star_seams = false;
    options.graphcut_seams = graphcut;
    const auto out = dir_ / (graphcut ? "cut.fits" : "depth.fits");
    sky_mosaic(plates, options, SolverOptions{}, out, WriteOptions{}, &summary);
    return read_image(out).image;
  }
};

TEST_F(SkyGraphcut, CostsNoMoreThanTheDistanceSeamsAndLeavesTheRidge) {
  const std::vector<std::string> plates = write_pair();
  SkySummary cut;
  mosaic(plates, true, cut);
  std::printf("seam cost: distance seams %.4g, graph cut %.4g\n", cut.seam_cost_depth, cut.seam_cost);
  EXPECT_GT(cut.seam_cost_depth, 0.0);
  EXPECT_LE(cut.seam_cost, cut.seam_cost_depth);
  EXPECT_LT(cut.seam_cost, 0.7 * cut.seam_cost_depth) << "the seams stay on the ridge";
}

TEST_F(SkyGraphcut, PixelsOnlyOnePlateCoversKeepThatPlate) {
  const std::vector<std::string> plates = write_pair();
  SkySummary s;
  const Image depth = mosaic(plates, false, s), cut = mosaic(plates, true, s);
  std::vector<sky::Plate> p;
  for (const std::string& path : plates) p.push_back(sky::open_plate(path));
  const sky::Wcs target(sky::target_header({{}, 102.5, 0.0, 70, 50, kScale, "TAN"}), 70, 50, "target");
  long long alone = 0, moved = 0;
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 70; ++x) {
      double lon = 0, lat = 0;
      ASSERT_TRUE(target.pixel_to_sky(x + 0.5, y + 0.5, lon, lat));
      int inside = 0;  // plates holding the point a pixel inside their edges
      for (const sky::Plate& plate : p) {
        double u = 0, v = 0;
        if (plate.wcs->sky_to_pixel(lon, lat, u, v) && u > -1.0 && v > -1.0 && u < kSize + 1.0 && v < kSize + 1.0)
          ++inside;
      }
      const float a = depth.at(0, x, y), b = cut.at(0, x, y);
      if (inside == 1 && !std::isnan(a)) {
        EXPECT_EQ(a, b) << "at " << x << "," << y;
        ++alone;
      }
      if (inside == 2 && a != b) ++moved;
    }
  EXPECT_GT(alone, 1000);
  EXPECT_GT(moved, 50) << "the cut moved the seam within the overlap";
}

}  // namespace
}  // namespace gdp
