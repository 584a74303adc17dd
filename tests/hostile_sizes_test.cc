// Headers that declare huge images: refused from the header, naming the file and what the size would need.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_fixture.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

std::string slurp(const std::string& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}
void put_be(std::string& s, std::size_t at, std::uint32_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) s[at + i] = static_cast<char>(v >> (8 * (bytes - 1 - i)));
}
void put_le(std::string& s, std::size_t at, std::uint32_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) s[at + i] = static_cast<char>(v >> (8 * i));
}
std::uint32_t get_le(const std::string& s, std::size_t at, int bytes) {
  std::uint32_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = v << 8 | static_cast<unsigned char>(s[at + i]);
  return v;
}

class HostileSizes : public test::CliFixture {
 protected:
  // A small real file of the format whose header then claims width x height.
  std::string png(std::uint32_t width, std::uint32_t height) const {
    write_image(path("small.png"), test::random_image(16, 16, 3, 1), {});
    std::string s = slurp(path("small.png"));
    put_be(s, 16, width, 4);  // IHDR data starts at 16 (signature 8, length 4, type 4)
    put_be(s, 20, height, 4);
    put_be(s, 29, static_cast<std::uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(s.data() + 12), 17)), 4);
    return write("huge.png", s);
  }
  std::string jpeg(std::uint16_t width, std::uint16_t height) const {
    write_image(path("small.jpg"), test::random_image(16, 16, 3, 1), {});
    std::string s = slurp(path("small.jpg"));
    const std::size_t sof = s.find("\xff\xc0");
    put_be(s, sof + 5, height, 2);
    put_be(s, sof + 7, width, 2);
    return write("huge.jpg", s);
  }
  std::string tiff(std::uint32_t width, std::uint32_t height) const {
    write_image(path("small.tif"), test::random_image(16, 16, 3, 1), WriteOptions{SampleType::UInt8, 95, false, "none", 256});
    std::string s = slurp(path("small.tif"));
    const std::uint32_t ifd = get_le(s, 4, 4);
    for (std::uint32_t i = 0, n = get_le(s, ifd, 2); i < n; ++i) {
      const std::size_t e = ifd + 2 + 12 * i;
      const std::uint32_t tag = get_le(s, e, 2);
      if (tag != 256 && tag != 257) continue;
      put_le(s, e + 2, 4, 2);  // LONG
      put_le(s, e + 8, tag == 256 ? width : height, 4);
    }
    return write("huge.tif", s);
  }
  std::string exr(std::uint32_t width, std::uint32_t height) const {
    write_image(path("small.exr"), test::random_image(16, 16, 3, 1), {});
    std::string s = slurp(path("small.exr"));
    const std::string attribute("dataWindow\0box2i\0", 17);
    const std::size_t box = s.find(attribute) + attribute.size() + 4;  // after the size: xmin ymin xmax ymax
    put_le(s, box + 8, width - 1, 4);
    put_le(s, box + 12, height - 1, 4);
    return write("huge.exr", s);
  }
  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path(name), std::ios::binary) << bytes;
    return path(name);
  }
};

TEST_F(HostileSizes, GigapixelHeadersAreRefusedByMaxPixels) {
  for (const std::string& file : {png(2000000000, 2000000000), tiff(2000000000, 2000000000), jpeg(65500, 65500)})
    expect_failure("sharpen " + file + " -o " + path("out.tif") + " --max-pixels 100000000", file + ": ");
  // OpenEXR refuses data windows of 2^30 rows or more itself; 100000 x 100000 gets to gdp's check.
  const std::string file = exr(100000, 100000);
  expect_failure("sharpen " + file + " -o " + path("out.tif") + " --max-pixels 100000000", file + ": ");
  EXPECT_NE(gdp("sharpen " + file + " -o " + path("out.tif") + " --max-pixels 100000000").err.find("--max-pixels"),
            std::string::npos);
}

// By default: what the scratch directory holds (/dev/shm: at most the machine's memory).
TEST_F(HostileSizes, ByDefaultTheScratchSpaceNeededIsSaid) {
  if (!fs::is_directory("/dev/shm")) GTEST_SKIP() << "no /dev/shm";
  const std::string file = jpeg(65500, 65500);
  expect_failure("stitch -c " + file + " -l " + file + " -o " + path("out.tif") + " --temp /dev/shm", file + ": ");
  EXPECT_NE(gdp("stitch -c " + file + " -l " + file + " -o " + path("out.tif") + " --temp /dev/shm").err.find(
                "--max-pixels"),
            std::string::npos);
  for (const std::string& f : {png(2000000000, 2000000000), tiff(2000000000, 2000000000)})
    expect_failure("sharpen " + f + " -o " + path("out.tif"), f + ": ");
}

// Scratch rows up to --memory stay in memory: they are counted against the memory available, not the disk.
TEST_F(HostileSizes, TheScratchMemoryBudgetCountsAsMemory) {
  if (!fs::is_directory("/dev/shm")) GTEST_SKIP() << "no /dev/shm";
  const std::string file = jpeg(65500, 65500);
  const std::string run = "stitch -c " + file + " -l " + file + " -o " + path("out.tif") + " --temp /dev/shm";
  expect_failure(run + " --memory 100000G", "of scratch rows: --memory");
  EXPECT_NE(gdp(run + " --memory files").err.find("of scratch space in /dev/shm"), std::string::npos);
}

TEST_F(HostileSizes, SidesBeyondAnIntAreSaidSo) {
  const std::string file = tiff(3000000000u, 16);
  expect_failure("convert " + file + " -o " + path("out.tif"), "beyond gdp's largest side");
}

// Sizes from options: a PQ grid 4H x H (whose width overflowed an int) is checked like a header's.
TEST_F(HostileSizes, SizesFromOptionsAreCheckedToo) {
  write_image(path("eq.png"), test::random_image(64, 32, 3, 1), {});
  expect_failure("sphere to-pq " + path("eq.png") + " -o " + path("pq.png") + " --height 1000000000", "--height");
  expect_failure("sharpen --sphere " + path("eq.png") + " -o " + path("out.png") + " --pq-height 1000000000",
                 "--pq-height");
}

TEST_F(HostileSizes, SmallImagesStillWork) {
  const test::CliRun r = gdp("sharpen " + tiff(16, 16) + " -o " + path("out.tif") + " --max-pixels 256");
  EXPECT_EQ(r.code, 0) << r.err;
}

}  // namespace
}  // namespace gdp
