// gdp sky --projected: images cut from one sky on a template, each with its own background, blended back; bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <functional>

#include <fmt/format.h>

#include "cli_fixture.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/sky_projected.h"
#include "sky/header.h"
#include "sky_test_util.h"
#include "stats_file.h"

namespace gdp {
namespace {

constexpr int kW = 120, kH = 90;  // the template, TAN at (150, 30), 0.01 degree pixels

// The sky at template pixel (x, y): smooth structure and a few stars.
double sky_at(int x, int y) {
  double v = 0.5 + 0.2 * std::sin(0.21 * x) * std::cos(0.13 * y) + 0.1 * std::sin(0.05 * (x + 2 * y));
  for (const auto& [sx, sy] : {std::pair{30.0, 20.0}, {70.0, 47.0}, {100.0, 75.0}})
    v += 0.8 * std::exp(-((x - sx) * (x - sx) + (y - sy) * (y - sy)) / 4.0);
  return v;
}

using Background = std::function<double(int, int)>;  // of the image's own pixel

class SkyProjected : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    std::ofstream(path("t.hdr")) << fmt::format(
        "SIMPLE = T\nBITPIX = -64\nNAXIS = 2\nNAXIS1 = {}\nNAXIS2 = {}\nCTYPE1 = 'RA---TAN'\nCTYPE2 = 'DEC--TAN'\n"
        "CRVAL1 = 150.0\nCRVAL2 = 30.0\nCRPIX1 = 60.5\nCRPIX2 = 45.5\nCDELT1 = -0.01\nCDELT2 = 0.01\nEND\n",
        kW, kH);
  }

  // The template's WCS cards for an image h pixels high whose pixel (0, 0) is template pixel (x0, y0)
  // (gdp's pixels, rows top down; FITS rows count from the bottom).
  static std::string cards(int x0, int y0, int h, double shift_x = 0.0, const std::string& code = "TAN",
                           double cdelt1 = -0.01) {
    std::string c;
    for (const auto& [key, value] :
         {std::pair<std::string, std::string>{"CTYPE1", "'RA---" + code + "'"}, {"CTYPE2", "'DEC--" + code + "'"},
          {"CRVAL1", "150.0"}, {"CRVAL2", "30.0"}, {"CRPIX1", fmt::format("{}", 60.5 - x0 + shift_x)},
          {"CRPIX2", fmt::format("{}", 45.5 - (kH - y0 - h))}, {"CDELT1", fmt::format("{}", cdelt1)},
          {"CDELT2", "0.01"}})
      c += sky::card(key, value);
    return c;
  }

  // Writes the sky's [x0, x0 + w) x [y0, y0 + h) plus `background`, NaN where `blank` says.
  void cut(const std::string& name, int x0, int y0, int w, int h, const Background& background,
           const std::function<bool(int, int)>& blank = {}, const std::string& header = "") {
    Image image(w, h, 1);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        image.at(0, x, y) = blank && blank(x, y) ? NAN : static_cast<float>(sky_at(x0 + x, y0 + y) + background(x, y));
    WriteOptions o;
    o.fits_header = header.empty() ? cards(x0, y0, h) : header;
    write_image(path(name), image, o);
  }

  // Two images overlapping by 20 columns, covering the template but for two corners and a gap
  // at the bottom where their seam ends (their own blank pixels): 308 pixels.
  void two(const Background& a, const Background& b) {
    cut("a.fits", 0, 0, 70, 90, a, [](int x, int y) { return x + (89 - y) < 12 || (x >= 50 && y >= 80); });
    cut("b.fits", 50, 0, 70, 90, b, [](int x, int y) { return (69 - x) + y < 15 || (x <= 10 && y >= 80); });
  }

  // Three overlapping images meeting at a junction, blank corners and a gap as above.
  void three(const Background& a, const Background& b, const Background& c) {
    cut("a.fits", 0, 0, 60, 90, a, [](int x, int y) { return x + (89 - y) < 12 || (x >= 45 && y >= 80); });
    cut("b.fits", 45, 0, 75, 50, b, [](int x, int y) { return (74 - x) + y < 15; });  // top-right corner
    cut("c.fits", 40, 40, 80, 50, c, [](int x, int y) { return x <= 15 && y >= 40; });
  }

  Image run(const std::vector<std::string>& names, Schedule schedule = Schedule::Streaming, bool fit = true,
            ProjectedSummary* summary = nullptr) {
    std::vector<ProjectedInput> inputs;
    for (const std::string& n : names) inputs.push_back({path(n), ""});
    SolverOptions solver;
    solver.precision = Precision::Float64;
    solver.tolerance = 1e-10;
    solver.schedule = schedule;
    solver.bands = schedule == Schedule::Bands ? 3 : 1;
    ProjectedOptions options;
    options.header = path("t.hdr");
    options.fit_backgrounds = fit;
    options.graphcut_seams = graphcut_;
    sky_projected(inputs, options, solver, path("out.fits"), WriteOptions{}, summary);
    return read_image(path("out.fits")).image;
  }

  bool graphcut_ = false;  // --seams graphcut
};

// Sky minus output over the covered pixels: {max - min after removing the mean, covered count}.
std::pair<double, int> spread_from_sky(const Image& out) {
  double lo = 1e9, hi = -1e9;
  int covered = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float v = out.at(0, x, y);
      if (!std::isfinite(v)) continue;
      ++covered;
      lo = std::min(lo, v - sky_at(x, y));
      hi = std::max(hi, v - sky_at(x, y));
    }
  return {hi - lo, covered};
}

// |output - sky - their median| over the covered pixels, sorted.
std::vector<double> off_the_median(const Image& out) {
  std::vector<double> e;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if (std::isfinite(out.at(0, x, y))) e.push_back(out.at(0, x, y) - sky_at(x, y));
  std::sort(e.begin(), e.end());
  const double median = e[e.size() / 2];
  std::vector<double> off;
  for (const double v : e) off.push_back(std::abs(v - median));
  std::sort(off.begin(), off.end());
  return off;
}

// Without the levels taken off first, the gap where the seam ends (its pixels run the composite's
// differences, 0 - value, as blend's Extend) would make the correction field inconsistent there.
TEST_F(SkyProjected, AConstantBackgroundDifferenceIsRemovedExactly) {
  two([](int, int) { return 0.3; }, [](int, int) { return -0.2; });
  const Image out = run({"a.fits", "b.fits"});
  ASSERT_EQ(out.width, kW);
  ASSERT_EQ(out.height, kH);
  const auto [spread, covered] = spread_from_sky(out);
  EXPECT_LT(spread, 1e-5) << "output = sky + one constant";
  EXPECT_EQ(covered, kW * kH - 308) << "the blank corners and the gap stay NaN";
  EXPECT_TRUE(std::isnan(out.at(0, 0, 89)) && std::isnan(out.at(0, 119, 0)) && std::isnan(out.at(0, 55, 85)));
}

// --seams graphcut (gdp blend's cut on the levelled images): a constant difference is still removed
// exactly, and with a ridge (not a plane: the fit leaves it) along the middle of the overlap, where
// the depth seams run, the cut leaves it and costs under 0.7 of the depth seams.
TEST_F(SkyProjected, GraphcutSeamsKeepTheLevelsExactAndLeaveADisagreement) {
  graphcut_ = true;
  two([](int, int) { return 0.3; }, [](int, int) { return -0.2; });
  ProjectedSummary flat;
  EXPECT_LT(spread_from_sky(run({"a.fits", "b.fits"}, Schedule::Streaming, true, &flat)).first, 1e-5);
  EXPECT_LE(flat.blend.seam_cost, flat.blend.seam_cost_depth);
  two([](int, int) { return 0.3; }, [](int x, int) { return -0.2 + 0.3 * std::exp(-(x - 10) * (x - 10) / 4.5); });
  ProjectedSummary ridge;
  run({"a.fits", "b.fits"}, Schedule::Streaming, true, &ridge);
  std::printf("seam cost: depth %.4g, graph cut %.4g\n", ridge.blend.seam_cost_depth, ridge.blend.seam_cost);
  EXPECT_LT(ridge.blend.seam_cost, 0.7 * ridge.blend.seam_cost_depth);
}

// Where three images meet, blend's seam guidance has no single across value (a pixel next to two
// other labels) and takes zero there: the levels are right, the junction's few edges are not.
TEST_F(SkyProjected, ThreeImagesLevelToOneConstantAwayFromTheirJunction) {
  three([](int, int) { return 0.3; }, [](int, int) { return -0.2; }, [](int, int) { return 0.05; });
  const std::vector<double> off = off_the_median(run({"a.fits", "b.fits", "c.fits"}));
  EXPECT_LT(off[off.size() * 99 / 100], 1e-3) << "99 % of the pixels: the jumps were 0.25 to 0.5";
  EXPECT_LT(off.back(), 0.02) << "the junction";
}

// Planes differ between the images: they stay inside each (they are its gradients), but the
// seam goes: the error's steps between neighbours are about the planes' slope, not the jump
// (0.42 to 0.55 along the seam); the largest, where the seam ends in the gap, a few times that.
TEST_F(SkyProjected, PlaneBackgroundsLeaveNoSeams) {
  const auto plane = [](double a, double b, double c) { return [=](int x, int y) { return a + b * x + c * y; }; };
  two(plane(0.3, 1e-3, -5e-4), plane(-0.2, -8e-4, 1e-3));
  const Image out = run({"a.fits", "b.fits"});
  std::vector<double> steps;
  for (int y = 0; y + 1 < kH; ++y)
    for (int x = 0; x + 1 < kW; ++x) {
      const double e = out.at(0, x, y) - sky_at(x, y);
      const double right = out.at(0, x + 1, y) - sky_at(x + 1, y), down = out.at(0, x, y + 1) - sky_at(x, y + 1);
      if (std::isfinite(e) && std::isfinite(right)) steps.push_back(std::abs(right - e));
      if (std::isfinite(e) && std::isfinite(down)) steps.push_back(std::abs(down - e));
    }
  std::sort(steps.begin(), steps.end());
  EXPECT_LT(steps[steps.size() * 99 / 100], 3e-3);
  EXPECT_LT(steps.back(), 0.03);
}

// Four images of 80 x 60 in a 2 x 2 grid (overlaps of 40 columns and 30 rows), each with its own
// offset + plane + radial term in its own pixels (the model gdp fits). Overlaps see the differences
// of the backgrounds, not what all share (a plane and bowl over the mosaic); the fit takes, among
// the backgrounds that explain them, the least energetic. These backgrounds' signs alternate so
// that they are that one: the fit recovers them (to its damping's shrinkage) and the output is the
// sky plus one constant. Without the fit the planes and bowls stay (the solve keeps each image's
// own gradients).
TEST_F(SkyProjected, FittedPlaneAndRadialBackgroundsAreTakenOff) {
  constexpr double kSlopeU = 0.08, kSlopeV = -0.05, kRadial = 0.12;
  const auto background = [&](double offset, double sign) {
    return [=](int x, int y) {
      const double u = (x + 0.5 - 40.0) / 80.0, v = (y + 0.5 - 30.0) / 80.0;
      return offset + sign * (kSlopeU * u + kSlopeV * v + kRadial * (u * u + v * v));
    };
  };
  const double offsets[4] = {0.3, -0.2, 0.1, 0.0}, signs[4] = {1, -1, -1, 1};
  const std::vector<std::string> names = {"tl.fits", "tr.fits", "bl.fits", "br.fits"};
  for (int k = 0; k < 4; ++k) cut(names[k], 40 * (k % 2), 30 * (k / 2), 80, 60, background(offsets[k], signs[k]));
  ProjectedSummary fitted;
  const std::vector<double> with_fit = off_the_median(run(names, Schedule::Streaming, true, &fitted));
  const std::vector<double> without = off_the_median(run(names, Schedule::Streaming, false));
  const std::size_t p99 = with_fit.size() * 99 / 100;
  std::cerr << "off the median, 99th percentile and worst: fitted " << with_fit[p99] << ", " << with_fit.back()
            << "; without the fit " << without[p99] << ", " << without.back() << "\n";
  EXPECT_LT(with_fit[p99], 2e-3) << "output = sky + one constant (measured 9.8e-4)";
  EXPECT_LT(with_fit.back(), 0.03) << "the junction of the four: zero guidance there (measured 0.011)";
  EXPECT_GT(without[p99], 20 * with_fit[p99]) << "measured 0.044";
  ASSERT_EQ(fitted.backgrounds.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(fitted.backgrounds[k][1], signs[k] * kSlopeU, 2e-3) << names[k];
    EXPECT_NEAR(fitted.backgrounds[k][2], signs[k] * kSlopeV, 2e-3) << names[k];
    EXPECT_NEAR(fitted.backgrounds[k][3], signs[k] * kRadial, 4e-3) << names[k];
  }
}

TEST_F(SkyProjected, SchedulesAgreeWithInCore) {
  const auto plane = [](double a, double b) { return [=](int x, int y) { return a + b * (x - y); }; };
  three(plane(0.3, 1e-3), plane(-0.2, -8e-4), plane(0.1, 5e-4));
  const Image reference = run({"a.fits", "b.fits", "c.fits"}, Schedule::InCore);
  for (const Schedule schedule : {Schedule::Streaming, Schedule::Bands}) {
    const Image out = run({"a.fits", "b.fits", "c.fits"}, schedule);
    double worst = 0.0;
    for (std::size_t k = 0; k < out.data.size(); ++k) {
      ASSERT_EQ(std::isnan(out.data[k]), std::isnan(reference.data[k]));
      if (!std::isnan(out.data[k])) worst = std::max(worst, double(std::abs(out.data[k] - reference.data[k])));
    }
    EXPECT_LT(worst, 1e-6) << (schedule == Schedule::Bands ? "bands" : "streaming");
  }
}

// The CLI under mpirun -np 2 (one band per rank), with the distance and the graph-cut seams, gives
// the one-process result within 1e-4, blanks at the same pixels; --stats counts the covered pixels
// of every rank's columns.
TEST_F(SkyProjected, UnderMpirunTheCliGivesTheOneProcessResult) {
  if (!test::mpirun_works()) GTEST_SKIP() << "mpirun cannot start 2 processes";
  const auto plane = [](double a, double b) { return [=](int x, int y) { return a + b * (x - y); }; };
  three(plane(0.3, 1e-3), plane(-0.2, -8e-4), plane(0.1, 5e-4));
  const std::string inputs = " sky --projected " + path("a.fits") + " " + path("b.fits") + " " + path("c.fits") +
                             " --header " + path("t.hdr") + " --tolerance 1e-6 --quiet";
  for (const std::string seams : {"", " --seams graphcut"}) {
    const auto solve = [&](const std::string& prefix, const std::string& name) {
      const std::string cmd =
          prefix + GDP_CLI_PATH + inputs + seams + " -o " + path(name) + " --stats " + path(name + ".json");
      const test::CliRun r = run_capturing_stderr(cmd);
      EXPECT_EQ(r.code, 0) << cmd << "\n" << r.err;
      return read_image(path(name)).image;
    };
    const Image one = solve("", "one.fits");
    const Image two = solve(test::kMpirun + " -np 2 ", "two.fits");
    ASSERT_EQ(one.data.size(), two.data.size());
    int covered = 0;
    for (std::size_t k = 0; k < one.data.size(); ++k) {
      ASSERT_EQ(std::isnan(one.data[k]), std::isnan(two.data[k])) << k << seams;
      if (std::isnan(one.data[k])) continue;
      EXPECT_NEAR(one.data[k], two.data[k], 1e-4) << k << seams;
      ++covered;
    }
    EXPECT_GT(covered, 5000) << seams;
    EXPECT_EQ(test::stat_of(path("one.fits.json"), "covered_pixels"), covered) << seams;
    EXPECT_EQ(test::stat_of(path("two.fits.json"), "covered_pixels"), covered) << seams << ": the ranks' sum";
  }
}

TEST_F(SkyProjected, OneImageIsThatImage) {
  cut("a.fits", 10, 5, 70, 60, [](int, int) { return 0.0; });
  const Image out = run({"a.fits"});
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const bool in = x >= 10 && x < 80 && y >= 5 && y < 65;
      if (in) EXPECT_NEAR(out.at(0, x, y), sky_at(x, y), 1e-5) << x << "," << y;
      else EXPECT_TRUE(std::isnan(out.at(0, x, y))) << x << "," << y;
    }
}

// Montage's projdir: images, their area images (steradians; 0 where nothing was projected) and
// tables. The template's WCS goes into the output's header.
TEST_F(SkyProjected, ReadsAMontageDirectoryWithAreaImages) {
  std::filesystem::create_directory(path("proj"));
  const double sr = 0.01 * 0.01 * M_PI / 180 * M_PI / 180;
  const auto area = [&](const std::string& name, int x0, int y0, int w, int h, int zero_below) {
    Image a(w, h, 1, static_cast<float>(sr));
    for (int y = zero_below; y < h; ++y)
      for (int x = 0; x < w; ++x) a.at(0, x, y) = x == 0 ? 0.4f * static_cast<float>(sr) : 0.0f;
    WriteOptions o;
    o.fits_header = cards(x0, y0, h);
    write_image(path("proj/" + name), a, o);
  };
  cut("proj/hdu0_a.fits", 0, 0, 70, 90, [](int, int) { return 0.1; });
  cut("proj/hdu0_b.fits", 50, 0, 70, 90, [](int, int) { return -0.1; });
  area("hdu0_a_area.fits", 0, 0, 70, 90, 80);  // a's rows 80.. are not covered
  area("hdu0_b_area.fits", 50, 0, 70, 90, 90);
  std::ofstream(path("proj/stats.tbl")) << "| stat |\n";
  const test::CliRun r = gdp("sky --projected " + path("proj") + " --header " + path("t.hdr") + " -o " +
                             path("out.fits") + " --tolerance 1e-8 --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const Image out = read_image(path("out.fits")).image;
  EXPECT_TRUE(std::isnan(out.at(0, 10, 85))) << "area 0";
  EXPECT_TRUE(std::isnan(out.at(0, 0, 85))) << "area under half a pixel's";
  EXPECT_TRUE(std::isfinite(out.at(0, 60, 85)));
  EXPECT_NEAR(out.at(0, 100, 40) - out.at(0, 10, 40), sky_at(100, 40) - sky_at(10, 40), 1e-4);
  test::expect_template_wcs(path("out.fits"), path("t.hdr"));
}

TEST(SkyProjectedInputs, DirectoriesAndAreaImages) {
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("gdp_projected_inputs_{}", ::getpid());
  std::filesystem::create_directories(dir);
  for (const char* f : {"b.fits", "a.fits", "a_area.fits", "lone_area.fits", "images.tbl"})
    std::ofstream(dir / f) << "x";
  const std::vector<ProjectedInput> in = projected_inputs({dir.string()});
  ASSERT_EQ(in.size(), 3u);
  EXPECT_EQ(in[0].image, (dir / "a.fits").string());
  EXPECT_EQ(in[0].area, (dir / "a_area.fits").string());
  EXPECT_EQ(in[1].image, (dir / "b.fits").string());
  EXPECT_EQ(in[1].area, "");
  EXPECT_EQ(in[2].image, (dir / "lone_area.fits").string()) << "no lone.fits: an image of its own";
  EXPECT_EQ(projected_inputs({(dir / "a.fits").string(), (dir / "a_area.fits").string()}).size(), 1u);
  EXPECT_THROW(projected_inputs({(dir / "none.fits").string()}), InputError);
  std::filesystem::remove_all(dir);
}

TEST_F(SkyProjected, BadInputExitsTwoWithOneLine) {
  const Background zero = [](int, int) { return 0.0; };
  cut("a.fits", 0, 0, 70, 90, zero);
  cut("sin.fits", 50, 0, 70, 90, zero, {}, cards(50, 0, 90, 0.0, "SIN"));
  cut("half.fits", 50, 0, 70, 90, zero, {}, cards(50, 0, 90, 0.3));
  cut("scale.fits", 50, 0, 70, 90, zero, {}, cards(50, 0, 90, 0.0, "TAN", -0.0100001));
  write_image(path("plain.fits"), Image(8, 8, 1, 0.5f), WriteOptions{});
  cut("apart.fits", 80, 0, 40, 40, zero);
  cut("small.fits", 0, 0, 30, 30, zero);
  cut("outside.fits", 200, 0, 30, 30, zero);
  const std::string rest = " --header " + path("t.hdr") + " -o " + path("out.fits");
  const auto with_a = [&](const std::string& other) { return "sky --projected " + path("a.fits") + " " + path(other) + rest; };
  expect_failure(with_a("sin.fits"), "sin.fits: projection SIN, but the template's is TAN");
  expect_failure(with_a("half.fits"), "half.fits: lies");
  expect_failure(with_a("scale.fits"), "scale.fits: not on the template's grid");
  expect_failure(with_a("plain.fits"), "plain.fits: no celestial WCS");
  expect_failure("sky --projected " + path("small.fits") + " " + path("apart.fits") + rest,
                 "small.fits: overlaps no other image");
  expect_failure(with_a("outside.fits"), "outside.fits");
  expect_failure("sky --projected " + path("a.fits") + " -o " + path("out.fits"), "--header");
  expect_failure(with_a("missing.fits"), "missing.fits: no such file");
}

}  // namespace
}  // namespace gdp
