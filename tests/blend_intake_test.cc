// gdp blend's intake: nona's TIFF tags, multi-page TIFFs, sample types, masks, canvas rules.
#include <gtest/gtest.h>

#include <filesystem>

#include "gdp/blend.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/image_stream.h"
#include "io/tiff_pages.h"
#include "nona_tiff.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

class BlendIntake : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("gdp_blend_intake_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

// A w x h RGBA layer of one colour, covered where (x + y) is not divisible by 7.
Image layer(int w, int h, float value) {
  Image img(w, h, 4, value);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(3, x, y) = (x + y) % 7 == 0 ? 0.0f : 1.0f;
  return img;
}

TEST_F(BlendIntake, NonaTagsPlaceTheLayerOnTheCanvas) {
  const Image a = layer(30, 20, 0.4f);
  test::write_nona_tiff(path("a.tif"), {{&a, 37, 11, 8}}, 120, 80);
  const BlendPlan plan = plan_blend({LayerSource{path("a.tif")}}, {});
  ASSERT_EQ(plan.layers.size(), 1u);
  EXPECT_EQ(plan.layers[0].x, 37);
  EXPECT_EQ(plan.layers[0].y, 11);
  EXPECT_EQ(plan.canvas.width, 120);  // PIXAR_IMAGEFULLWIDTH/LENGTH
  EXPECT_EQ(plan.canvas.height, 80);
  EXPECT_EQ(plan.colour_channels, 3);
  EXPECT_EQ(plan.sample_type, SampleType::UInt8);
  Image out(120, 80, 4);
  ImageRowWriter writer(out);
  blend(plan, {}, {}, writer);
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 120; ++x) {
      const bool inside = x >= 37 && x < 67 && y >= 11 && y < 31 && (x - 37 + y - 11) % 7 != 0;
      ASSERT_EQ(out.at(3, x, y), inside ? 1.0f : 0.0f) << x << "," << y;
      if (inside) {
        EXPECT_NEAR(out.at(0, x, y), 102.0f / 255.0f, 1e-5);
      }
    }
}

TEST_F(BlendIntake, EveryPageOfAMultiPageTiffIsALayer) {
  const Image a = layer(40, 30, 0.25f), b = layer(40, 30, 0.25f);
  test::write_nona_tiff(path("pages.tif"), {{&a, 0, 0, 16}, {&b, 30, 5, 16}}, 70, 35);
  const BlendPlan plan = plan_blend({LayerSource{path("pages.tif")}}, {});
  ASSERT_EQ(plan.layers.size(), 2u);
  EXPECT_EQ(plan.layers[1].x, 30);
  EXPECT_EQ(plan.layers[1].y, 5);
  EXPECT_NE(plan.layers[1].name.find("page 2"), std::string::npos);
  EXPECT_EQ(plan.sample_type, SampleType::UInt16);
  Image out(70, 35, 4);
  ImageRowWriter writer(out);
  blend(plan, {}, {}, writer);
  EXPECT_EQ(out.at(3, 65, 30), 1.0f);  // only page 2 covers it
  EXPECT_NEAR(out.at(1, 65, 30), 0.25f, 1e-4);
  EXPECT_EQ(out.at(3, 65, 2), 0.0f);  // nothing covers it
}

TEST_F(BlendIntake, FloatLayersAndExplicitPlacement) {
  Image a = layer(20, 10, 2.5f);  // float values above 1 stay
  test::write_nona_tiff(path("f.tif"), {{&a, 0, 0, 32}}, 0, 0);
  LayerSource s{path("f.tif")};
  s.placed = true;
  s.x = -5;
  s.y = 3;
  const BlendPlan plan = plan_blend({s}, {});
  EXPECT_EQ(plan.sample_type, SampleType::Float);
  EXPECT_EQ(plan.canvas.x, -5);
  EXPECT_EQ(plan.canvas.y, 3);
  EXPECT_EQ(plan.canvas.width, 20);
}

TEST_F(BlendIntake, MaskFilesAndTheirSize) {
  Image grey(30, 20, 1, 0.5f), mask(30, 20, 1, 1.0f), small(29, 20, 1, 1.0f);
  for (int y = 0; y < 20; ++y) mask.at(0, 3, y) = 0.0f;
  WriteOptions png;
  png.sample_type = SampleType::UInt8;
  write_image(path("g.png"), grey, png);
  write_image(path("m.png"), mask, png);
  write_image(path("s.png"), small, png);
  const BlendPlan plan = plan_blend({LayerSource{path("g.png"), path("m.png")}}, {});
  EXPECT_EQ(plan.colour_channels, 1);
  Image out(30, 20, 2);
  ImageRowWriter writer(out);
  blend(plan, {}, {}, writer);
  EXPECT_EQ(out.at(1, 3, 7), 0.0f);
  EXPECT_EQ(out.at(1, 4, 7), 1.0f);
  try {
    plan_blend({LayerSource{path("g.png"), path("s.png")}}, {});
    FAIL() << "a mask of another size is an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.png"), std::string::npos) << e.what();
  }
}

// A grey GeoTIFF, north up: its top-left corner at (west, north), square pixels, an EPSG code.
void write_geotiff(const std::string& path, double west, double north, double pixel, std::uint16_t epsg) {
  TIFF* t = TIFFOpen(path.c_str(), "w");
  ASSERT_NE(t, nullptr);
  static TIFFFieldInfo info[] = {
      {33550, -1, -1, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelPixelScaleTag")},
      {33922, -1, -1, TIFF_DOUBLE, FIELD_CUSTOM, 1, 1, const_cast<char*>("ModelTiepointTag")},
      {34735, -1, -1, TIFF_SHORT, FIELD_CUSTOM, 1, 1, const_cast<char*>("GeoKeyDirectoryTag")}};
  TIFFMergeFieldInfo(t, info, 3);
  const int w = 40, h = 30;
  TIFFSetField(t, TIFFTAG_IMAGEWIDTH, w);
  TIFFSetField(t, TIFFTAG_IMAGELENGTH, h);
  TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 8);
  TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  double scale[3] = {pixel, pixel, 0.0}, tie[6] = {0.0, 0.0, 0.0, west, north, 0.0};
  std::uint16_t keys[8] = {1, 1, 0, 1, 3072, 0, 1, epsg};  // ProjectedCSTypeGeoKey
  TIFFSetField(t, 33550, 3, scale);
  TIFFSetField(t, 33922, 6, tie);
  TIFFSetField(t, 34735, 8, keys);
  std::vector<unsigned char> row(w, 128);
  for (int y = 0; y < h; ++y) TIFFWriteScanline(t, row.data(), y);
  TIFFClose(t);
}

TEST_F(BlendIntake, GeoTiffLayersArePlacedByTheirCoordinates) {
  write_geotiff(path("a.tif"), 1000.0, 5000.0, 2.0, 32633);
  write_geotiff(path("b.tif"), 1060.0, 4980.0, 2.0, 32633);  // 30 pixels east, 10 south
  const BlendPlan plan = plan_blend({LayerSource{path("b.tif")}, LayerSource{path("a.tif")}}, {});
  EXPECT_EQ(plan.layers[1].x, 0);
  EXPECT_EQ(plan.layers[1].y, 0);
  EXPECT_EQ(plan.layers[0].x, 30);
  EXPECT_EQ(plan.layers[0].y, 10);
  EXPECT_EQ(plan.canvas.width, 70);
  EXPECT_EQ(plan.canvas.height, 40);
  // The output carries the canvas's georeference.
  ASSERT_TRUE(plan.geo.has_value());
  WriteOptions options;
  options.geo = plan.geo;
  {
    ImageFileWriter out(path("out.tif"), 70, 40, 2, options);
    blend(plan, {}, {}, out);
  }
  const auto written = io::tiff_pages(path("out.tif"));
  ASSERT_TRUE(written.at(0).geo.has_value());
  EXPECT_EQ(written[0].geo->origin_x, 1000.0);
  EXPECT_EQ(written[0].geo->origin_y, 5000.0);
  EXPECT_EQ(written[0].geo->scale_x, 2.0);
  EXPECT_EQ(written[0].geo->keys, (std::vector<std::uint16_t>{1, 1, 0, 1, 3072, 0, 1, 32633}));
  write_geotiff(path("c.tif"), 1000.0, 5000.0, 2.5, 32633);
  write_geotiff(path("d.tif"), 1000.0, 5000.0, 2.0, 32634);
  for (const char* other : {"c.tif", "d.tif"}) {
    try {
      plan_blend({LayerSource{path("a.tif")}, LayerSource{path(other)}}, {});
      FAIL() << other << ": another pixel size or CRS is an error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(other), std::string::npos) << e.what();
    }
  }
}

TEST_F(BlendIntake, CanvasRules) {
  const Image grey(10, 10, 1, 0.5f), rgb(10, 10, 3, 0.5f);
  BlendOptions f;
  f.canvas = CanvasRect{100, 100, 50, 50};
  EXPECT_THROW(plan_blend({ImageLayer{&grey}}, f), InputError);  // wholly outside -f
  // A grey layer among RGB ones: promoted, its grey in all three channels, with a note.
  const BlendPlan mixed = plan_blend({ImageLayer{&rgb}, ImageLayer{&grey, nullptr, 10, 0}}, {});
  EXPECT_EQ(mixed.colour_channels, 3);
  ASSERT_EQ(mixed.notes.size(), 1u);
  EXPECT_NE(mixed.notes[0].find("layer 2"), std::string::npos) << mixed.notes[0];
  const Image promoted = blend({ImageLayer{&rgb}, ImageLayer{&grey, nullptr, 10, 0}}, {}, {});
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(promoted.at(c, 15, 5), 0.5f, 1e-5);
  EXPECT_THROW(plan_blend(std::vector<ImageLayer>{}, {}), UsageError);
  f.canvas = CanvasRect{5, 0, 50, 50};
  const Image cut = blend({ImageLayer{&grey}}, f, {});  // partly outside: its part inside
  EXPECT_EQ(cut.width, 50);
  EXPECT_EQ(cut.at(1, 4, 5), 1.0f);
  EXPECT_EQ(cut.at(1, 5, 5), 0.0f);
}

}  // namespace
}  // namespace gdp
