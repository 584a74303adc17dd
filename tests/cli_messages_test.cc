// Every failure message names its file: mismatched inputs, non-spherical images, full scratch disks, --stats files.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

class CliMessages : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    write_image(path("comp.png"), test::random_image(40, 30, 3, 5), {});
    write_image(path("labels.png"), Image(40, 30, 1, 0.5f), {});
  }
  std::string stitch(const std::string& labels, const std::string& extra = "") const {
    return "stitch -c " + path("comp.png") + " -l " + path(labels) + " -o " + path("out.png") + " " + extra;
  }
};

TEST_F(CliMessages, LabelMapOfAnotherSizeIsNamed) {
  write_image(path("small.png"), Image(10, 10, 1), {});
  expect_failure(stitch("small.png"), "small.png");
}

TEST_F(CliMessages, NonSphericalImageIsNamed) {
  expect_failure("sphere to-pq " + path("comp.png") + " -o " + path("pq.png"), path("comp.png") + ": ");
}

// An all-white label map gives no pixel a source: an error (it used to write a flat gray image),
// unless white is taken for a label.
TEST_F(CliMessages, AllUnknownLabelMapIsAnError) {
  write_image(path("white.png"), Image(40, 30, 1, 1.0f), {});
  expect_failure(stitch("white.png"), "white.png");
  expect_failure(stitch("white.png", "--in-core"), "white.png");
  EXPECT_EQ(gdp(stitch("white.png", "--unknown label -q")).code, 0);
}

// A scratch disk that fills up (a file-size limit here) is named, so that --temp can move it.
TEST_F(CliMessages, FullScratchDiskIsNamed) {
  // With --memory 0 every scratch store is a file, written (1 MiB at a time) before the first output row.
  write_image(path("big.png"), test::random_image(1200, 700, 3, 5), {});
  const std::string scratch = path("scratch");
  fs::create_directory(scratch);
  const test::CliRun r = gdp_shell("ulimit -f 8; exec " + std::string(GDP_CLI_PATH) + " sharpen " + path("big.png") +
                                   " -o " + path("out.png") + " --memory 0 --temp " + scratch);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("scratch"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(scratch), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--temp"), std::string::npos) << "how to put it elsewhere: " << r.err;
  EXPECT_FALSE(fs::exists(path("out.png")));
}

// A --stats file that cannot be written is found before the run, not after the output exists.
TEST_F(CliMessages, StatsIntoAMissingDirectoryFailsUpFront) {
  expect_failure(stitch("labels.png", "--stats " + path("nowhere/s.json")), "nowhere");
}

TEST_F(CliMessages, StatsOnAFullDiskIsAnError) {
  const test::CliRun r = gdp(stitch("labels.png", "--stats /dev/full -q"));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("/dev/full"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace gdp
