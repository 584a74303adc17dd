// gdp sky's plate passes as sweeps: only the plates crossing the current PQ rows are held, and the results are those of whole plates.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "bands/transport.h"
#include "gdp/errors.h"
#include "gdp/sky.h"
#include "image_stream_util.h"
#include "sky/plate.h"
#include "sky/plate_backgrounds.h"
#include "sky/mosaic_rows.h"
#include "sky/plate_passes.h"
#include "sky/plate_sweep.h"
#include "sky/pq_window.h"
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
      paths.push_back(test::write_plate(dir_, fmt::format("p{}.fits", k), 90.0, lat(k), kSize, kScale, sky,
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

// One rank's (or the one process's) plate passes over the column's plates: the plates with their
// levels and edge corrections, the fit and stars, and the plate pixels it read.
struct Intake {
  std::vector<sky::Plate> plates;
  sky::PlateIntake in;
  long long pixels_read = 0;
};

Intake take_in(const std::vector<std::string>& paths, const std::filesystem::path& temp, const sky::PlateShare& share) {
  Intake r;
  for (const std::string& p : paths) r.plates.push_back(sky::open_plate(p));
  std::vector<sky::Plate> finders;
  const sky::PqWindow win = *sky::plate_window(r.plates, 2048, sky::kExtension);
  sky::PlatePixels pixels(r.plates, finders, win, sky::kReleaseLag);
  sky::IntakeOptions options;
  options.temp_dir = temp;
  r.in = sky::take_in_plates(r.plates, pixels, options, share);
  r.pixels_read = pixels.pixels_read();
  return r;
}

// Two ranks (threads on the band transport) share the passes, each owning the plates `owners`
// gives it: each reads fewer plate pixels than one process, and both end with the one process's
// backgrounds, levels, edge corrections and stars, bit for bit.
TEST_F(SkySweep, RanksSharingThePassesGetTheOneProcessResultsBitForBit) {
  const std::vector<std::string> paths = write_column();
  const Intake one = take_in(paths, dir_, {});
  ASSERT_TRUE(one.in.stars.has_value());
  ASSERT_GT(one.in.stars->size(), 0u) << "stars in the overlaps";
  for (const bool halves : {true, false}) {
    std::vector<int> owners;
    for (int k = 0; k < kPlates; ++k) owners.push_back(halves ? k >= kPlates / 2 : k % 2);
    bands::ThreadHub hub(2);
    Intake ranks[2];
    std::string failed[2];
    std::vector<std::thread> threads;
    for (int r = 0; r < 2; ++r)
      threads.emplace_back([&, r] {
        sky::PlateShare share;
        share.net = &hub.endpoint(r);
        share.owners = owners;
        share.agree = [&, r](const std::string& error) {  // the first rank's error, on both
          bands::Bytes first;
          for (bands::Bytes& b : bands::all_gather(*share.net, 99, bands::Bytes(error.begin(), error.end())))
            if (first.empty()) first = b;
          if (!first.empty()) throw UsageError(std::string(first.begin(), first.end()));
        };
        try {
          ranks[r] = take_in(paths, dir_, share);
        } catch (const std::exception& e) {
          failed[r] = e.what();
        }
      });
    for (std::thread& t : threads) t.join();
    const std::string how = halves ? "plates 0-4 and 5-9" : "alternate plates";
    for (int r = 0; r < 2; ++r) {
      ASSERT_EQ(failed[r], "") << how << ", rank " << r;
      std::printf("%s: rank %d read %lld plate pixels, one process %lld\n", how.c_str(), r, ranks[r].pixels_read,
                  one.pixels_read);
      if (halves) {
        EXPECT_LT(ranks[r].pixels_read, one.pixels_read) << how << ": rank " << r << " read every plate";
      }
      const Intake& got = ranks[r];
      EXPECT_EQ(got.in.overlap_samples, one.in.overlap_samples) << how;
      ASSERT_EQ(got.in.backgrounds.size(), one.in.backgrounds.size());
      for (int k = 0; k < kPlates; ++k) {
        const auto &a = got.in.backgrounds[k], &b = one.in.backgrounds[k];
        EXPECT_EQ(a.offset, b.offset) << how << ", rank " << r << ", plate " << k;
        EXPECT_EQ(a.slope_u, b.slope_u);
        EXPECT_EQ(a.slope_v, b.slope_v);
        EXPECT_EQ(a.radial, b.radial);
        EXPECT_EQ(got.plates[k].mean, one.plates[k].mean) << how << ", rank " << r << ", plate " << k;
        EXPECT_EQ(got.plates[k].fade_to, one.plates[k].fade_to) << how << ", rank " << r << ", plate " << k;
        EXPECT_EQ(got.plates[k].edge_correction, one.plates[k].edge_correction) << how << ", plate " << k;
      }
      ASSERT_TRUE(got.in.stars.has_value());
      EXPECT_EQ(got.in.stars->size(), one.in.stars->size()) << how;
      for (int k = 0; k + 1 < kPlates; ++k)  // around each overlap's star: the same plate at every point
        for (int a = -8; a <= 8; ++a)
          for (int b = -8; b <= 8; ++b) {
            const sphere::Vec3 d = sky::direction(90.3 + 0.05 * a, lat(k) + kStep / 2 + 0.05 * b);
            EXPECT_EQ(got.in.stars->plate_at(d), one.in.stars->plate_at(d)) << how << ", star " << k;
          }
    }
  }
}

}  // namespace
}  // namespace gdp
