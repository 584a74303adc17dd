// gdp blend on the command line: enblend's options as Hugin passes them, gdp-blend, bad input.
#include <gtest/gtest.h>
#include <tiffio.h>

#include <cmath>
#include <fstream>
#include <iterator>

#include "blend_args.h"
#include "cli_fixture.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "nona_tiff.h"
#include "stats_file.h"
#include "test_util.h"

namespace gdp {
namespace {

TEST(BlendArgs, EnblendOptionsAsHuginPassesThem) {
  std::vector<std::string> ignored;
  const auto out = cli::from_enblend({"--compression=LZW", "-w", "-f11618x5809", "-o", "pano.tif", "--", "a.tif"},
                                     ignored);
  const std::vector<std::string> want = {"--compression=lzw", "--wrap=horizontal", "--canvas=11618x5809", "-o",
                                         "pano.tif", "--", "a.tif"};
  EXPECT_EQ(out, want);
  EXPECT_TRUE(ignored.empty());
  const auto more = cli::from_enblend({"--compression=90", "-f2795x4607+1002+1232", "-d", "r32", "--wrap=both",
                                       "-opano.jpg", "--depth=16", "-l", "29", "--fine-mask", "--no-optimize",
                                       "--levels=3", "-v"},
                                      ignored);
  const std::vector<std::string> want_more = {"--quality=90",  "--canvas=2795x4607+1002+1232", "--depth=float",
                                              "--wrap=both",   "-o",
                                              "pano.jpg",      "--depth=16",
                                              "--verbose"};
  EXPECT_EQ(more, want_more);
  const std::vector<std::string> want_ignored = {"-l 29", "--fine-mask", "--no-optimize", "--levels=3"};
  EXPECT_EQ(ignored, want_ignored);
  EXPECT_THROW(cli::from_enblend({"-d", "12"}, ignored), UsageError);
}

class BlendCli : public test::CliFixture {
 protected:
  // Two overlapping nona layers of an RGB ramp, the second 0.1 brighter, on a 90x40 canvas.
  void write_layers() {
    Image a(60, 40, 4, 1.0f), b(60, 40, 4, 1.0f);
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 60; ++x)
        for (int c = 0; c < 3; ++c) {
          a.at(c, x, y) = 0.2f + 0.004f * x + 0.001f * y;
          b.at(c, x, y) = 0.2f + 0.004f * (x + 30) + 0.001f * y + 0.1f;
        }
    test::write_nona_tiff(path("l0.tif"), {{&a, 0, 0, 8}}, 90, 40);
    test::write_nona_tiff(path("l1.tif"), {{&b, 30, 0, 8}}, 90, 40);
  }
};

TEST_F(BlendCli, HuginStyleCommandLine) {
  write_layers();
  std::ofstream(path("list.txt")) << "# layers\n" << path("l1.tif") << "\n";
  const auto r = gdp("blend --compression=LZW -w -f90x40 --fine-mask -o " + path("pano.tif") + " -- " +
                     path("l0.tif") + " @" + path("list.txt"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("ignoring enblend-only option(s) --fine-mask"), std::string::npos) << r.err;
  const ReadResult out = read_image(path("pano.tif"));
  EXPECT_EQ(out.image.width, 90);
  EXPECT_EQ(out.image.channels, 4);
  EXPECT_EQ(out.info.sample_type, SampleType::UInt8);
  // No seam: the step between columns stays the ramp's wherever the layers meet.
  for (int x = 40; x < 50; ++x)
    EXPECT_NEAR(out.image.at(0, x + 1, 20) - out.image.at(0, x, 20), 0.004, 2.5 / 255) << x;
}

// Blend's own defaults: a TIFF deflated (level 1: not visible in the file) unless --compression
// says otherwise, and the solver's scratch in files (--memory 0) giving the in-memory run's bits.
TEST_F(BlendCli, DefaultsDeflateTheTiffAndKeepTheInMemoryResult) {
  write_layers();
  const std::string layers = " " + path("l0.tif") + " " + path("l1.tif");
  ASSERT_EQ(gdp("blend -q -o " + path("default.tif") + layers).code, 0);
  ASSERT_EQ(gdp("blend -q --memory 1G --compression=LZW -o " + path("lzw.tif") + layers).code, 0);
  const auto compression = [&](const std::string& name) {
    TIFF* t = TIFFOpen(path(name).c_str(), "r");
    std::uint16_t c = 0;
    if (t) TIFFGetField(t, TIFFTAG_COMPRESSION, &c);
    if (t) TIFFClose(t);
    return c;
  };
  EXPECT_EQ(compression("default.tif"), COMPRESSION_ADOBE_DEFLATE);
  EXPECT_EQ(compression("lzw.tif"), COMPRESSION_LZW);
  EXPECT_EQ(test::max_difference(read_image(path("default.tif")).image, read_image(path("lzw.tif")).image), 0.0);
}

TEST_F(BlendCli, CanvasWithAnOffsetCropsAndGdpBlendIsBlend) {
  write_layers();
  const std::string link = path("gdp-blend");
  std::filesystem::create_symlink(GDP_CLI_PATH, link);
  const std::string cmd = link + " -f40x20+25+10 -d 16 -o " + path("crop.tif") + " " + path("l0.tif") + " " +
                          path("l1.tif") + " 2> " + path("err.txt");
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const ReadResult out = read_image(path("crop.tif"));
  EXPECT_EQ(out.image.width, 40);
  EXPECT_EQ(out.image.height, 20);
  EXPECT_EQ(out.info.sample_type, SampleType::UInt16);
}

// --pin and --weights by layer number, or as images of the canvas's size (as gdp stitch's).
TEST_F(BlendCli, PinAndWeightsByLayerOrImage) {
  write_layers();
  const std::string layers = " " + path("l0.tif") + " " + path("l1.tif");
  ASSERT_EQ(gdp("blend -q --pin 2 --tolerance 1e-6 --depth float -o " + path("pin.tif") + layers).code, 0);
  ASSERT_EQ(gdp("blend -q --weights 1e-6,0 --depth float -o " + path("w.tif") + layers).code, 0);
  const Image pinned = read_image(path("pin.tif")).image, weighted = read_image(path("w.tif")).image;
  const Image l1 = read_image(path("l1.tif")).image;
  // Layer 2 (x >= 45 by depth) keeps its values; with weights 1e-6, 0 all take layer 1's level: its
  // value at x = 10 and layer 2's shifted down by its +0.1 (8-bit: within 1.5/255 of each).
  for (int x = 50; x < 90; x += 7) EXPECT_NEAR(pinned.at(0, x, 20), l1.at(0, x - 30, 20), 1e-5) << x;
  EXPECT_NEAR(weighted.at(0, 70, 20), l1.at(0, 40, 20) - 0.1f, 1.5 / 255) << "levelled to layer 1";
  Image mask(90, 40, 1, 0.0f);
  for (int y = 0; y < 40; ++y)
    for (int x = 60; x < 90; ++x) mask.at(0, x, y) = 1.0f;
  write_image(path("mask.png"), mask, {});
  ASSERT_EQ(gdp("blend -q --pin " + path("mask.png") + " --tolerance 1e-6 --depth float -o " + path("m.tif") + layers).code, 0);
  EXPECT_NEAR(read_image(path("m.tif")).image.at(0, 80, 20), l1.at(0, 50, 20), 1e-5);
  expect_failure("blend --weights 1,2,3 -o " + path("o.tif") + layers, "--weights");
  expect_failure("blend --pin " + path("l0.tif") + " -o " + path("o.tif") + layers, "l0.tif");  // 60x40, not the canvas
}

// mpirun with 2 processes, or "" where it cannot start them.
std::string mpirun_two() {
  const std::string mpirun = "timeout -v -k 30 120 mpirun --oversubscribe --allow-run-as-root";
  if (std::system((mpirun + " -np 2 true > /dev/null 2>&1").c_str()) != 0) return "";
  return mpirun + " -np 2 ";
}

// Under mpirun every rank finds the seams of its own columns only (reading the layers that meet
// them) and solves them; rank 0 writes the file: within 1e-4 of one process. Six layers across a
// 400-wide canvas: rank 0 (the left half, plus margins) reads four of them at most.
TEST_F(BlendCli, UnderMpirunAgreesWithOneProcess) {
  const std::string mpirun = mpirun_two();
  if (mpirun.empty()) GTEST_SKIP() << "mpirun cannot start 2 processes";
  std::string layers;
  for (int k = 0; k < 6; ++k) {
    Image l(90, 50, 4, 1.0f);
    for (int y = 0; y < 50; ++y)
      for (int x = 0; x < 90; ++x)
        for (int c = 0; c < 3; ++c)
          l.at(c, x, y) = 0.3f + 0.2f * std::sin(0.05f * (x + 62 * k) + c) * std::cos(0.07f * y) + 0.03f * k;
    const std::string name = path("m" + std::to_string(k) + ".tif");
    test::write_nona_tiff(name, {{&l, 62 * k, 0, 8}}, 400, 50);
    layers += " " + name;
  }
  const auto one_run = gdp("blend -q --depth float --stats " + path("one.json") + " -o " + path("one.tif") + layers);
  ASSERT_EQ(one_run.code, 0) << one_run.err;
  const std::string cmd = mpirun + GDP_CLI_PATH + " blend -q --bands 1 --depth float --stats " + path("two.json") +
                          " -o " + path("two.tif") + layers + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const Image one = read_image(path("one.tif")).image, two = read_image(path("two.tif")).image;
  EXPECT_LT(test::max_difference(one, two), 1e-4);
  EXPECT_EQ(test::stat_of(path("one.json"), "seam_layers_read"), 6);
  const double rank0 = test::stat_of(path("two.json"), "seam_layers_read");
  EXPECT_GE(rank0, 3);  // the left half's layers, each read whole
  EXPECT_LE(rank0, 4);
}

// Graph-cut seams under mpirun: rank 0 finds the cut (it is global) and shares it, so 2 ranks give
// one process's result within 1e-4. Five layers that disagree (offsets and each its own grain) in
// a row, and three that overlap no other below them: one in each rank's columns and one across
// both. Every rank's columns count for the isolated layers: all three are named, with depth seams
// too (where rank 0 alone used to name only the layer wholly in its columns).
TEST_F(BlendCli, UnderMpirunGraphcutSeamsAndIsolatedLayersAgreeWithOneProcess) {
  const std::string mpirun = mpirun_two();
  if (mpirun.empty()) GTEST_SKIP() << "mpirun cannot start 2 processes";
  std::string layers;
  const auto add = [&](int k, int x0, int y0, int w, int h) {
    Image l(w, h, 4, 1.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          const float grain = 0.04f * std::sin(1.7f * x * (k + 1) + 2.3f * y + c);
          l.at(c, x, y) = 0.4f + 0.2f * std::sin(0.05f * (x + x0) + c) * std::cos(0.07f * (y + y0)) + 0.03f * k + grain;
        }
    const std::string name = path("g" + std::to_string(k) + ".tif");
    test::write_nona_tiff(name, {{&l, x0, y0, 8}}, 400, 90);
    layers += " " + name;
  };
  for (int k = 0; k < 5; ++k) add(k, 76 * k, 0, 96, 50);
  add(5, 20, 60, 60, 30);   // rank 0's columns
  add(6, 170, 60, 60, 30);  // across the middle
  add(7, 300, 60, 60, 30);  // rank 1's columns
  const std::string common = " -q --depth float --tolerance 1e-6 --stats ";
  const auto run_one = gdp("blend" + common + path("one.json") + " --seams graphcut -o " + path("one.tif") + layers);
  ASSERT_EQ(run_one.code, 0) << run_one.err;
  const std::string two = mpirun + GDP_CLI_PATH + " blend --bands 1" + common;
  ASSERT_EQ(std::system((two + path("two.json") + " --seams graphcut -o " + path("two.tif") + layers + " > /dev/null 2>&1").c_str()), 0);
  ASSERT_EQ(std::system((two + path("depth.json") + " -o " + path("depth.tif") + layers + " > /dev/null 2>&1").c_str()), 0);
  EXPECT_LT(test::stat_of(path("one.json"), "seam_cost"), 0.9 * test::stat_of(path("one.json"), "seam_cost_depth"));  // the cut moved
  EXPECT_LT(test::max_difference(read_image(path("one.tif")).image, read_image(path("two.tif")).image), 1e-4);
  EXPECT_EQ(test::stat_of(path("one.json"), "isolated_layers"), 3);
  EXPECT_EQ(test::stat_of(path("two.json"), "isolated_layers"), 3);
  EXPECT_EQ(test::stat_of(path("depth.json"), "isolated_layers"), 3);
}

TEST_F(BlendCli, BadInputIsOneLineNamingTheFile) {
  write_layers();
  expect_failure("blend -o " + path("o.tif"), "no layers");
  Image grey(20, 20, 1, 0.5f), five(20, 20, 5, 0.5f);
  write_image(path("grey.png"), grey, {});
  write_image(path("five.tif"), five, {});
  expect_failure("blend -o " + path("o.tif") + " " + path("l0.tif") + " " + path("five.tif"), "five.tif");
  expect_failure("blend -f10x10+500+500 -o " + path("o.tif") + " " + path("l0.tif"), "wholly outside");
  Image small(10, 10, 1, 1.0f);
  write_image(path("small.png"), small, {});
  expect_failure("blend -o " + path("o.tif") + " " + path("grey.png") + ":" + path("small.png"), "small.png");
  expect_failure("blend -o " + path("o.tif") + " @" + path("missing.txt"), "missing.txt");
  expect_failure("blend --anchor 3 -o " + path("o.tif") + " " + path("l0.tif") + " " + path("l1.tif"), "--anchor 3");
  // A layer whose pixels are cut short (its header is whole): found mid-run.
  write_image(path("big.png"), test::random_image(200, 200, 1), {});
  std::filesystem::copy_file(path("big.png"), path("cut.png"));
  std::filesystem::resize_file(path("cut.png"), std::filesystem::file_size(path("cut.png")) / 2);
  expect_failure("blend -o " + path("o.tif") + " " + path("big.png") + " " + path("cut.png"), "cut.png");
}

// The canvas is read from no file header: its size is checked as an image's would be, before any output.
TEST_F(BlendCli, ACanvasTooLargeIsRefusedUpFront) {
  write_layers();
  const std::string huge = "blend -f 2000000000x2000000000 -o " + path("o.tif") + " " + path("l0.tif");
  expect_failure(huge + " --max-pixels 100000000", "canvas of 1 layer(s): 2000000000x2000000000");
  EXPECT_NE(gdp(huge + " --max-pixels 100000000").err.find("--max-pixels"), std::string::npos);
  if (!std::filesystem::is_directory("/dev/shm")) GTEST_SKIP() << "no /dev/shm";
  expect_failure(huge + " --temp /dev/shm", "canvas of 1 layer(s)");  // scratch space (or memory) it lacks
}

}  // namespace
}  // namespace gdp
