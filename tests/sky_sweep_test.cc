// gdp sky's plate passes as sweeps: only the plates crossing the current PQ rows are held, and the results are those of whole plates.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "gdp/sky.h"
#include "image_stream_util.h"
#include "sky/plate.h"
#include "sky/plate_backgrounds.h"
#include "sky_test_util.h"
#include "sphere/vec3.h"

namespace gdp {
namespace {

// A column of plates along the meridian RA 90 (down the PQ rows there), each overlapping the next
// by a fifth, each with its own offset, plane and radial term, on a smooth sky with a star in
// every overlap.
class SkySweep : public test::TempDirTest {
 protected:
  static constexpr int kPlates = 10, kSize = 30;
  static constexpr double kScale = 0.2, kStep = 0.8 * kSize * kScale;  // degrees

  std::vector<std::string> write_column() {
    const auto sky = [](const sphere::Vec3& d) {
      double v = 1.0 + 0.3 * d.x + 0.2 * d.y * d.z + 0.1 * std::sin(3.0 * d.z);
      for (int k = 0; k + 1 < kPlates; ++k) {  // a star (sigma 1.5 pixels) in each overlap
        const double theta = sphere::angle(d, sky::direction(90.3, lat(k) + kStep / 2)) * 180.0 / M_PI;
        v += 0.8 * std::exp(-theta * theta / (2.0 * 0.3 * 0.3));
      }
      return v;
    };
    std::vector<std::string> paths;
    for (int k = 0; k < kPlates; ++k) {
      const double su = 0.05 * std::sin(k + 1.0), sv = 0.04 * std::cos(2.0 * k), r = 0.03 * std::sin(3.0 * k);
      const auto background = [=](double x, double y) {
        const double u = (x - kSize / 2.0) / kSize, v = (y - kSize / 2.0) / kSize;
        return su * u + sv * v + r * (u * u + v * v);
      };
      paths.push_back(test::write_plate(dir_, std::string("p").append(std::to_string(k)).append(".fits"), 90.0, lat(k), kSize, kScale, sky,
                                        0.1 * k * (k % 2 ? -1 : 1), background));
    }
    return paths;
  }
  static double lat(int k) { return 30.0 + (k - (kPlates - 1) / 2.0) * kStep; }
};

TEST_F(SkySweep, OnlyThePlatesCrossingARowAreHeldAndTheFitIsTheWholePlatesFit) {
  const std::vector<std::string> paths = write_column();
  SkyOptions options;
  options.target = {{}, 90.0, 30.0, 40, kPlates * 24, kScale, "TAN"};
  SolverOptions solver;
  solver.tolerance = 1e-5;
  SkySummary summary;
  sky_mosaic(paths, options, solver, dir_ / "out.fits", WriteOptions{}, &summary);
  std::printf("%d plates in a column, PQ window %d x %d: at most %zu held at once, %zu crossing a PQ row\n", kPlates,
              summary.pq_window[2], summary.pq_window[3], summary.plates_held,
              summary.plates_crossing);
  EXPECT_GE(summary.plates_held, 2u) << "overlapping plates are held together";
  EXPECT_LE(summary.plates_held, summary.plates_crossing) << "never more than the plates crossing the current rows";
  EXPECT_LE(summary.plates_crossing, kPlates - 4u) << "the column's plates do not all cross one row";
  // The streamed fit (overlap samples in scratch, pairs while both are held) is the whole plates' fit.
  std::vector<sky::Plate> whole;
  for (const std::string& p : paths) whole.push_back(sky::load_plate(p));
  const std::vector<sky::PlateBackground> reference = sky::plate_backgrounds(whole, options.background_damping);
  ASSERT_EQ(summary.backgrounds.size(), reference.size());
  for (std::size_t k = 0; k < reference.size(); ++k) {
    const auto& b = summary.backgrounds[k];
    const std::array<double, 4> r = {reference[k].offset, reference[k].slope_u, reference[k].slope_v, reference[k].radial};
    for (int i = 0; i < 4; ++i) EXPECT_EQ(b[i], r[i]) << "plate " << k << " term " << i;
  }
}

}  // namespace
}  // namespace gdp
