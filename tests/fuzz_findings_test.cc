// What the decoder fuzz targets (fuzz/, scripts/fuzz.sh) found, each with its fix's check; the
// inputs they found lie in tests/data/fuzz.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <tiffio.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "io/tiff_pages.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

const std::string kFindings = std::string(GDP_TEST_DATA) + "/fuzz/";

int open_descriptors() {
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator("/proc/self/fd")) ++n;
  return n;
}

// Every input the fuzzers kept reads whole or is one InputError naming the file.
TEST(FuzzFindings, EachReadsOrIsAnInputErrorNamingTheFile) {
  int files = 0;
  for (const auto& entry : fs::directory_iterator(kFindings)) {
    if (entry.path().extension() != ".fuzz") continue;
    ++files;
    try {
      read_image(entry.path());
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(entry.path().string() + ": ", 0), 0u) << e.what();
    }
  }
  EXPECT_EQ(files, 4);
}

// A FITS file whose first HDU is no image: cfitsio's open fails but leaves the file open; gdp
// closed nothing (LeakSanitizer found the handle), and every such file kept a descriptor.
TEST(FuzzFindings, FitsThatIsNoImageLeavesNoFileOpen) {
  const fs::path file = kFindings + "fits-not-an-image.fuzz";
  const int before = open_descriptors();
  for (int i = 0; i < 3; ++i) EXPECT_THROW(read_image(file), InputError);
  EXPECT_EQ(open_descriptors(), before);
}

// GeoTIFF tags of another type than the standard's DOUBLE: their SHORTs were read as doubles
// (past the array's end: AddressSanitizer's heap-buffer-overflow). Now they are not a georeference.
TEST(FuzzFindings, GeoTiffTagsOfAnotherTypeAreIgnored) {
  const std::string path = (fs::temp_directory_path() / ("gdp_geo_short_" + std::to_string(::getpid()) + ".tif")).string();
  static TIFFFieldInfo info[] = {{33550, -1, -1, TIFF_SHORT, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelPixelScaleTag")},
                                 {33922, -1, -1, TIFF_SHORT, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelTiepointTag")}};
  TIFF* t = TIFFOpen(path.c_str(), "w");
  ASSERT_TRUE(t);
  TIFFMergeFieldInfo(t, info, 2);
  TIFFSetField(t, TIFFTAG_IMAGEWIDTH, 4);
  TIFFSetField(t, TIFFTAG_IMAGELENGTH, 2);
  TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 8);
  TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  // As doubles these bytes would be a scale of (1, 1) and a tie point at 0: a georeference.
  std::uint16_t scale[12] = {0, 0, 0, 0x3ff0, 0, 0, 0, 0x3ff0, 0, 0, 0, 0}, tie[24] = {};
  TIFFSetField(t, 33550, 12, scale);
  TIFFSetField(t, 33922, 24, tie);
  unsigned char row[4] = {1, 2, 3, 4};
  for (int y = 0; y < 2; ++y) TIFFWriteScanline(t, row, y);
  TIFFClose(t);
  const std::vector<io::TiffPage> pages = io::tiff_pages(path);
  fs::remove(path);
  ASSERT_EQ(pages.size(), 1u);
  EXPECT_FALSE(pages[0].geo.has_value());
}

// A tiled TIFF of a few pixels whose tiles are declared huge: the tile buffer (allocated and
// zeroed before any pixel is read) took gigabytes. Tiles over 64 MB are refused now.
TEST(FuzzFindings, HugeTiffTilesAreRefusedBeforeTheyAreAllocated) {
  const fs::path file = kFindings + "tiff-huge-tiles.fuzz";
  try {
    read_image(file);
    ADD_FAILURE() << "read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tiles of "), std::string::npos) << e.what();
  }
}

// libpng allocates a text chunk as long as its header says (Debian's libpng only warns past
// 8 MB): a 93-byte file claiming 1.5 GB had it allocate that (a timeout under AddressSanitizer).
// Chunks gdp does not use are now skipped unread: a file with a 48 MB text chunk reads without
// that memory (the peak resident size of a child process reading it).
long peak_kb_reading(const std::string& path) {
  const pid_t pid = fork();
  if (pid == 0) {
    try {
      read_image(path);
    } catch (...) {
      _exit(1);
    }
    _exit(0);
  }
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? usage.ru_maxrss : -1;
}

TEST(FuzzFindings, PngChunksAreNotAllocatedWhole) {
  const std::string dir = fs::temp_directory_path() / ("gdp_png_chunk_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write_image(dir + "/small.png", test::random_image(16, 16, 3, 4), {});
  std::ifstream in(dir + "/small.png", std::ios::binary);
  const std::string png(std::istreambuf_iterator<char>(in), {});
  const std::uint32_t length = 48u << 20;
  std::string chunk = {char(length >> 24), char(length >> 16), char(length >> 8), char(length)};
  chunk += "tEXt";
  chunk += "key";
  chunk.resize(8 + length, 'x');
  chunk += std::string(4, '\0');  // a wrong CRC: libpng only warns for an ancillary chunk
  std::ofstream(dir + "/big_text.png", std::ios::binary) << png.substr(0, 33) + chunk + png.substr(33);
  const long small = peak_kb_reading(dir + "/small.png"), big = peak_kb_reading(dir + "/big_text.png");
  fs::remove_all(dir);
  ASSERT_GT(small, 0);
  ASSERT_GT(big, 0) << "the PNG with a large text chunk reads";
  EXPECT_LT(big - small, 16 * 1024) << "peak KB reading it: " << big << ", without the chunk: " << small;
}

}  // namespace
}  // namespace gdp
