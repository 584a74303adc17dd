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

std::string file_bytes(const std::string& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

// Streaming is the one-band plan of the one streamed V-cycle: --bands 1 writes the default's bytes.
TEST_F(BandsCli, OneBandIsTheDefaultByteForByte) {
  write_image(path("pq.tif"), test::random_image(256, 64, 2, 3), {});
  for (const std::string domain : {"planar", "cylindrical", "spherical"}) {
    SCOPED_TRACE(domain);
    const std::string in = domain == "spherical" ? path("pq.tif") : path("in.png");
    const std::string common = "sharpen " + in + " --domain " + domain + " --depth float -q --vcycles 2 -o ";
    test::CliRun r = gdp(common + path("default.tif"));
    ASSERT_EQ(r.code, 0) << r.err;
    r = gdp(common + path("one.tif") + " --bands 1");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string a = file_bytes(path("default.tif")), b = file_bytes(path("one.tif"));
    EXPECT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == b) << "--bands 1 differs from the default";
    // The default's narrow scratch is rounded alike in-core; --scratch float: one band is the default too.
    r = gdp(common + path("in_core.tif") + " --in-core");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(a == file_bytes(path("in_core.tif"))) << "--in-core differs from the default";
    r = gdp(common + path("float.tif") + " --scratch float");
    ASSERT_EQ(r.code, 0) << r.err;
    r = gdp(common + path("float1.tif") + " --scratch float --bands 1");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(file_bytes(path("float.tif")) == file_bytes(path("float1.tif"))) << "--scratch float, --bands 1";
  }
}

TEST_F(BandsCli, RefusesBadBandCounts) {
  expect_failure("reconstruct " + path("in.png") + " -o " + path("out.tif") + " --bands 2 --in-core", "--in-core");
  expect_failure("reconstruct " + path("in.png") + " -o " + path("out.tif") + " --bands -1", "--bands");
  expect_failure("reconstruct " + path("in.png") + " -o " + path("out.tif") + " --bands 9", "bands need");
}

}  // namespace
}  // namespace gdp
