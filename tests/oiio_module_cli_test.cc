// The gdp tool reads and writes PNG, TIFF, JPEG and OpenEXR without OpenImageIO's module, and says so when a format needs it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "cli_fixture.h"
#include "gdp/image_io.h"

namespace gdp {
namespace {

using test::CliFixture;
using test::CliRun;

// Points GDP_OIIO_MODULE (inherited by the gdp runs) at a file that does not exist while alive.
class NoModule {
 public:
  NoModule() { ::setenv("GDP_OIIO_MODULE", "/nonexistent/libgdp_oiio.so", 1); }
  ~NoModule() { ::unsetenv("GDP_OIIO_MODULE"); }
};

class OiioModuleCli : public CliFixture {};

TEST_F(OiioModuleCli, PngTiffJpegAndExrNeedNoModule) {
  Image image(300, 200, 3);
  for (std::size_t i = 0; i < image.data.size(); ++i) image.data[i] = static_cast<float>(i % 251) / 250.0f;
  write_image(path("in.png"), image, {});
  const NoModule no_module;
  for (const char* out : {"out.tif", "out.jpg", "out.exr", "out2.png"}) {
    const CliRun r = gdp("convert " + path("in.png") + " -o " + path(out));
    EXPECT_EQ(r.code, 0) << out << ": " << r.err;
  }
  const CliRun r = gdp("sharpen " + path("out.tif") + " --scale 4 -o " + path("sharp.jpg") + " --tiled --quiet");
  EXPECT_NE(r.code, 0) << "tiled JPEG output must be refused";
  const CliRun s = gdp("smooth " + path("out.jpg") + " --scale 4 -o " + path("smooth.tif") + " --tiled --quiet");
  EXPECT_EQ(s.code, 0) << s.err;
  const CliRun t = gdp("smooth " + path("out.exr") + " --scale 4 -o " + path("smooth.exr") + " --tiled --quiet");
  EXPECT_EQ(t.code, 0) << t.err;
}

TEST_F(OiioModuleCli, AFormatNeedingTheMissingModuleIsAOneLineError) {
  write_image(path("in.png"), Image(8, 8, 3), {});
  std::ofstream(path("in.hdr")) << "not read";
  const NoModule no_module;
  expect_failure("convert " + path("in.png") + " -o " + path("out.hdr"), "needs OpenImageIO's module");
  expect_failure("convert " + path("in.hdr") + " -o " + path("out.png"), "/nonexistent/libgdp_oiio.so");
}

TEST_F(OiioModuleCli, ConvertingPngToTiffStaysFarBelowOpenImageIOsOwnFootprint) {
  // An empty program linked against Debian's OpenImageIO peaks at some 130 MB; gdp converting a
  // 2048 x 2048 RGB PNG to TIFF must stay far below that (its bands are a few MB).
  Image image(2048, 2048, 3);
  for (std::size_t i = 0; i < image.data.size(); ++i) image.data[i] = static_cast<float>((i * 7) % 256) / 255.0f;
  write_image(path("big.png"), image, {});
  // gdp runs as a child of a small shell, not of this (large) test process: Linux carries the
  // peak of the process image an exec replaces into the new program's ru_maxrss, which --stats reports.
  const std::string command = "sh -c '" + std::string(GDP_CLI_PATH) + " convert " + path("big.png") + " -o " +
                              path("big.tif") + " --stats " + path("stats.json") + " -q; true'";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream file(path("stats.json"));
  const std::string stats((std::istreambuf_iterator<char>(file)), {});
  const std::size_t at = stats.find("\"peak_rss_mb\":");
  ASSERT_NE(at, std::string::npos) << stats;
  const double peak_mb = std::stod(stats.substr(at + 14));
  EXPECT_LT(peak_mb, 64.0) << "peak resident MB of the gdp run";
  EXPECT_GT(peak_mb, 1.0);
}

}  // namespace
}  // namespace gdp
