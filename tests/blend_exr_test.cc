// gdp blend and OpenEXR layers: placed by their data windows in the display window, the output keeping a data window.
#include <gtest/gtest.h>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>

#include "gdp/blend.h"
#include "gdp/image_io.h"
#include "gdp/image_stream.h"
#include "io/exr_windows.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

class BlendExr : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("gdp_blend_exr_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

// The scene at display coordinates (x, y): smooth, about 0.3 to 0.9.
float scene(int c, int x, int y) { return 0.6f + 0.2f * std::sin(0.17f * x + c) * std::cos(0.11f * y) + 0.01f * c; }

// An RGBA float layer of the scene as cropping tools write it with OpenEXR: the pixels of
// [x, x + w) x [y, y + h) as the data window, `display` as the display window.
void write_exr_layer(const std::string& path, const Imath::Box2i& display, int x, int y, int w, int h) {
  Imf::Header header(display, Imath::Box2i({x, y}, {x + w - 1, y + h - 1}));
  const char* names[] = {"R", "G", "B", "A"};
  for (const char* n : names) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
  std::vector<float> pixels(static_cast<std::size_t>(w) * h * 4);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      for (int c = 0; c < 4; ++c) pixels[(static_cast<std::size_t>(j) * w + i) * 4 + c] = c < 3 ? scene(c, x + i, y + j) : 1.0f;
  Imf::FrameBuffer frame;
  for (int c = 0; c < 4; ++c)
    frame.insert(names[c], Imf::Slice::Make(Imf::FLOAT, pixels.data() + c, Imath::V2i(x, y), std::int64_t{w},
                                            std::int64_t{h}, std::size_t{16}, std::size_t{16} * w));
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(frame);
  file.writePixels(h);
}

// Two agreeing layers in a display window that does not start at (0, 0): the canvas is the display
// window, each layer lies at its data window, and the output's windows say where it lies.
TEST_F(BlendExr, DataWindowsPlaceLayersInTheDisplayWindow) {
  const Imath::Box2i display({-10, 5}, {89, 44});  // 100 x 40: its last 10 columns no layer covers
  write_exr_layer(path("a.exr"), display, -10, 5, 60, 40);
  write_exr_layer(path("b.exr"), display, 30, 5, 50, 40);
  const BlendPlan plan = plan_blend({LayerSource{path("a.exr")}, LayerSource{path("b.exr")}}, {});
  ASSERT_EQ(plan.layers.size(), 2u);
  EXPECT_EQ(plan.layers[1].x, 30);
  EXPECT_EQ(plan.layers[1].y, 5);
  EXPECT_EQ(plan.canvas.x, -10);
  EXPECT_EQ(plan.canvas.y, 5);
  EXPECT_EQ(plan.canvas.width, 100);
  EXPECT_EQ(plan.canvas.height, 40);
  EXPECT_EQ(plan.sample_type, SampleType::Float);
  WriteOptions options;
  options.frame = frame_placement(plan);
  {
    ImageFileWriter out(path("out.exr"), 100, 40, 4, options);
    SolverOptions accurate;
    accurate.precision = Precision::Float64;
    accurate.tolerance = 1e-10;
    blend(plan, {}, accurate, out);
  }
  const auto w = io::exr_windows(path("out.exr"));
  ASSERT_TRUE(w.has_value());
  EXPECT_EQ(w->data_x, -10);
  EXPECT_EQ(w->data_y, 5);
  EXPECT_EQ(w->data_width, 100);
  EXPECT_EQ(w->display_x, -10);
  EXPECT_EQ(w->display_height, 40);
  const Image out = read_image(path("out.exr")).image;
  ASSERT_EQ(out.width, 100);
  double worst = 0.0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 100; ++x) {
      const bool covered = x < 90;  // a: canvas columns 0..59, b: 40..89
      ASSERT_EQ(out.at(3, x, y), covered ? 1.0f : 0.0f) << x << "," << y;
      if (covered) worst = std::max(worst, std::abs(double(out.at(1, x, y)) - scene(1, x - 10, y + 5)));
    }
  EXPECT_LT(worst, 1e-4);
  // gdp blend writes the same windows.
  const std::string cmd = std::string(GDP_CLI_PATH) + " blend -q -o " + path("cli.exr") + " " + path("a.exr") + " " +
                          path("b.exr");
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const auto cli = io::exr_windows(path("cli.exr"));
  ASSERT_TRUE(cli.has_value());
  EXPECT_EQ(cli->data_x, -10);
  EXPECT_EQ(cli->display_y, 5);
}

// -f crops: the output's data window is the cropped canvas, its display window still the layers'.
TEST_F(BlendExr, CroppedCanvasKeepsItsPlaceInTheFrame) {
  const Imath::Box2i display({0, 0}, {99, 59});
  write_exr_layer(path("a.exr"), display, 20, 10, 40, 30);
  BlendOptions crop;
  crop.canvas = CanvasRect{25, 15, 20, 10};
  const BlendPlan plan = plan_blend({LayerSource{path("a.exr")}}, crop);
  const auto f = frame_placement(plan);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->x, 25);
  EXPECT_EQ(f->y, 15);
  EXPECT_EQ(f->frame_width, 100);
  EXPECT_EQ(f->frame_height, 60);
  WriteOptions options;
  options.frame = f;
  {
    ImageFileWriter out(path("crop.exr"), 20, 10, 4, options);
    blend(plan, crop, {}, out);
  }
  const auto w = io::exr_windows(path("crop.exr"));
  ASSERT_TRUE(w.has_value());
  EXPECT_EQ(w->data_x, 25);
  EXPECT_EQ(w->data_y, 15);
  EXPECT_EQ(w->data_width, 20);
  EXPECT_EQ(w->display_width, 100);
  const Image out = read_image(path("crop.exr")).image;
  EXPECT_NEAR(out.at(0, 0, 0), scene(0, 25, 15), 1e-5);
  EXPECT_NEAR(out.at(2, 19, 9), scene(2, 44, 24), 1e-5);
}

}  // namespace
}  // namespace gdp
