// Option values the gdp tool must refuse (one line naming the option, exit 2, no output) or honour as given.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace gdp {
namespace {

class CliOptions : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    write_image(path("in.png"), test::random_image(24, 16, 3, 4), {});
  }
  std::string sharpen(const std::string& extra, const std::string& out = "out.png") const {
    return "sharpen " + path("in.png") + " -o " + path(out) + " " + extra;
  }
};

// Infinite or absurd weights gave an all-NaN (or black) image with "residual 0".
TEST_F(CliOptions, NonFiniteOrAbsurdWeightsAreRefused) {
  expect_failure(sharpen("--alpha inf"), "--alpha");
  expect_failure(sharpen("--alpha nan"), "--alpha");
  expect_failure(sharpen("--alpha 1e300"), "--alpha");
  expect_failure(sharpen("--beta inf"), "--beta");
  expect_failure(sharpen("--beta 1e300"), "--beta");
  expect_failure(sharpen("--scale 1e-30"), "--scale");
  expect_failure(sharpen("--scale inf"), "--scale");
  expect_failure("smooth " + path("in.png") + " -o " + path("out.png") + " --beta -inf", "--beta");
}

// A value given is a value: 0 is not "not given".
TEST_F(CliOptions, ZeroIsAValueNotAnAbsentOption) {
  expect_failure(sharpen("--bands 0"), "--bands");
  expect_failure(sharpen("--alpha 0"), "--alpha");
}

TEST_F(CliOptions, NegativeSizesAreRefused) {
  expect_failure(sharpen("--incore-bytes -1"), "--incore-bytes");
}

TEST_F(CliOptions, UnknownCompressionIsRefused) {
  expect_failure(sharpen("--compression bogus", "out.tif"), "bogus");
  expect_failure(sharpen("--compression zip", "out.png"), "--compression");
  const test::CliRun r = gdp(sharpen("--compression lzw", "out.tif"));
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST_F(CliOptions, ConvertRefusesUnknownCompression) {  // convert writes without open_output: the writer checks
  expect_failure("convert " + path("in.png") + " -o " + path("out.tif") + " --compression bogus", "bogus");
  expect_failure("convert " + path("in.png") + " -o " + path("out.exr") + " --compression zstd", "zstd");
}

TEST_F(CliOptions, UnknownExrCompressionIsRefused) {  // the EXR encoder used to fall back to piz silently
  expect_failure(sharpen("--compression bogus", "out.exr"), "bogus");
  const test::CliRun r = gdp(sharpen("--compression dwaa:45", "out.exr"));
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST_F(CliOptions, UnknownSubcommandIsNamed) {
  const test::CliRun r = gdp("stich -c a.png");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("stich"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("stitch"), std::string::npos) << "the commands there are: " << r.err;
}

}  // namespace
}  // namespace gdp
