// gdp sky against mathematics: one plate is that plate reprojected, constant background differences vanish, stars keep their flux, errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/sky.h"
#include "image_stream_util.h"
#include "sky_test_util.h"
#include "sky/header.h"
#include "sky/overlap_samples.h"
#include "sky/plate_backgrounds.h"
#include "sky/plate.h"
#include "sky/wcs.h"
#include "sphere/vec3.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;
using test::SkyFunction;

// A smooth sky: a few low-order terms over the sphere.
double smooth_sky(const sphere::Vec3& d) { return 1.0 + 0.3 * d.x + 0.2 * d.y * d.z + 0.1 * std::sin(3.0 * d.z); }

using test::write_plate;

class SkyMosaic : public test::TempDirTest {
 protected:
  // `whole`: the whole PQ sphere (what --toast needs), else the plates' PQ window.
  Image run(const std::vector<std::string>& plates, const SkyTarget& target, bool blend, bool whole = false) {
    SkyOptions options;
    options.target = target;
    options.blend = blend;
    options.fit_backgrounds = fit_;
    options.pq_height = pq_height_;
    options.star_seams = star_seams_;
    options.seam_plates = seam_plates_;
    if (whole) options.toast = dir_ / "toast";
    fs::remove_all(dir_ / "toast");
    SolverOptions solver;
    solver.tolerance = 1e-7;
    solver.precision = Precision::Float64;
    const fs::path out = dir_ / (blend ? "blend.fits" : "seamed.fits");
    sky_mosaic(plates, options, solver, out, WriteOptions{}, &summary_);
    return read_image(out).image;
  }
  SkySummary summary_;
  int pq_height_ = 0;
  bool fit_ = false;  // --fit-backgrounds
  bool star_seams_ = true;
  std::vector<std::string> seam_plates_;
};

TEST_F(SkyMosaic, OnePlateIsThatPlateReprojected) {
  const std::string plate = write_plate(dir_, "a.fits", 40.0, 20.0, 48, 0.5, smooth_sky, 0.0);
  // The target: the plate's own grid widened by 8 pixels on every side.
  const SkyTarget target{{}, 40.0, 20.0, 64, 64, 0.5, "TAN"};
  const Image blended = run({plate}, target, true);
  const Image seamed = run({plate}, target, false);
  const Image truth = read_image(plate).image;
  int covered = 0;
  double worst = 0.0, truth_error = 0.0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const float b = blended.at(0, x, y), s = seamed.at(0, x, y);
      // Pixels of the plate are covered (but for a PQ pixel at its edges); pixels beyond are blank.
      if (x >= 10 && x < 54 && y >= 10 && y < 54) {
        ASSERT_TRUE(std::isfinite(b)) << x << " " << y;
      }
      if (x < 6 || x >= 58 || y < 6 || y >= 58) {
        ASSERT_TRUE(std::isnan(b)) << x << " " << y;
      }
      ASSERT_EQ(std::isnan(b), std::isnan(s)) << x << " " << y;
      if (std::isnan(b)) continue;
      ++covered;
      worst = std::max(worst, std::abs(double(b) - s));
      if (x >= 10 && x < 54 && y >= 10 && y < 54)
        truth_error = std::max(truth_error, std::abs(double(b) - truth.at(0, x - 8, y - 8)));
    }
  EXPECT_GE(covered, 46 * 46);
  EXPECT_LE(worst, 1e-4) << "the solve changes a single plate's reprojection";
  EXPECT_LE(truth_error, 2e-3) << "resampling through the PQ sphere and back (range 1)";
}

TEST_F(SkyMosaic, AConstantBackgroundDifferenceIsRemovedExactly) {
  // A constant sky seen by two overlapping plates 0.5 apart: the blend is one constant, the mean.
  const SkyFunction flat = [](const sphere::Vec3&) { return 2.0; };
  const std::vector<std::string> plates = {write_plate(dir_, "a.fits", 30.0, 10.0, 40, 0.5, flat, 0.0),
                                           write_plate(dir_, "b.fits", 42.0, 12.0, 40, 0.5, flat, 0.5)};
  const SkyTarget target{{}, 36.0, 11.0, 70, 50, 0.5, "CAR"};
  for (const bool fit : {false, true}) {
    SCOPED_TRACE(fit ? "with fitted backgrounds" : "offsets only");
    fit_ = fit;
    const Image seamed = run(plates, target, false);
    const Image blended = run(plates, target, true);
    ASSERT_GT(summary_.plate_pixels[0], 0);
    ASSERT_GT(summary_.plate_pixels[1], 0);
    double lo = 1e9, hi = -1e9;
    int at_a = 0, at_b = 0;  // seamed pixels of either plate's level (the cubic rings at the step)
    for (std::size_t k = 0; k < blended.data.size(); ++k) {
      if (std::isnan(blended.data[k])) continue;
      lo = std::min(lo, double(blended.data[k]));
      hi = std::max(hi, double(blended.data[k]));
      at_a += std::abs(seamed.data[k] - 2.0) < 1e-5;
      at_b += std::abs(seamed.data[k] - 2.5) < 1e-5;
    }
    EXPECT_GT(at_a, 500) << "both plates are in the seamed mosaic";
    EXPECT_GT(at_b, 500) << "both plates are in the seamed mosaic";
    EXPECT_LE(hi - lo, 1e-5) << "the blend is constant";
    EXPECT_GT(lo, 2.0);
    EXPECT_LT(hi, 2.5);
  }
}

TEST_F(SkyMosaic, ASmoothSkyKeepsItsShapeAcrossTheSeam) {
  // The smooth sky with plates 0.5 apart: the blend differs from the sky by nearly a constant
  // (seams take the mean of both plates' gradients: 0.0036, what the extensions and the
  // resampling leave; 0.0066 with zero guidance across the seam), the seamed mosaic by the step.
  const std::vector<std::string> plates = {write_plate(dir_, "a.fits", 30.0, 10.0, 40, 0.5, smooth_sky, 0.0),
                                           write_plate(dir_, "b.fits", 42.0, 12.0, 40, 0.5, smooth_sky, 0.5)};
  const SkyTarget target{{}, 36.0, 11.0, 70, 50, 0.5, "CAR"};
  const Image blended = run(plates, target, true);
  const sky::Wcs wcs(sky::target_header(target), 70, 50, "target");
  double lo = 1e9, hi = -1e9;
  for (int y = 0; y < 50; ++y)
    for (int x = 0; x < 70; ++x) {
      if (std::isnan(blended.at(0, x, y))) continue;
      double a = 0, b = 0;
      ASSERT_TRUE(wcs.pixel_to_sky(x + 0.5, y + 0.5, a, b));
      const double e = blended.at(0, x, y) - smooth_sky(sky::direction(a, b));
      lo = std::min(lo, e);
      hi = std::max(hi, e);
    }
  std::printf("smooth sky: blend - sky varies by %.4f\n", hi - lo);
  EXPECT_LE(hi - lo, 0.005) << "of a 0.5 step";
}

// Three overlapping plates of the smooth sky, each with its own background in its pixel
// coordinates (x, y) of a 40-pixel plate; `scale` 0: no backgrounds, offsets only.
struct ThreePlates {
  std::array<sky::PlateBackground, 3> truth;
  std::vector<sky::Plate> plates;

  // `defect`: added to the first plate only (a star or flaw the others do not show).
  ThreePlates(const fs::path& dir, double scale, const SkyFunction& defect = {}) {
    truth = {{{0.0, 0.05, -0.03, 0.08}, {0.5, -0.04, 0.02, -0.06}, {-0.2, 0.03, 0.05, 0.1}}};
    const std::array<std::array<double, 2>, 3> centres = {{{30.0, 10.0}, {42.0, 12.0}, {36.0, 24.0}}};
    for (int k = 0; k < 3; ++k) {
      sky::PlateBackground b = truth[k];
      b.slope_u *= scale;
      b.slope_v *= scale;
      b.radial *= scale;
      truth[k] = b;
      const auto background = [b](double x, double y) {
        const double u = (x - 20.0) / 40.0, v = (y - 20.0) / 40.0;
        const double mean = 2.0 * (40.0 * 40.0 - 1.0) / (12.0 * 40.0 * 40.0);  // of u^2 + v^2 over the pixels
        return b.slope_u * u + b.slope_v * v + b.radial * (u * u + v * v - mean);
      };
      const std::string name = std::string(1, char('a' + k)) + ".fits";
      const SkyFunction sky = [&](const sphere::Vec3& d) { return smooth_sky(d) + (k == 0 && defect ? defect(d) : 0.0); };
      plates.push_back(
          sky::load_plate(write_plate(dir, name, centres[k][0], centres[k][1], 40, 0.5, sky, b.offset, background)));
    }
  }
};

double model(const sky::Plate& p, const sky::PlateBackground& b, double x, double y) {
  const auto f = sky::background_basis(p, x, y);
  return b.offset * f[0] + b.slope_u * f[1] + b.slope_v * f[2] + b.radial * f[3];
}

// The fitted backgrounds' differences against the true ones over every pair's overlap: rms of
// the error and of the true differences' smooth part (offsets left out of both).
std::array<double, 2> difference_errors(const ThreePlates& t, const std::vector<sky::PlateBackground>& fitted) {
  double error = 0.0, size = 0.0;
  long long n = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
      for (const sky::OverlapSample& s : sky::overlap_samples(t.plates[a], t.plates[b])) {
        const double truth = model(t.plates[a], t.truth[a], s.ax, s.ay) - model(t.plates[b], t.truth[b], s.bx, s.by);
        const double fit = model(t.plates[a], fitted[a], s.ax, s.ay) - model(t.plates[b], fitted[b], s.bx, s.by);
        const double offsets = (t.truth[a].offset - t.truth[b].offset);
        error += (fit - truth) * (fit - truth);
        size += (truth - offsets) * (truth - offsets);
        ++n;
      }
  return {std::sqrt(error / n), std::sqrt(size / n)};
}

TEST_F(SkyMosaic, FittedBackgroundsRecoverTheDifferences) {
  const ThreePlates t(dir_, 1.0);
  const std::vector<sky::PlateBackground> fitted = sky::plate_backgrounds(t.plates, 1e-3);
  const auto [error, size] = difference_errors(t, fitted);
  std::printf("fitted background differences: rms error %.2e of %.2e\n", error, size);
  EXPECT_GT(size, 0.01);
  EXPECT_LE(error, 0.02 * size) << "the fit recovers the plates' background differences";
}

TEST_F(SkyMosaic, TheBackgroundFitIgnoresADefectInAnOverlap) {
  // A bright blob (sigma 1 plate pixel, peak 3) in plate a only, in the middle of its overlap with
  // b: least squares reads it as background; Huber's weights leave it out.
  const sphere::Vec3 spot = sky::direction(36.0, 11.0);
  const ThreePlates t(dir_, 1.0, [&](const sphere::Vec3& d) {
    const double theta = sphere::angle(d, spot) * 180.0 / M_PI;
    return 3.0 * std::exp(-theta * theta / (2.0 * 0.5 * 0.5));
  });
  const double robust = difference_errors(t, sky::plate_backgrounds(t.plates, 1e-3))[0];
  const auto [plain, size] = difference_errors(t, sky::plate_backgrounds(t.plates, 1e-3, false));
  std::printf("background fit with a defect: rms error %.2e (least squares %.2e) of %.2e\n", robust, plain, size);
  EXPECT_LE(robust, 0.02 * size) << "the robust fit recovers the plates' background differences";
  EXPECT_GT(plain, 2.0 * robust) << "least squares is pulled by the defect: what this test sees";
}

TEST_F(SkyMosaic, NoBackgroundFitsNearlyZero) {
  const ThreePlates t(dir_, 0.0);
  const std::vector<sky::PlateBackground> fitted = sky::plate_backgrounds(t.plates, 1e-3);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LE(std::abs(fitted[k].slope_u) + std::abs(fitted[k].slope_v) + std::abs(fitted[k].radial), 1e-3) << k;
    EXPECT_NEAR(fitted[k].offset - fitted[0].offset, t.truth[k].offset - t.truth[0].offset, 1e-3) << k;
  }
}

TEST_F(SkyMosaic, ThePlatesWindowAndTheWholeSphereAgree) {
  const std::vector<std::string> plates = {write_plate(dir_, "a.fits", 30.0, 10.0, 40, 0.5, smooth_sky, 0.0),
                                           write_plate(dir_, "b.fits", 42.0, 12.0, 40, 0.5, smooth_sky, 0.5)};
  const SkyTarget target{{}, 36.0, 11.0, 70, 50, 0.5, "CAR"};
  pq_height_ = 256;  // a TOAST height, for both
  const Image window = run(plates, target, true);
  const std::array<int, 4> solved = summary_.pq_window;
  const Image sphere = run(plates, target, true, true);
  EXPECT_LT(solved[2], 4 * summary_.pq_height / 4) << "a window, not the whole PQ image";
  EXPECT_EQ(summary_.pq_window[2], 4 * summary_.pq_height) << "the whole sphere";
  double worst = 0.0;
  for (std::size_t k = 0; k < window.data.size(); ++k) {
    ASSERT_EQ(std::isnan(window.data[k]), std::isnan(sphere.data[k])) << k;
    if (!std::isnan(window.data[k])) worst = std::max(worst, std::abs(double(window.data[k]) - sphere.data[k]));
  }
  std::printf("window vs whole sphere: %.2e\n", worst);
  EXPECT_LE(worst, 1e-3);
}

// A Gaussian star of `flux` (value x square degrees) and sigma `sigma` degrees at `centre`.
SkyFunction star(const sphere::Vec3& centre, double flux, double sigma) {
  return [=](const sphere::Vec3& d) {
    const double theta = sphere::angle(d, centre) * 180.0 / M_PI;
    return flux / (2.0 * M_PI * sigma * sigma) * std::exp(-theta * theta / (2.0 * sigma * sigma));
  };
}

// The sum over the pixels within 6.5 pixels of (x, y) of `image` less the median of those 9 to
// 12 pixels away (the bench's aperture flux).
double aperture_flux(const Image& image, int x, int y) {
  double sum = 0.0;
  std::vector<double> outer;
  int inner = 0;
  for (int dy = -12; dy <= 12; ++dy)
    for (int dx = -12; dx <= 12; ++dx) {
      const double r = std::hypot(dx, dy), v = image.at(0, x + dx, y + dy);
      EXPECT_TRUE(std::isfinite(v)) << x + dx << " " << y + dy;
      if (r <= 6.5) sum += v, ++inner;
      if (r >= 9.0) outer.push_back(v);
    }
  std::nth_element(outer.begin(), outer.begin() + outer.size() / 2, outer.end());
  return sum - inner * outer[outer.size() / 2];
}

TEST_F(SkyMosaic, AStarOnTheSeamKeepsItsFlux) {
  // Two plates 0.5 apart on the smooth sky, a star (sigma 1.5 plate pixels, peak 1) on the
  // medial line of their overlap, where the plain seam rule cuts it. The star image: the blend
  // with the star less the blend without it on the same seams (the star's plates place them).
  const double sigma = 0.75;
  const sphere::Vec3 centre = sky::direction(36.0, 11.0);
  const SkyFunction bright = star(centre, 2.0 * M_PI * sigma * sigma, sigma);
  const SkyFunction starry = [&](const sphere::Vec3& d) { return smooth_sky(d) + bright(d); };
  const std::vector<std::string> plain = {write_plate(dir_, "a.fits", 30.0, 10.0, 40, 0.5, smooth_sky, 0.0),
                                          write_plate(dir_, "b.fits", 42.0, 12.0, 40, 0.5, smooth_sky, 0.5)};
  const std::vector<std::string> stars = {write_plate(dir_, "as.fits", 30.0, 10.0, 40, 0.5, starry, 0.0),
                                          write_plate(dir_, "bs.fits", 42.0, 12.0, 40, 0.5, starry, 0.5)};
  const SkyTarget target{{}, 36.0, 11.0, 70, 50, 0.5, "CAR"};
  const sky::Wcs wcs(sky::target_header(target), 70, 50, "target");
  double px = 0, py = 0;
  ASSERT_TRUE(wcs.sky_to_pixel(36.0, 11.0, px, py));
  const int x = static_cast<int>(px), y = static_cast<int>(py);
  Image truth(70, 50, 1);
  for (int j = 0; j < 50; ++j)
    for (int i = 0; i < 70; ++i) {
      double a = 0, b = 0;
      ASSERT_TRUE(wcs.pixel_to_sky(i + 0.5, j + 0.5, a, b));
      truth.at(0, i, j) = static_cast<float>(bright(sky::direction(a, b)));
    }
  const double expected = aperture_flux(truth, x, y);
  const auto relative_error = [&](bool star_seams) {
    star_seams_ = star_seams;
    Image with = run(stars, target, true);
    seam_plates_ = star_seams ? stars : std::vector<std::string>{};
    const Image without = run(plain, target, true);
    seam_plates_.clear();
    for (std::size_t k = 0; k < with.data.size(); ++k) with.data[k] -= without.data[k];
    return aperture_flux(with, x, y) / expected - 1.0;
  };
  const double kept = relative_error(true), cut = relative_error(false);
  std::printf("star on the seam: flux error %.2e around it, %.2e through it\n", kept, cut);
  EXPECT_LE(std::abs(kept), 1e-3);
  EXPECT_GT(std::abs(cut), 2.0 * std::abs(kept)) << "the plain rule cuts the star: it is what this test sees";
}

TEST_F(SkyMosaic, AStarCutByAPlateEdgeAtACoverageGapStaysPut) {
  // Two plates of the smooth sky side by side at the equator (their facing edges are meridians)
  // with a gap of 2 pixels between them; a star (sigma 1.5 plate pixels, peak 1) 2 pixels inside
  // a's edge, cut by it, and one 14 pixels inside b. The solve's own change: the star image
  // (plates with stars less plates without, on the same seams) of the blend less that of the
  // seamed mosaic. An extension that repeats a's edge pixels outwards carries the cut star across
  // the gap into b's extension, and the solve spreads that mismatch into both plates.
  const double sigma = 0.75, edge = std::atan(10.0 * M_PI / 180.0) * 180.0 / M_PI;  // centre to edge, degrees
  const double lon_b = 30.0 + 2.0 * edge + 1.0;
  const SkyFunction cut = star(sky::direction(30.0 + edge - 1.0, 0.0), 2.0 * M_PI * sigma * sigma, sigma);
  const sphere::Vec3 centre = sky::direction(lon_b - edge + 7.0, 2.0);
  const SkyFunction inside = star(centre, 2.0 * M_PI * sigma * sigma, sigma);
  const SkyFunction starry = [&](const sphere::Vec3& d) { return smooth_sky(d) + cut(d) + inside(d); };
  const std::vector<std::string> plain = {write_plate(dir_, "a.fits", 30.0, 0.0, 40, 0.5, smooth_sky, 0.0),
                                          write_plate(dir_, "b.fits", lon_b, 0.0, 40, 0.5, smooth_sky, 0.0)};
  const std::vector<std::string> stars = {write_plate(dir_, "as.fits", 30.0, 0.0, 40, 0.5, starry, 0.0),
                                          write_plate(dir_, "bs.fits", lon_b, 0.0, 40, 0.5, starry, 0.0)};
  const SkyTarget target{{}, (30.0 + lon_b) / 2.0, 0.0, 90, 50, 0.5, "CAR"};
  const auto star_image = [&](bool blend) {
    Image with = run(stars, target, blend);
    seam_plates_ = stars;
    const Image without = run(plain, target, blend);
    seam_plates_.clear();
    for (std::size_t k = 0; k < with.data.size(); ++k) with.data[k] -= without.data[k];
    return with;
  };
  const Image blended = star_image(true), seamed = star_image(false);
  double worst = 0.0;
  for (std::size_t k = 0; k < blended.data.size(); ++k)
    if (std::isfinite(blended.data[k])) worst = std::max(worst, std::abs(double(blended.data[k]) - seamed.data[k]));
  double px = 0, py = 0;
  ASSERT_TRUE(sky::Wcs(sky::target_header(target), 90, 50, "target").sky_to_pixel(lon_b - edge + 7.0, 2.0, px, py));
  const int x = static_cast<int>(px), y = static_cast<int>(py);
  const double change = aperture_flux(blended, x, y) / aperture_flux(seamed, x, y) - 1.0;
  std::printf("star cut at a gap: the solve changes pixels by %.2e, the star inside b by %.2e\n", worst, change);
  EXPECT_LE(worst, 5e-3) << "of the star's peak 1 (0.12 with the edge drawn out)";
  EXPECT_LE(std::abs(change), 1e-3) << "(1.3e-2 with the edge drawn out)";
}

TEST_F(SkyMosaic, BadInputIsAnInputErrorNamingTheFile) {
  const std::string plate = write_plate(dir_, "a.fits", 40.0, 20.0, 16, 0.5, smooth_sky, 0.0);
  write_image(dir_ / "nowcs.fits", Image(8, 8, 1, 1.0f), WriteOptions{});
  const auto message = [&](const std::vector<std::string>& plates, const SkyTarget& target) -> std::string {
    try {
      run(plates, target, true);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  const std::string nowcs = message({plate, (dir_ / "nowcs.fits").string()}, {{}, 40.0, 20.0, 16, 16, 0.5, "TAN"});
  EXPECT_NE(nowcs.find("nowcs.fits: no celestial WCS"), std::string::npos) << nowcs;
  const std::string far = message({plate}, {{}, 220.0, -20.0, 16, 16, 0.5, "TAN"});
  EXPECT_NE(far.find("no plate reaches the target"), std::string::npos) << far;
  EXPECT_FALSE(fs::exists(dir_ / "blend.fits"));
}

}  // namespace
}  // namespace gdp
