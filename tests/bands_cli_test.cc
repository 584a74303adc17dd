// The tool's --bands flag: a band solve end to end, and the options it refuses.
#include <gtest/gtest.h>

#include <fstream>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace gdp {
namespace {

class BandsCli : public test::CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    write_image(path("in.png"), test::random_image(240, 64, 3, 7), {});
  }
};

TEST_F(BandsCli, ReconstructWithTwoBands) {
  const test::CliRun r = gdp("reconstruct " + path("in.png") + " -o " + path("out.tif") + " --bands 2 -q --stats " +
                       path("s.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_image(path("out.tif")).image.width, 240);
  std::ifstream f(path("s.json"));
  const std::string json(std::istreambuf_iterator<char>(f), {});
  EXPECT_NE(json.find("\"schedule\": \"bands\""), std::string::npos) << json;
}

TEST_F(BandsCli, RefusesBadBandCounts) {
  expect_failure("reconstruct " + path("in.png") + " -o " + path("out.tif") + " --bands 2 --in-core", "--in-core");
  expect_failure("reconstruct " + path("in.png") + " -o " + path("out.tif") + " --bands -1", "--bands");
  expect_failure("reconstruct " + path("in.png") + " -o " + path("out.tif") + " --bands 9", "bands need");
}

}  // namespace
}  // namespace gdp
