// Seam files in multiblend's format (8-bit palette PNG, value = layer index): written, read back, and read when libpng wrote them.
#include <gtest/gtest.h>

#include <csetjmp>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

#include <png.h>

#include "blend/seam_files.h"
#include "blend/seam_png.h"
#include "gdp/blend.h"
#include "gdp/errors.h"

namespace gdp {
namespace {

std::string temp(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("gdp_seamfile_" + std::to_string(::getpid()) + "_" + name)).string();
}

// A palette PNG written with libpng alone: `bits` per index, values from `value(x, y)`.
template <class F>
void write_palette_png(const std::string& path, int w, int h, int bits, F value) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_TRUE(f);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, w, h, bits, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  std::vector<png_color> palette(1 << bits, png_color{10, 20, 30});
  png_set_PLTE(png, info, palette.data(), static_cast<int>(palette.size()));
  png_write_info(png, info);
  if (bits < 8) png_set_packing(png);
  std::vector<png_byte> row(w);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) row[x] = static_cast<png_byte>(value(x, y));
    png_write_row(png, row.data());
  }
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

// The indices of a palette PNG, read with libpng alone.
std::vector<std::vector<png_byte>> read_indices(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_read_info(png, info);
  EXPECT_EQ(png_get_color_type(png, info), PNG_COLOR_TYPE_PALETTE);
  EXPECT_EQ(png_get_bit_depth(png, info), 8);
  std::vector<std::vector<png_byte>> rows(png_get_image_height(png, info),
                                          std::vector<png_byte>(png_get_image_width(png, info)));
  for (auto& r : rows) png_read_row(png, r.data(), nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(f);
  return rows;
}

class SeamFiles : public ::testing::Test {
 protected:
  // Layer a covers canvas columns [0, 60), b [40, 100), 40 rows: depth seam at 50.
  Image a{60, 40, 1, 0.2f}, b{60, 40, 1, 0.7f};
  BlendPlan plan = plan_blend({ImageLayer{&a, nullptr, 0, 0}, ImageLayer{&b, nullptr, 40, 0}}, {});
  std::string file = temp("seams.png");
  void TearDown() override { std::filesystem::remove(file); }
};

TEST_F(SeamFiles, PalettePngRoundTrip) {
  const auto depth = blending::compute_seams(plan, false, {}, nullptr);
  blending::save_seams(*depth.labels, 2, file);
  EXPECT_TRUE(blending::is_palette_png(file));
  const auto indices = read_indices(file);  // multiblend's convention: 0 = the first layer
  EXPECT_EQ(indices[10][45], 0);
  EXPECT_EQ(indices[10][55], 1);
  const auto loaded = blending::load_seams(plan, file, {});
  std::vector<blending::Label> want(100), got(100);
  for (int y = 0; y < 40; ++y) {
    depth.labels->read_row(y, want);
    loaded.labels->read_row(y, got);
    ASSERT_EQ(got, want) << "row " << y;
  }
}

TEST_F(SeamFiles, PalettePngWrittenByLibpngIsRead) {
  for (int bits : {8, 4}) {
    const int none = bits == 8 ? blending::kPaletteNone : 15;
    // The seam at 44; (70, 5) names a, which does not cover it (b, the first that does, takes it);
    // (10, 5) names no layer (a, the first covering, takes it).
    write_palette_png(file, 100, 40, bits, [&](int x, int y) {
      if (x == 70 && y == 5) return 0;
      if (x == 10 && y == 5) return none;
      return x < 44 ? 0 : 1;
    });
    EXPECT_TRUE(blending::is_palette_png(file));
    if (bits < 8) {  // 4-bit: 15 is a layer index past the count, so refused
      EXPECT_THROW(blending::load_seams(plan, file, {}), InputError);
      write_palette_png(file, 100, 40, bits, [&](int x, int y) { return x == 70 && y == 5 ? 0 : x < 44 ? 0 : 1; });
    }
    const auto loaded = blending::load_seams(plan, file, {});
    std::vector<blending::Label> row(100);
    loaded.labels->read_row(5, row);
    EXPECT_EQ(row[10], 1);
    EXPECT_EQ(row[43], 1);
    EXPECT_EQ(row[44], 2);
    EXPECT_EQ(row[70], 2);
  }
}

TEST_F(SeamFiles, BadPalettePngs) {
  write_palette_png(file, 100, 40, 8, [](int x, int) { return x < 50 ? 0 : 2; });  // layer 2 of 2
  EXPECT_THROW(blending::load_seams(plan, file, {}), InputError);
  write_palette_png(file, 99, 40, 8, [](int, int) { return 0; });
  EXPECT_THROW(blending::load_seams(plan, file, {}), InputError);
  std::filesystem::remove(file);
  blending::LabelPlane many({}, 4, 4);
  EXPECT_THROW(blending::save_seams(many, 256, file), UsageError);
  EXPECT_FALSE(std::filesystem::exists(file));
}

// gdp's own label maps (grey, 1 = the first layer) still load from any lossless format.
TEST_F(SeamFiles, GreyLabelMapsStillLoad) {
  const std::string tif = temp("seams.tif");
  const auto depth = blending::compute_seams(plan, false, {}, nullptr);
  blending::save_seams(*depth.labels, 2, tif);
  EXPECT_FALSE(blending::is_palette_png(tif));
  const auto loaded = blending::load_seams(plan, tif, {});
  std::vector<blending::Label> row(100);
  loaded.labels->read_row(20, row);
  EXPECT_EQ(row[45], 1);
  EXPECT_EQ(row[55], 2);
  std::filesystem::remove(tif);
}

}  // namespace
}  // namespace gdp
