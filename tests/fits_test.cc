// FITS through gdp's cfitsio codec: integer scaling and BLANK, orientation, cubes, header cards, writer round trips.
#include <fitsio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/image_stream.h"
#include "image_stream_util.h"
#include "io/fits_image.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

// Writes a FITS file with cfitsio directly: `values` in FITS order (row 1, the bottom, first),
// of cfitsio type `type` into an image of `bitpix`, then the extra integer/float keywords.
template <class T>
void write_fits(const fs::path& p, int bitpix, int type, std::vector<long> axes, std::vector<T> values,
                const std::vector<std::pair<const char*, double>>& keys = {}) {
  fitsfile* f = nullptr;
  int status = 0;
  const std::string name = "!" + p.string();
  fits_create_file(&f, name.c_str(), &status);
  ASSERT_EQ(status, 0) << io::fits_error(status);
  fits_create_img(f, bitpix, static_cast<int>(axes.size()), axes.data(), &status);
  for (const auto& [key, value] : keys) {
    double v = value;
    if (std::string(key) == "BLANK") {
      long blank = static_cast<long>(value);
      fits_update_key(f, TLONG, key, &blank, nullptr, &status);
    } else {
      fits_update_key(f, TDOUBLE, key, &v, nullptr, &status);
    }
  }
  long first[3] = {1, 1, 1};
  if (!values.empty()) {
    fits_set_bscale(f, 1.0, 0.0, &status);  // values are written raw, as stored on disk
    fits_write_pix(f, type, first, static_cast<LONGLONG>(values.size()), values.data(), &status);
  }
  fits_close_file(f, &status);
  ASSERT_EQ(status, 0) << io::fits_error(status);
}

class Fits : public test::TempDirTest {};

TEST_F(Fits, IntegersAreScaledByBscaleBzeroAndBlankIsNaN) {
  const fs::path p = dir_ / "int16.fits";
  // 3 x 2, FITS rows bottom first: raw -5, 0, 7 / 100, BLANK, -32767.
  write_fits<short>(p, SHORT_IMG, TSHORT, {3, 2}, {-5, 0, 7, 100, -32768, -32767},
                    {{"BSCALE", 0.5}, {"BZERO", 10.0}, {"BLANK", -32768}});
  const ReadResult r = read_image(p);
  ASSERT_EQ(r.image.width, 3);
  ASSERT_EQ(r.image.height, 2);
  EXPECT_EQ(r.info.format_name, "fits");
  EXPECT_EQ(r.info.sample_type, SampleType::Float);
  // gdp's row 0 is the top: FITS row 2.
  EXPECT_FLOAT_EQ(r.image.at(0, 0, 0), 10.0f + 0.5f * 100);
  EXPECT_TRUE(std::isnan(r.image.at(0, 1, 0))) << "BLANK";
  EXPECT_FLOAT_EQ(r.image.at(0, 2, 0), 10.0f + 0.5f * -32767);
  EXPECT_FLOAT_EQ(r.image.at(0, 0, 1), 10.0f - 2.5f);
  EXPECT_FLOAT_EQ(r.image.at(0, 1, 1), 10.0f);
  EXPECT_FLOAT_EQ(r.image.at(0, 2, 1), 13.5f);
}

TEST_F(Fits, EveryBitpixReadsItsValues) {
  const std::vector<double> want = {-3.0, 0.0, 2.5, 1e6, 255.0, 7.0};  // bottom row first
  const auto check = [&](const fs::path& p, double scale) {
    const Image image = read_image(p).image;
    ASSERT_EQ(image.data.size(), want.size());
    for (int k = 0; k < 6; ++k)
      EXPECT_DOUBLE_EQ(image.at(0, k % 3, 1 - k / 3), static_cast<float>(want[k] * scale)) << p << " " << k;
  };
  write_fits<unsigned char>(dir_ / "u8.fits", BYTE_IMG, TBYTE, {3, 2}, {1, 0, 5, 200, 255, 7}, {{"BZERO", -4.0}});
  const Image u8 = read_image(dir_ / "u8.fits").image;
  EXPECT_FLOAT_EQ(u8.at(0, 0, 1), -3.0f);  // 1 - 4: unsigned bytes with an offset, not fractions of 255
  EXPECT_FLOAT_EQ(u8.at(0, 1, 0), 251.0f);
  write_fits<int>(dir_ / "i32.fits", LONG_IMG, TINT, {3, 2}, {-6, 0, 5, 2000000, 510, 14}, {{"BSCALE", 0.5}});
  check(dir_ / "i32.fits", 1.0);
  write_fits<float>(dir_ / "f32.fits", FLOAT_IMG, TFLOAT, {3, 2}, {-3.0f, 0.0f, 2.5f, 1e6f, 255.0f, 7.0f});
  check(dir_ / "f32.fits", 1.0);
  write_fits<double>(dir_ / "f64.fits", DOUBLE_IMG, TDOUBLE, {3, 2}, want);
  check(dir_ / "f64.fits", 1.0);
  EXPECT_EQ(read_image(dir_ / "f64.fits").info.sample_type, SampleType::Double);
}

TEST_F(Fits, NaNFloatsStayNaN) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  write_fits<float>(dir_ / "nan.fits", FLOAT_IMG, TFLOAT, {2, 1}, {nan, 1.0f});
  const Image image = read_image(dir_ / "nan.fits").image;
  EXPECT_TRUE(std::isnan(image.at(0, 0, 0)));
  EXPECT_EQ(image.at(0, 1, 0), 1.0f);
}

TEST_F(Fits, CubesGiveTheirFirstPlaneOrAnyPlaneThroughFitsImage) {
  std::vector<float> v(2 * 2 * 5);
  for (std::size_t k = 0; k < v.size(); ++k) v[k] = static_cast<float>(k);
  write_fits<float>(dir_ / "cube.fits", FLOAT_IMG, TFLOAT, {2, 2, 5}, v);
  const Image image = read_image(dir_ / "cube.fits").image;
  ASSERT_EQ(image.channels, 1);
  EXPECT_EQ(image.at(0, 1, 1), 1.0f);  // bottom row, second column, plane 1
  io::FitsImage cube((dir_ / "cube.fits").string());
  EXPECT_EQ(cube.planes(), 5);
  float row[2];
  cube.read(3, 0, 1, 0, 2, row);  // top row of plane 4
  EXPECT_EQ(row[0], 14.0f);
  EXPECT_EQ(row[1], 15.0f);
}

TEST_F(Fits, WriterRoundTripsChannelsNaNColumnWindowsAndHeaderCards) {
  Image image(37, 1200, 3);  // several bands
  for (std::size_t k = 0; k < image.data.size(); ++k) image.data[k] = static_cast<float>(std::sin(0.37 * k) * 1e3);
  image.at(1, 5, 7) = std::numeric_limits<float>::quiet_NaN();
  WriteOptions options;
  char card[81];
  std::snprintf(card, sizeof card, "%-80s", "CTYPE1  = 'RA---TAN'           / a card from the caller");
  options.fits_header = card;
  const fs::path p = dir_ / "out.fits";
  {
    ImageFileWriter writer(p, image.width, image.height, image.channels, options);
    std::vector<float> row(static_cast<std::size_t>(image.width) * image.channels);
    for (int y = 0; y < image.height; ++y) {
      for (int c = 0; c < image.channels; ++c)
        std::copy_n(image.row(c, y).begin(), image.width, row.begin() + c * image.width);
      writer.write_row(y, row);
    }
    writer.commit();
  }
  const Image back = read_image(p).image;
  ASSERT_EQ(back.channels, 3);
  for (std::size_t k = 0; k < image.data.size(); ++k) {
    if (std::isnan(image.data[k])) EXPECT_TRUE(std::isnan(back.data[k]));
    else ASSERT_EQ(back.data[k], image.data[k]) << k;
  }
  io::FitsImage fits(p.string());
  EXPECT_NE(fits.header().find("CTYPE1  = 'RA---TAN'"), std::string::npos);
  ImageFileReader window(p, true, ColumnRange{10, 20});
  std::vector<float> row(30);
  for (int y = 0; y < 3; ++y) window.read_row(y, row);
  EXPECT_EQ(row[0], image.at(0, 10, 2));
  EXPECT_EQ(row[19], image.at(1, 19, 2));
  EXPECT_EQ(names().size(), 1u) << "no temporary file is left";
}

TEST_F(Fits, NotAnImageIsAnInputErrorNamingTheFile) {
  write_fits<float>(dir_ / "empty.fits", FLOAT_IMG, TFLOAT, {}, std::vector<float>{});
  try {
    read_image(dir_ / "empty.fits");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("empty.fits"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gdp
