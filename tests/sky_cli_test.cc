// gdp sky on the command line: the output's header carries the target WCS; bad input exits 2 with one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <string>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "gdp/sphere.h"
#include "io/fits_image.h"
#include "sky/header.h"
#include "sky/plate.h"
#include "sky_test_util.h"
#include "test_util.h"

namespace gdp {
namespace {

class SkyCli : public test::CliFixture {
 protected:
  // A 24 x 24 TAN plate of 0.5 degree pixels at (lon, lat), values 1 + x / 24.
  void plate(const std::string& name, double lon, double lat) {
    Image image(24, 24, 1);
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x) image.at(0, x, y) = 1.0f + x / 24.0f;
    WriteOptions options;
    options.fits_header = sky::target_header({{}, lon, lat, 24, 24, 0.5, "TAN"});
    write_image(path(name), image, options);
  }
  // Three such plates overlapping around (125, -27), and gdp sky's arguments for them on a 50 x 40
  // target of 0.5 degree pixels, 4 V-cycles.
  std::string three_plates() {
    plate("a.fits", 120.0, -30.0);
    plate("b.fits", 129.0, -30.0);
    plate("c.fits", 124.0, -22.0);
    return "sky " + path("a.fits") + " " + path("b.fits") + " " + path("c.fits") +
           " --center 125,-27 --size 50,40 --scale 0.5 --vcycles 4 --quiet";
  }
  // The number after "key": in a --stats file, -1 where it has none.
  double stat(const std::string& file, const std::string& key) {
    std::ifstream in(path(file));
    const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t at = json.find("\"" + key + "\": ");
    return at == std::string::npos ? -1.0 : std::stod(json.substr(at + key.size() + 4));
  }
};

TEST_F(SkyCli, WritesTheTargetWcsIntoTheFitsHeader) {
  plate("a.fits", 120.0, -30.0);
  std::ofstream(path("t.hdr")) << "SIMPLE = T\nNAXIS = 2\nNAXIS1 = 30\nNAXIS2 = 20\nCTYPE1 = 'RA---CAR'\n"
                                  "CTYPE2 = 'DEC--CAR'\nCRVAL1 = 120.0\nCRVAL2 = -30.0\nCRPIX1 = 15.5\n"
                                  "CRPIX2 = 10.5\nCDELT1 = -0.5\nCDELT2 = 0.5\nEND\n";
  const test::CliRun r = gdp("sky " + path("a.fits") + " --header " + path("t.hdr") + " -o " + path("out.fits") +
                             " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  io::FitsImage out(path("out.fits"));
  EXPECT_EQ(out.width(), 30);
  EXPECT_EQ(out.height(), 20);
  test::expect_template_wcs(path("out.fits"), path("t.hdr"));
}

TEST_F(SkyCli, ToastTilesShowThePlateWhereItIsAndNothingElsewhere) {
  plate("a.fits", 120.0, -30.0);
  const test::CliRun r = gdp("sky " + path("a.fits") + " --center 120,-30 --size 20,20 --scale 0.5 -o " +
                             path("out.fits") + " --toast " + path("toast") + " --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  // 0.5 degree plates: PQ height 208, rounded up to 256, so level 1 (a 512 x 512 square).
  const int n = 512;
  const auto alpha_at = [&](double lon, double lat) {
    const sphere::Point2 st = sphere::square_from_sphere(sphere::SquareMap::Toast, sky::direction(lon, lat));
    const int u = static_cast<int>((st.x + 1.0) / 2.0 * n), v = static_cast<int>((1.0 - st.y) / 2.0 * n);
    const Image tile =
        read_image(path(fmt::format("toast/1/{}/{}_{}.png", v / 256, v / 256, u / 256))).image;
    EXPECT_EQ(tile.channels, 2);
    return tile.at(1, u % 256, v % 256);
  };
  EXPECT_EQ(alpha_at(120.0, -30.0), 1.0f) << "the plate's centre";
  EXPECT_EQ(alpha_at(121.0, -29.0), 1.0f);
  EXPECT_EQ(alpha_at(300.0, 30.0), 0.0f) << "the antipode";
  EXPECT_EQ(alpha_at(120.0, 10.0), 0.0f) << "40 degrees north of the plate";
  EXPECT_TRUE(std::filesystem::exists(path("toast/toast.wtml")));
}

// The same pixels within `tolerance`, blank (NaN) at the same places; the count of finite ones.
long long expect_same_sky(const Image& a, const Image& b, double tolerance, const std::string& what) {
  EXPECT_EQ(a.data.size(), b.data.size()) << what;
  long long finite = 0;
  double worst = 0.0;
  for (std::size_t k = 0; k < a.data.size() && k < b.data.size(); ++k) {
    EXPECT_EQ(std::isnan(a.data[k]), std::isnan(b.data[k])) << what << " at " << k;
    if (std::isnan(a.data[k]) || std::isnan(b.data[k])) continue;
    worst = std::max(worst, std::abs(double(a.data[k]) - b.data[k]));
    ++finite;
  }
  EXPECT_LT(worst, tolerance) << what;
  std::printf("%s: worst difference %.2e over %lld pixels\n", what.c_str(), worst, finite);
  return finite;
}

// --bands 2 and mpirun -np 2 (every rank builds the mosaic rows and solves its columns, rank 0
// gathers the PQ rows and writes the output) give the one-band result within 1e-4 (the values
// span 1..2), on the plates' PQ window (planar) and on the whole PQ sphere (--toast: its folds).
TEST_F(SkyCli, BandsAndMpirunGiveTheOneBandResult) {
  const std::string run = three_plates();
  const auto solve = [&](const std::string& prefix, const std::string& name, const std::string& more) {
    const std::string cmd = prefix + GDP_CLI_PATH + " " + run + " -o " + path(name) + more;
    const test::CliRun r = run_capturing_stderr(cmd);
    EXPECT_EQ(r.code, 0) << cmd << "\n" << r.err;
    return read_image(path(name)).image;
  };
  const bool mpi = test::mpirun_works();
  const std::string mpirun = test::kMpirun + " -np 2 ";
  for (const bool sphere : {false, true}) {
    // The whole sphere at the smallest TOAST height (1 s a run; mpirun runs several V-cycles of 2 ranks).
    const std::string toast = sphere ? " --toast " + path("toast") + " --pq-height 128" : "";
    const std::string kind = sphere ? "sphere" : "window";
    const auto fresh = [&](const std::string& name) {
      std::filesystem::remove_all(path("toast"));
      return name + "-" + kind + ".fits";
    };
    const Image one = solve("", fresh("one"), toast);
    EXPECT_GT(expect_same_sky(one, solve("", fresh("bands"), toast + " --bands 2"), 1e-4, kind + ": --bands 2"), 1000);
    if (mpi) expect_same_sky(one, solve(mpirun, fresh("mpi"), toast + " --stats " + path("mpi.json")), 1e-4,
                             kind + ": mpirun -np 2");
    if (mpi && !sphere) {  // on a window each rank builds the mosaic over its columns and a halo only
      std::ifstream in(path("mpi.json"));
      const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      const auto number = [&](const std::string& key) {
        const std::size_t at = json.find("\"" + key + "\": ");
        return at == std::string::npos ? -1.0 : std::stod(json.substr(at + key.size() + 4));
      };
      const std::size_t w = json.find("\"pq_window\": \"");
      ASSERT_NE(w, std::string::npos) << json;
      int cols = 0, rows = 0;
      ASSERT_EQ(std::sscanf(json.c_str() + w + 14, "%dx%d", &cols, &rows), 2) << json;
      EXPECT_GT(number("mosaic_pixels_computed"), 0.0) << json;
      EXPECT_LT(number("mosaic_pixels_computed"), 0.75 * cols * rows) << "rank 0 built whole mosaic rows";
    }
    if (mpi) expect_same_sky(one, solve(mpirun, fresh("mpi-bands"), toast + " --bands 2"), 1e-4, kind + ": mpirun x bands 2");
  }
  if (!mpi) GTEST_SKIP() << "mpirun cannot start 2 processes: --bands 2 checked only";
}

// --seams graphcut (rank 0 cuts, the others take its labels): --bands 2 and mpirun -np 2 give the
// one-band result within 1e-4, on the plates' PQ window and on the whole sphere (rows wrap); the
// cut costs no more than the distance seams (--stats).
TEST_F(SkyCli, GraphcutSeamsUnderBandsAndMpirunGiveTheOneBandResult) {
  const std::string run = three_plates() + " --seams graphcut";
  const bool mpi = test::mpirun_works();
  for (const bool sphere : {false, true}) {
    const std::string kind = sphere ? "sphere" : "window";
    const auto solve = [&](const std::string& prefix, const std::string& name, const std::string& more) {
      std::filesystem::remove_all(path("toast"));
      const std::string toast = sphere ? " --toast " + path("toast") + " --pq-height 128" : "";
      const std::string cmd = prefix + GDP_CLI_PATH + " " + run + toast + " -o " + path(name + kind + ".fits") + more;
      const test::CliRun r = run_capturing_stderr(cmd);
      EXPECT_EQ(r.code, 0) << cmd << "\n" << r.err;
      return read_image(path(name + kind + ".fits")).image;
    };
    const Image one = solve("", "one", " --stats " + path("gc.json"));
    EXPECT_GT(stat("gc.json", "seam_cost_depth"), 0.0);
    EXPECT_LE(stat("gc.json", "seam_cost"), stat("gc.json", "seam_cost_depth"));
    EXPECT_GE(stat("gc.json", "seam_cost"), 0.0);
    EXPECT_GT(expect_same_sky(one, solve("", "bands", " --bands 2"), 1e-4, kind + ": graphcut, --bands 2"), 1000);
    if (mpi) expect_same_sky(one, solve(test::kMpirun + " -np 2 ", "mpi", ""), 1e-4, kind + ": graphcut, mpirun -np 2");
  }
  if (!mpi) GTEST_SKIP() << "mpirun cannot start 2 processes: --bands 2 checked only";
}

// Under mpirun -np 2 each rank reads only the plates near its share of the PQ columns (its own,
// their neighbours, and in the solve those reaching its columns): each reads fewer plate pixels
// than one process, and the output is the one process's within 1e-4 (the passes before the solve
// give every rank the one process's bits: SkySweep.RanksSharingThePasses...; the solve under
// mpirun differs by its rounding).
TEST_F(SkyCli, UnderMpirunEachRankReadsOnlyThePlatesNearItsColumns) {
  if (!test::mpirun_works()) GTEST_SKIP() << "mpirun cannot start 2 processes";
  std::string plates;
  for (int k = 0; k < 7; ++k) {  // along the parallel Dec 30 (across the PQ columns there), 10 degrees apart
    const std::string name = fmt::format("p{}.fits", k);
    plate(name, 90.0 + (k - 3) * 10.0 / std::cos(M_PI / 6), 30.0);
    plates += fmt::format(" {}", path(name));
  }
  const auto solve = [&](const std::string& prefix, const std::string& name) {
    const std::string cmd = prefix + GDP_CLI_PATH + " sky" + plates + " --center 90,30 --size 150,30 --scale 0.5 " +
                            "--vcycles 4 --quiet -o " + path(name + ".fits") + " --stats " + path(name + ".json");
    const test::CliRun r = run_capturing_stderr(cmd);
    EXPECT_EQ(r.code, 0) << cmd << "\n" << r.err;
    std::ifstream in(path(name + ".json"));
    const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t at = json.find("\"plate_pixels_read\": [");
    EXPECT_NE(at, std::string::npos) << json;
    std::vector<long long> read;
    for (std::size_t p = at + 22; at != std::string::npos && json[p - 1] != ']'; p = json.find_first_of(",]", p) + 1)
      read.push_back(std::stoll(json.substr(p)));
    return std::pair(read_image(path(name + ".fits")).image, read);
  };
  const auto [one, one_read] = solve("", "one");
  const auto [two, two_read] = solve(test::kMpirun + " -np 2 ", "two");
  EXPECT_GT(expect_same_sky(one, two, 1e-4, "mpirun -np 2"), 1000);
  ASSERT_EQ(one_read.size(), 1u);
  ASSERT_EQ(two_read.size(), 2u);
  std::printf("plate pixels read: one process %lld, ranks %lld and %lld\n", one_read[0], two_read[0], two_read[1]);
  for (const long long r : two_read) {
    EXPECT_GT(r, 0);
    EXPECT_LT(r, 0.9 * one_read[0]) << "a rank read (nearly) every plate";
  }
  // A blank plate that only one rank reads fails every rank with its message: exit 2, no output.
  Image blank(24, 24, 1);
  std::fill(blank.data.begin(), blank.data.end(), std::nanf(""));
  WriteOptions options;
  options.fits_header = sky::target_header({{}, 90.0 + 3 * 10.0 / std::cos(M_PI / 6), 30.0, 24, 24, 0.5, "TAN"});
  write_image(path("p6.fits"), blank, options);
  const test::CliRun r = run_capturing_stderr(test::kMpirun + " -np 2 " + GDP_CLI_PATH + " sky" + plates +
                                              " --center 90,30 --size 150,30 --scale 0.5 --quiet -o " + path("bad.fits"));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("p6.fits: every pixel is blank"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(path("bad.fits")));
}

TEST_F(SkyCli, TheBackgroundFitIsOneNoteAndEachPlateWithVerboseAndInStats) {
  plate("a.fits", 120.0, -30.0);
  plate("b.fits", 128.0, -30.0);
  plate("c.fits", 124.0, -23.0);
  const std::string plates = path("a.fits") + " " + path("b.fits") + " " + path("c.fits");
  const auto count = [](const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  const std::string args = " --center 124,-27 --size 40,30 --scale 0.5 -o " + path("out.fits");
  const test::CliRun plain = gdp("sky " + plates + args);
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_EQ(count(plain.err, "smooth backgrounds (plane + radial) fitted to the overlaps and taken off 3 plate(s)"), 1u)
      << plain.err;
  EXPECT_EQ(count(plain.err, "background fitted:"), 0u) << plain.err;
  const test::CliRun verbose = gdp("sky " + plates + args + " --verbose --stats " + path("s.json"));
  ASSERT_EQ(verbose.code, 0) << verbose.err;
  EXPECT_EQ(count(verbose.err, "background fitted:"), 3u) << verbose.err;
  std::ifstream in(path("s.json"));
  const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(count(json, "\"plate_backgrounds\": ["), 1u) << json;
  EXPECT_EQ(count(json, "\"smooth_rms\": "), 3u) << json;
  EXPECT_EQ(count(json, "\"plate\": \"" + path("b.fits") + "\""), 1u) << json;
}

TEST_F(SkyCli, BadInputExitsTwoWithOneLine) {
  plate("a.fits", 120.0, -30.0);
  write_image(path("plain.fits"), Image(8, 8, 1, 0.5f), WriteOptions{});
  const std::string target = " --center 120,-30 --size 20,20 --scale 0.5 -o " + path("out.fits");
  expect_failure("sky " + path("plain.fits") + target, "plain.fits: no celestial WCS");
  expect_failure("sky " + path("missing.fits") + target, "missing.fits");
  expect_failure("sky " + path("a.fits") + " --center 300,40 --size 20,20 --scale 0.5 -o " + path("out.fits"),
                 "no plate reaches the target");
  expect_failure("sky " + path("a.fits") + " --center 120 --size 20,20 --scale 0.5 -o " + path("out.fits"),
                 "--center takes two numbers");
  expect_failure("sky " + path("a.fits") + " -o " + path("out.fits"), "--header");
  expect_failure("sky " + path("a.fits") + target + " --plane 2", "a.fits: --plane 2 but the image has 1 plane");
  expect_failure("sky " + path("a.fits") + target + " --seams bogus", "--seams");
  expect_failure("sky " + path("a.fits") + target + " --seams graph", "--seams: graph not in {stars,deepest,graphcut}");
  expect_failure("sky " + path("a.fits") + " --seams deepest --seams-from " + path("a.fits") + target,
                 "--seams-from needs --seams stars");
  expect_failure("sky " + path("a.fits") + " --seams-from " + path("a.fits") + " " + path("a.fits") + target,
                 "--seams-from takes one plate per plate: 2 for 1");
}

}  // namespace
}  // namespace gdp
