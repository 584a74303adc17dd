// The gdp command line tool: successful runs and every error path (message, exit code 2, no output).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

using test::CliRun;

// Runs in a scratch directory holding a 40x30 composite and its two-label map.
class Cli : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    write_stitch_inputs("comp.png", "labels.png", 40, 30, 5, [](int x, int) { return x < 20 ? 0.0f : 0.5f; }, 3);
  }
};

TEST_F(Cli, StitchWritesOutputAndStatistics) {
  const CliRun r = gdp("stitch -c " + path("comp.png") + " -l " + path("labels.png") + " -o " + path("out.png") +
                    " --stats " + path("s.json") + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  const ReadResult out = read_image(path("out.png"));
  EXPECT_EQ(out.image.width, 40);
  EXPECT_EQ(out.info.sample_type, SampleType::UInt8);
  std::ifstream f(path("s.json"));
  const std::string json(std::istreambuf_iterator<char>(f), {});
  for (const char* key : {"\"relative_residuals\"", "\"peak_rss_mb\"", "\"seconds\"", "\"levels\"",
                          "\"peak_memory_mb\"", "\"scratch_memory_mb\"", "\"scratch_disk_mb\"",
                          "\"minor_faults_per_mpix\""})
    EXPECT_NE(json.find(key), std::string::npos) << key;
}

TEST_F(Cli, VerbosePrintsResidualPerLevel) {
  const CliRun r = gdp("reconstruct " + path("comp.png") + " -v --coarsest 8");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("per level"), std::string::npos) << r.err;
}

// Residual norms are measured when asked for (--residuals, --verbose): else the note has none and
// --stats says null; the image is the same bytes either way.
TEST_F(Cli, ResidualsOnlyWhenAskedFor) {
  const auto slurp = [&](const std::string& name) {
    std::ifstream f(path(name), std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  const std::string stitch = "stitch -c " + path("comp.png") + " -l " + path("labels.png") + " --coarsest 8 --vcycles 2";
  const CliRun plain = gdp(stitch + " -o " + path("a.tif") + " --stats " + path("a.json"));
  const CliRun asked = gdp(stitch + " -o " + path("b.tif") + " --stats " + path("b.json") + " --residuals");
  const CliRun verbose = gdp(stitch + " -o " + path("c.tif") + " --stats " + path("c.json") + " -v");
  for (const CliRun* r : {&plain, &asked, &verbose}) ASSERT_EQ(r->code, 0) << r->err;
  EXPECT_EQ(plain.err.find("relative residual"), std::string::npos) << plain.err;
  EXPECT_NE(slurp("a.json").find("\"relative_residuals\": null"), std::string::npos) << slurp("a.json");
  for (const char* name : {"b", "c"}) {
    const std::string json = slurp(std::string(name) + ".json");
    const std::size_t at = json.find("\"relative_residuals\": [");
    ASSERT_NE(at, std::string::npos) << json;
    const std::string list = json.substr(at, json.find(']', at) - at);
    EXPECT_EQ(std::count(list.begin(), list.end(), ','), 2) << list;  // before, and after each of 2 V-cycles
  }
  EXPECT_NE(asked.err.find("relative residual"), std::string::npos) << asked.err;
  EXPECT_EQ(slurp("a.tif"), slurp("b.tif"));
  EXPECT_EQ(slurp("a.tif"), slurp("c.tif"));
  EXPECT_FALSE(slurp("a.tif").empty());
}

TEST_F(Cli, MissingInputFile) {
  expect_failure("stitch -c " + path("nope.png") + " -l " + path("labels.png") + " -o " + path("out.png"), "nope.png");
}

TEST_F(Cli, UnreadableInputFile) {
  std::ofstream(path("text.png")) << "this is not an image\n";
  expect_failure("sharpen " + path("text.png") + " -o " + path("out.png"), "text.png");
  fs::remove(path("text.png"));
}

TEST_F(Cli, CompositeAndLabelSizesDiffer) {
  write_image(path("small.png"), Image(10, 10, 3), {});
  expect_failure("stitch -c " + path("comp.png") + " -l " + path("small.png") + " -o " + path("out.png"), "label map");
  fs::remove(path("small.png"));
}

TEST_F(Cli, UnsupportedChannelCount) {
  write_image(path("five.tif"), Image(8, 8, 5), {});
  expect_failure("smooth " + path("five.tif") + " -o " + path("out.tif"), "five.tif");
  fs::remove(path("five.tif"));
}

TEST_F(Cli, UnknownOption) {
  expect_failure("stitch -c " + path("comp.png") + " -l " + path("labels.png") + " -o " + path("out.png") +
                     " --frobnicate",
                 "frobnicate");
  expect_failure("stitch -c " + path("comp.png") + " -o " + path("out.png"), "--labels");
}

TEST_F(Cli, InvalidOptionValue) {
  expect_failure("sharpen " + path("comp.png") + " -o " + path("out.png") + " --beta 0.5", "beta");
  expect_failure("reconstruct " + path("comp.png") + " --vcycles 0", "vcycles");
  expect_failure("reconstruct " + path("comp.png") + " --memory 4X", "--memory");
}

TEST_F(Cli, UnwritableOutput) {
  expect_failure("convert " + path("comp.png") + " -o " + path("no/such/dir/out.png"), "out.png");
}

TEST_F(Cli, LossyLabelMapWarns) {
  write_image(path("labels.jpg"), read_image(path("labels.png")).image, {});
  const CliRun r = gdp("stitch -c " + path("comp.png") + " -l " + path("labels.jpg") + " -o " + path("out.png"));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("lossy"), std::string::npos) << r.err;
}

TEST_F(Cli, ReconstructReportsSmallError) {
  const std::string out = path("rec.txt");
  const int status = std::system((std::string(GDP_CLI_PATH) + " reconstruct " + path("comp.png") + " > " + out).c_str());
  ASSERT_EQ(WEXITSTATUS(status), 0);
  std::ifstream f(out);
  const std::string text(std::istreambuf_iterator<char>(f), {});
  const auto at = text.find("rms error ");
  ASSERT_NE(at, std::string::npos) << text;
  EXPECT_LT(std::stod(text.substr(at + 10)), 1e-3) << text;
  fs::remove(out);
}

}  // namespace
}  // namespace gdp

namespace gdp {
namespace {

TEST_F(Cli, StreamingAndInCoreWriteTheSameFile) {
  const std::string args = "stitch -c " + path("comp.png") + " -l " + path("labels.png") + " -q --depth float";
  ASSERT_EQ(gdp(args + " -o " + path("s.tif") + " --temp " + dir_.string() + " --coarsest 4").code, 0);
  ASSERT_EQ(gdp(args + " -o " + path("i.tif") + " --in-core --coarsest 4").code, 0);
  ASSERT_EQ(gdp(args + " -o " + path("m.tif") + " --memory files --coarsest 4").code, 0);  // scratch in files
  ASSERT_EQ(gdp(args + " -o " + path("t.tif") + " --tiled --vcycles 2 --half-scratch").code, 0);
  EXPECT_EQ(read_image(path("s.tif")).image.data, read_image(path("i.tif")).image.data);
  EXPECT_EQ(read_image(path("m.tif")).image.data, read_image(path("i.tif")).image.data);
  EXPECT_LT(test::max_difference(read_image(path("t.tif")).image, read_image(path("i.tif")).image), 2e-3);
  EXPECT_EQ(files(), (std::set<std::string>{"comp.png", "labels.png", "s.tif", "i.tif", "t.tif", "m.tif"}));
}

TEST_F(Cli, MissingScratchDirectory) {
  expect_failure("stitch -c " + path("comp.png") + " -l " + path("labels.png") + " -o " + path("out.png") +
                     " --temp " + path("nowhere"),
                 "nowhere");
}

}  // namespace
}  // namespace gdp

namespace gdp {
namespace {

TEST_F(Cli, InterruptedStitchLeavesNothing) {
  // Many V-cycles keep it running (with its scratch files and temporary output) when stopped.
  // SIGTERM, as SIGINT is ignored by background jobs of a non-interactive shell.
  write_image(path("big.tif"), test::random_image(800, 800, 3, 2), {});
  write_image(path("big_labels.tif"), Image(800, 800, 1, 0.25f), {});
  const std::set<std::string> before = files();
  const std::string cmd = std::string(GDP_CLI_PATH) + " stitch -c " + path("big.tif") + " -l " + path("big_labels.tif") +
                          " -o " + path("out.tif") + " --vcycles 200 --temp " + dir_.string() + " -q & pid=$!; sleep 1.5; kill -TERM $pid; wait $pid";
  const int status = std::system(("bash -c '" + cmd + "'").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM) << "the run should have been stopped, not finished";
  EXPECT_EQ(files(), before) << "no output, temporary or scratch file may remain";
}

}  // namespace
}  // namespace gdp

namespace gdp {
namespace {

TEST_F(Cli, SphereStitchesEquirectangularAndPqInputs) {
  // 64x32 equirectangular: resampled to PQ and back, output of the input's size.
  const Image equi = test::random_image(64, 32, 3, 8);
  Image labels(64, 32, 1);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) labels.at(0, x, y) = (x + y) % 16 < 8 ? 0.0f : 0.5f;
  write_image(path("equi.tif"), equi, {});
  write_image(path("equi_labels.png"), labels, {});
  CliRun r = gdp("stitch --sphere -c " + path("equi.tif") + " -l " + path("equi_labels.png") + " -o " + path("out.tif") + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_image(path("out.tif")).image.width, 64);
  // A PQ image (4H x H) is solved in place; --domain spherical is the same thing.
  write_image(path("pq.tif"), test::random_image(64, 16, 1, 2), {});
  r = gdp("sharpen --sphere " + path("pq.tif") + " -o " + path("pq_out.tif") + " --depth float -q");
  ASSERT_EQ(r.code, 0) << r.err;
  r = gdp("sharpen --domain spherical " + path("pq.tif") + " -o " + path("pq_out2.tif") + " --depth float -q");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_image(path("pq_out.tif")).image.data, read_image(path("pq_out2.tif")).image.data);
}

TEST_F(Cli, SphereRejectsImagesThatAreNotSpherical) {
  expect_failure("sharpen --sphere " + path("comp.png") + " -o " + path("out.png"), "comp.png");
  expect_failure("sharpen --sphere --domain cylindrical " + path("comp.png") + " -o " + path("out.png"), "--sphere");
}

}  // namespace
}  // namespace gdp

namespace gdp {
namespace {

TEST_F(Cli, SharpenWithALowImage) {
  ASSERT_EQ(gdp("sharpen " + path("comp.png") + " --low " + path("comp.png") + " -o " + path("hl.png") + " -q").code, 0);
  write_image(path("small.png"), Image(10, 10, 3), {});
  expect_failure("smooth " + path("comp.png") + " --beta 0.5 --low " + path("small.png") + " -o " + path("out.png"),
                 "small.png");
}

}  // namespace
}  // namespace gdp

namespace gdp {
namespace {

TEST_F(Cli, TonemapOnTheSphereKeepsThePoleWhole) {
  // A real equirectangular HDR map through PQ and back: the top row circles the zenith within
  // 0.35 degrees, where this map's sky is uniform (its linear values vary by 1-5%), so it
  // must come out uniform, not split by the map's seams. (The nadir row has real ground detail.)
  const std::string in = GDP_TEST_DATA "/polyhaven/sunset.exr";
  const CliRun r = gdp("tonemap --sphere " + in + " -o " + path("tm.png") + " -q");
  ASSERT_EQ(r.code, 0) << r.err;
  const Image out = read_image(path("tm.png")).image;
  ASSERT_EQ(out.width, 512);
  for (int c = 0; c < out.channels; ++c) {
    const auto row = out.row(c, 0);
    const auto [lo, hi] = std::minmax_element(row.begin(), row.end());
    EXPECT_LT(*hi - *lo, 0.02f) << "channel " << c;
  }
}

}  // namespace
}  // namespace gdp
