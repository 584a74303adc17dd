// Per-band input files: an image read from vertical strips in several files, only the needed ones decoded.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/strip_files.h"
#include "image_stream_util.h"
#include "test_util.h"

namespace gdp {
namespace {

class StripFiles : public test::TempDirTest {
 protected:
  // `whole` cut into strips of the given widths, written as strip_0.tif, strip_1.tif, ...
  void write_strips(const Image& whole, const std::vector<int>& widths) {
    int x0 = 0;
    for (std::size_t i = 0; i < widths.size(); ++i) {
      Image s(widths[i], whole.height, whole.channels);
      for (int c = 0; c < whole.channels; ++c)
        for (int y = 0; y < whole.height; ++y)
          for (int x = 0; x < widths[i]; ++x) s.at(c, x, y) = whole.at(c, x0 + x, y);
      write_image(file("strip_" + std::to_string(i) + ".tif"), s, {});
      x0 += widths[i];
    }
  }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  std::string pattern() const { return file("strip_{rank}.tif"); }
};

TEST_F(StripFiles, StripsSideBySideAreTheImage) {
  const Image whole = test::random_image(300, 40, 3, 7);
  write_strips(whole, {70, 130, 100});
  StripFilesReader r(pattern());
  EXPECT_EQ(r.strips(), 3);
  ASSERT_EQ(r.width(), 300);
  ASSERT_EQ(r.height(), 40);
  std::vector<float> row(3 * 300);
  for (int pass = 0; pass < 2; ++pass) {
    for (int y = 0; y < 40; ++y) {
      r.read_row(y, row);
      for (int c = 0; c < 3; ++c)
        for (int x = 0; x < 300; ++x) ASSERT_EQ(row[c * 300 + x], whole.at(c, x, y)) << c << " " << x << " " << y;
    }
    r.rewind();
  }
}

TEST_F(StripFiles, OnlyStripsOverlappingTheColumnsAreDecoded) {
  const Image whole = test::random_image(300, 40, 2, 8);
  write_strips(whole, {70, 130, 100});
  StripFilesReader r(pattern());
  r.set_columns(150, 220);  // strips 1 and 2
  std::filesystem::remove(file("strip_0.tif"));  // would fail the read if it were still needed
  std::vector<float> row(2 * 300, -1.0f);
  for (int y = 0; y < 40; ++y) {
    r.read_row(y, row);
    for (int c = 0; c < 2; ++c)
      for (int x = 150; x < 220; ++x) ASSERT_EQ(row[c * 300 + x], whole.at(c, x, y));
  }
  EXPECT_EQ(row[0], -1.0f) << "columns outside the window are left as they were";
}

TEST_F(StripFiles, MismatchedOrMissingStripsAreInputErrorsNamingTheFile) {
  write_image(file("strip_0.tif"), test::random_image(50, 40, 3), {});
  write_image(file("strip_1.tif"), test::random_image(50, 41, 3), {});
  try {
    StripFilesReader r(pattern());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("strip_1.tif"), std::string::npos) << e.what();
  }
  try {
    StripFilesReader r(file("none_{rank}.tif"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("none_0.tif"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gdp
