// Canvases past 2^31 pixels: the label plane and scratch blocks address bytes past 2^32 (sparse files, no big data).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <vector>

#include "blend/scratch.h"
#include "blend/seams.h"

namespace gdp::blending {
namespace {

// 70000 x 31000 = 2.17e9 pixels (past 2^31): rows written far apart come back in their place, and
// only the rows written take room (the plane keeps rows as they come, with an index by row).
TEST(BlendBigCanvas, LabelRowsPast2To31PixelsKeepTheirPlace) {
  const int w = 70000, h = 31000;
  LabelPlane plane(std::filesystem::temp_directory_path(), w, h);
  // Only the rows written take room (2 bytes a pixel for these, which do not repeat), beside the index.
  const auto pattern = [&](int y) {
    std::vector<Label> row(w);
    for (int x = 0; x < w; ++x) row[x] = static_cast<Label>((x * 7 + y) & 0xffff);
    return row;
  };
  const int rows[] = {0, 15342, 30682, h - 1};  // 30682 x 70000 is the first row starting past 2^31 pixels
  for (const int y : rows) plane.write_row(y, pattern(y));
  for (const int y : rows) {
    std::vector<Label> got(w, 0);
    plane.read_row(y, got);
    EXPECT_EQ(got, pattern(y)) << "row " << y;
    std::vector<Label> part(w, 0);
    plane.read_row(y, part, w - 100, w);  // the row's last columns only
    for (int x = w - 100; x < w; ++x) ASSERT_EQ(part[x], pattern(y)[x]) << "row " << y << " column " << x;
  }
  std::vector<Label> between(w, 1);
  plane.read_row(30000, between);  // never written: zeros, not another row's labels
  EXPECT_EQ(between, std::vector<Label>(w, 0));
  EXPECT_LE(plane.bytes(), std::size_t{16} * h + std::size_t{2} * w * std::size(rows));
}

TEST(BlendBigCanvas, ScratchOffsetsPast2To32Bytes) {
  const std::size_t size = (std::size_t{5} << 30) + 64;
  Scratch s(std::filesystem::temp_directory_path(), size, "big");
  const std::uint64_t marks[] = {0x0123456789abcdefULL, 0xfedcba9876543210ULL};
  s.write(0, &marks[0], 8);
  s.write(size - 8, &marks[1], 8);
  std::uint64_t got[2] = {0, 0};
  s.read(0, &got[0], 8);
  s.read(size - 8, &got[1], 8);
  EXPECT_EQ(got[0], marks[0]);
  EXPECT_EQ(got[1], marks[1]);
  std::uint64_t far = 1;
  s.read(std::size_t{1} << 32, &far, 8);  // between them: never written
  EXPECT_EQ(far, 0u);
}

}  // namespace
}  // namespace gdp::blending
