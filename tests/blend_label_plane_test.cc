// The label plane: rows kept as runs (or as they are), in memory and past 8 MiB in a file, come back exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <thread>
#include <vector>

#include "blend/label_plane.h"

namespace gdp {
namespace {

using blending::Label;

// Row y of a plane mixing the kinds of rows a label plane meets: runs of a few labels (seams),
// one label throughout, uncovered (0), and noise (more runs than pixels: kept as it is).
std::vector<Label> row_of(int width, int y) {
  std::vector<Label> row(width);
  std::mt19937 random(static_cast<unsigned>(y) * 7919u + 1u);
  switch (y % 4) {
    case 0:
      for (int x = 0; x < width; ++x) row[x] = static_cast<Label>(1 + (x * 5 / width + y) % 3);
      break;
    case 1:
      std::fill(row.begin(), row.end(), static_cast<Label>(y % 7));
      break;
    case 2:
      for (int x = 0; x < width; ++x) row[x] = static_cast<Label>(x % 3 == 0 ? 0 : 65535);
      break;
    default:
      for (Label& l : row) l = static_cast<Label>(random() % 5);
  }
  return row;
}

void expect_rows(const blending::LabelPlane& plane, int written_rows) {
  const int W = plane.width();
  std::vector<Label> got(W);
  for (int y = 0; y < plane.height(); ++y) {
    const std::vector<Label> want = y < written_rows ? row_of(W, y) : std::vector<Label>(W, 0);
    plane.read_row(y, got);
    ASSERT_EQ(got, want) << "row " << y;
    // Columns [a, b) only: those filled, the rest left as they were.
    const int a = (y * 37) % W, b = std::min(W, a + 1 + (y * 101) % W);
    std::vector<Label> part(W, 12345);
    plane.read_row(y, part, a, b);
    for (int x = 0; x < W; ++x) ASSERT_EQ(part[x], x >= a && x < b ? want[x] : 12345) << x << "," << y;
  }
}

// Rows written in a shuffled order on four threads come back exactly, whole and in part; rows
// never written are 0. The seam-like rows take bytes per row, not per pixel.
TEST(BlendLabelPlane, RowsComeBackAsWrittenFromAnyThreadInAnyOrder) {
  const int W = 300, H = 200, written = 180;
  blending::LabelPlane plane({}, W, H);
  std::vector<int> order(written);
  for (int y = 0; y < written; ++y) order[y] = y;
  std::shuffle(order.begin(), order.end(), std::mt19937(5));
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int i = t; i < written; i += 4) plane.write_row(order[i], row_of(W, order[i]));
    });
  for (std::thread& t : threads) t.join();
  expect_rows(plane, written);
  // Noise and alternating rows (half) as they are, 2 bytes a pixel; the others a few runs each,
  // beside a 16-byte index entry per row.
  EXPECT_LT(plane.bytes(), H * 16 + (written / 2 + 1) * W * sizeof(Label) + written * 32);
}

// Runs longer than a Label counts are split; a row of 70,000 pixels of one label comes back.
TEST(BlendLabelPlane, RunsLongerThanALabelCountComeBack) {
  const int W = 70000;
  blending::LabelPlane plane({}, W, 3);
  std::vector<Label> row(W, 9), got(W);
  row[W - 1] = 4;
  plane.write_row(1, row);
  plane.read_row(1, got);
  EXPECT_EQ(got, row);
  plane.read_row(1, got, 65530, 65540);
  EXPECT_EQ(std::vector<Label>(got.begin() + 65530, got.begin() + 65540), std::vector<Label>(10, 9));
}

// Past 8 MiB the rows go to a scratch file, those kept in memory before too: all come back.
TEST(BlendLabelPlane, RowsPastEightMebibytesGoToAFileAndComeBack) {
  const int W = 4096, H = 4200;  // a quarter noise rows: 1050 * 8 KiB = 8.4 MiB as they are
  blending::LabelPlane plane({}, W, H);
  for (int y = 0; y < H; ++y) plane.write_row(y, row_of(W, y));
  EXPECT_GT(plane.bytes(), std::size_t{8} << 20);
  expect_rows(plane, H);
}

}  // namespace
}  // namespace gdp
