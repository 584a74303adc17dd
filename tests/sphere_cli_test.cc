// `gdp sphere`: round trips through the command line, and errors (one line, exit 2, no output).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "gdp/image_io.h"
#include "gdp/sphere.h"

namespace fs = std::filesystem;

namespace gdp {
namespace {

class SphereCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("gdp_sphere_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    Image er(128, 64, 3);
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 128; ++x)
        for (int c = 0; c < 3; ++c) {  // smooth on the sphere (continuous at the poles and the seam)
          const sphere::Vec3 d = sphere::equirect_direction(128, 64, x + 0.5, y + 0.5);
          er.at(c, x, y) = static_cast<float>(0.5 + 0.3 * d.x * (c + 1) / 3 + 0.15 * std::sin(3 * d.y) - 0.1 * d.z * d.z);
        }
    write_image(path("er.png"), er, {});
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  int gdp(const std::string& args, std::string* err = nullptr) const {
    const std::string e = path("stderr.txt");
    const int status = std::system((std::string(GDP_CLI_PATH) + " " + args + " 2> " + e + " > /dev/null").c_str());
    if (err) {
      std::ifstream f(e);
      err->assign(std::istreambuf_iterator<char>(f), {});
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  fs::path dir_;
};

TEST_F(SphereCli, ToPqFromPqAndToast) {
  ASSERT_EQ(gdp("sphere to-pq " + path("er.png") + " -o " + path("pq.png") + " -q"), 0);
  const Image pq = read_image(path("pq.png")).image;
  EXPECT_EQ(pq.height, 44);  // sqrt(128 * 64 / 4) = 45.3 -> 11 * 2^2
  EXPECT_EQ(pq.width, 4 * 44);
  ASSERT_EQ(gdp("sphere from-pq " + path("pq.png") + " -o " + path("back.png") + " --format equirect --width 128 -q"),
            0);
  const Image er = read_image(path("er.png")).image, back = read_image(path("back.png")).image;
  double err = 0.0;
  for (std::size_t k = 0; k < er.data.size(); ++k) err = std::max(err, double(std::abs(er.data[k] - back.data[k])));
  EXPECT_LT(err, 0.02);  // 8-bit files, interpolation twice
  ASSERT_EQ(gdp("sphere from-pq " + path("pq.png") + " -o " + path("cube.png") + " --format cube -q"), 0);
  const Image cube = read_image(path("cube.png")).image;
  EXPECT_EQ(cube.height, 6 * cube.width);
  ASSERT_EQ(gdp("sphere to-pq " + path("er.png") + " -o " + path("t.png") + " --height 128 --nearest -q"), 0);
  ASSERT_EQ(gdp("sphere toast " + path("t.png") + " -o " + path("tiles") + " -q"), 0);
  EXPECT_TRUE(fs::exists(path("tiles/0/0/0_0.png")));
  EXPECT_TRUE(fs::exists(path("tiles/toast.wtml")));
}

TEST_F(SphereCli, ErrorsAreOneLineWithNoOutput) {
  std::string err;
  EXPECT_EQ(gdp("sphere from-pq " + path("er.png") + " -o " + path("x.png") + " --format equirect", &err), 2);
  EXPECT_NE(err.find("er.png"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_EQ(gdp("sphere to-pq " + path("missing.png") + " -o " + path("x.png"), &err), 2);
  EXPECT_NE(err.find("missing.png"), std::string::npos) << err;
  EXPECT_EQ(gdp("sphere toast " + path("er.png") + " -o " + path("tiles"), &err), 2);
  EXPECT_NE(err.find("er.png"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(path("x.png")));
  EXPECT_FALSE(fs::exists(path("tiles")));
  for (const auto& e : fs::directory_iterator(dir_)) {
    const std::string name = e.path().filename().string();
    EXPECT_TRUE(name == "er.png" || name == "stderr.txt") << "left behind: " << name;
  }
}

}  // namespace
}  // namespace gdp
