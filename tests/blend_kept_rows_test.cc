// Kept rows: the seam pass's decoded rows read back by the sweep are the decoded rows exactly, 8- and 16-bit; others not kept.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "blend/kept_rows.h"
#include "blend/layer_rows.h"
#include "gdp/blend.h"
#include "gdp/image_io.h"
#include "test_util.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

struct BlendKeptRows : ::testing::Test {
  fs::path dir = fs::temp_directory_path() / ("gdp_kept_rows_" + std::to_string(::getpid()));
  void SetUp() override { fs::create_directories(dir); }
  void TearDown() override { fs::remove_all(dir); }
  std::string path(const std::string& name) const { return (dir / name).string(); }
};

// An image of w x h with `channels` channels whose last is alpha: a disc left uncovered.
Image layer_image(int w, int h, int channels, unsigned seed) {
  Image img = test::random_image(w, h, channels, seed);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(channels - 1, x, y) = (x - 20) * (x - 20) + (y - 15) * (y - 15) < 64 ? 0.0f : 1.0f;
  return img;
}

// Every row of layer k, colour and coverage, as LayerRows gives them.
void read_all(blending::LayerRows& rows, std::vector<float>& colour, std::vector<unsigned char>& covered, int channels) {
  const blending::Footprint& f = rows.where();
  std::vector<float> c(static_cast<std::size_t>(channels) * f.width());
  std::vector<unsigned char> v(f.width());
  colour.clear();
  covered.clear();
  for (int y = f.y0; y < f.y1; ++y) {
    rows.read(y, c, v);
    colour.insert(colour.end(), c.begin(), c.end());
    covered.insert(covered.end(), v.begin(), v.end());
  }
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// 8-bit RGBA (LZW TIFF) and 16-bit RGBA (PNG) layers: kept by the pass that decodes them, read
// back (once: then given up) as the very floats decoding gives; a float layer is not kept. A sweep
// started again decodes the layers again, to the same floats.
TEST_F(BlendKeptRows, RowsReadBackAreTheDecodedRowsExactly) {
  WriteOptions u8, u16, f32;
  u8.sample_type = SampleType::UInt8;
  u8.compression = "lzw";
  u16.sample_type = SampleType::UInt16;
  f32.sample_type = SampleType::Float;
  write_image(path("a.tif"), layer_image(70, 50, 4, 1), u8);
  write_image(path("b.png"), layer_image(60, 45, 4, 2), u16);
  write_image(path("c.tif"), layer_image(40, 30, 4, 3), f32);
  LayerSource a{path("a.tif")}, b{path("b.png")}, c{path("c.tif")};
  b.placed = c.placed = true;
  b.x = 30, b.y = 10, c.x = 5, c.y = 25;
  const BlendPlan plan = plan_blend({a, b, c}, {});
  blending::KeptRows kept(plan, dir);
  const int W = plan.canvas.width;
  for (int k = 0; k < 3; ++k) {
    std::vector<float> decoded, again, from_kept;
    std::vector<unsigned char> covered, covered_again, covered_kept;
    {
      blending::LayerRows seam_pass(plan, k, 0, W, true, &kept);
      read_all(seam_pass, decoded, covered, plan.colour_channels);
    }
    blending::LayerRows file(plan, k, 0, W, true);
    read_all(file, again, covered_again, plan.colour_channels);
    ASSERT_TRUE(same_bits(decoded, again)) << "layer " << k;
    const blending::Footprint& f = file.where();
    const int rows = f.y1 - f.y0 + f.skip_y;
    EXPECT_EQ(kept.has(k, rows), k < 2) << "layer " << k;
    for (int pass = 0; pass < 2; ++pass) {
      {
        blending::LayerRows sweep(plan, k, 0, W, true, nullptr, &kept);
        read_all(sweep, from_kept, covered_kept, plan.colour_channels);
      }
      EXPECT_FALSE(kept.has(k, rows)) << "layer " << k << ": read once, then given up";
      EXPECT_TRUE(same_bits(from_kept, decoded)) << "layer " << k << ", pass " << pass;
      EXPECT_EQ(covered_kept, covered) << "layer " << k << ", pass " << pass;
    }
  }
}

// A layer whose rows were not all written (a seam pass stopped by an error) is not kept.
TEST_F(BlendKeptRows, ALayerNotWrittenToItsEndIsNotKept) {
  write_image(path("a.png"), layer_image(50, 40, 2, 4), {});
  const BlendPlan plan = plan_blend({LayerSource{path("a.png")}}, {});
  blending::KeptRows kept(plan, dir);
  {
    auto writer = kept.writer(0, SampleType::UInt8, 2, 50, 40);
    ASSERT_NE(writer, nullptr);
    std::vector<float> row(100, 0.0f);
    for (int y = 0; y < 39; ++y) writer->write(row);
  }
  EXPECT_EQ(kept.reader(0, 40), nullptr);
}

}  // namespace
}  // namespace gdp
