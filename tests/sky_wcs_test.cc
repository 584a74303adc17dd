// Sky WCS (src/sky/wcs.h): pixel -> sky -> pixel round trips, pixel conventions, errors naming the file and keyword.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "gdp/errors.h"
#include "sky/header.h"
#include "sky/wcs.h"

namespace gdp::sky {
namespace {

std::string cards(const std::vector<std::pair<std::string, std::string>>& kv) {
  std::string h;
  for (const auto& [k, v] : kv) h += card(k, v);
  return h;
}

const std::vector<std::pair<std::string, std::string>> kTan = {
    {"CTYPE1", "'RA---TAN'"}, {"CTYPE2", "'DEC--TAN'"}, {"CRVAL1", "83.6"}, {"CRVAL2", "22.0"},
    {"CRPIX1", "140.5"}, {"CRPIX2", "90.25"}, {"CD1_1", "-2.1E-4"}, {"CD1_2", "0.6E-4"},
    {"CD2_1", "0.5E-4"}, {"CD2_2", "2.0E-4"}};

std::vector<std::pair<std::string, std::string>> with(std::vector<std::pair<std::string, std::string>> base,
                                                     const std::vector<std::pair<std::string, std::string>>& more) {
  base.insert(base.end(), more.begin(), more.end());
  return base;
}

TEST(SkyWcs, PixelToSkyToPixelRoundTripsWithin1e6Pixel) {
  const std::vector<std::pair<const char*, std::vector<std::pair<std::string, std::string>>>> headers = {
      {"TAN with CD", kTan},
      {"TAN-SIP",
       {{"CTYPE1", "'RA---TAN-SIP'"}, {"CTYPE2", "'DEC--TAN-SIP'"}, {"CRVAL1", "10.0"}, {"CRVAL2", "41.0"},
        {"CRPIX1", "150.0"}, {"CRPIX2", "100.0"}, {"CD1_1", "-1E-3"}, {"CD2_2", "1E-3"}, {"A_ORDER", "2"},
        {"B_ORDER", "2"}, {"A_2_0", "2E-5"}, {"A_1_1", "-1E-5"}, {"B_0_2", "1E-5"}, {"B_1_1", "2E-5"}}},
      {"TPV",
       {{"CTYPE1", "'RA---TPV'"}, {"CTYPE2", "'DEC--TPV'"}, {"CRVAL1", "150.1"}, {"CRVAL2", "2.2"},
        {"CRPIX1", "150.0"}, {"CRPIX2", "100.0"}, {"CD1_1", "-7E-5"}, {"CD2_2", "7E-5"}, {"PV1_1", "1.0"},
        {"PV1_4", "0.002"}, {"PV1_7", "0.05"}, {"PV2_1", "1.0"}, {"PV2_5", "-0.003"}}},
      {"ZEA at the pole",
       {{"CTYPE1", "'RA---ZEA'"}, {"CTYPE2", "'DEC--ZEA'"}, {"CRVAL1", "0.0"}, {"CRVAL2", "-90.0"},
        {"CRPIX1", "150.5"}, {"CRPIX2", "100.5"}, {"CDELT1", "-0.2"}, {"CDELT2", "0.2"}}},
      {"CAR with PC",
       {{"CTYPE1", "'RA---CAR'"}, {"CTYPE2", "'DEC--CAR'"}, {"CRVAL1", "30.0"}, {"CRVAL2", "0.0"},
        {"CRPIX1", "10.0"}, {"CRPIX2", "190.0"}, {"CDELT1", "-0.01"}, {"CDELT2", "0.01"}, {"PC1_1", "0.8"},
        {"PC1_2", "-0.6"}, {"PC2_1", "0.6"}, {"PC2_2", "0.8"}}},
  };
  for (const auto& [name, kv] : headers) {
    SCOPED_TRACE(name);
    const Wcs wcs(cards(kv), 300, 200, name);
    double worst = 0.0;
    for (double x = -0.5; x <= 300.5; x += 12.37)
      for (double y = -0.5; y <= 200.5; y += 9.91) {
        double lon = 0, lat = 0, bx = 0, by = 0;
        ASSERT_TRUE(wcs.pixel_to_sky(x, y, lon, lat)) << x << " " << y;
        ASSERT_TRUE(wcs.sky_to_pixel(lon, lat, bx, by)) << x << " " << y;
        worst = std::max(worst, std::hypot(bx - x, by - y));
      }
    EXPECT_LE(worst, 1e-6);
  }
}

TEST(SkyWcs, PixelsAreTopDownWithCentresAtHalfIntegers) {
  // CDELT2 > 0: Dec grows with FITS rows, so it falls down gdp's rows. FITS pixel (1, 1), the
  // centre of the bottom-left pixel, is gdp's (0.5, H - 0.5).
  const Wcs wcs(cards({{"CTYPE1", "'RA---CAR'"}, {"CTYPE2", "'DEC--CAR'"}, {"CRVAL1", "0.0"}, {"CRVAL2", "0.0"},
                       {"CRPIX1", "1.0"}, {"CRPIX2", "1.0"}, {"CDELT1", "-1.0"}, {"CDELT2", "1.0"}}),
                10, 20, "car");
  double lon = 1, lat = 1;
  ASSERT_TRUE(wcs.pixel_to_sky(0.5, 19.5, lon, lat));
  EXPECT_NEAR(lon, 0.0, 1e-12);
  EXPECT_NEAR(lat, 0.0, 1e-12);
  ASSERT_TRUE(wcs.pixel_to_sky(0.5, 0.5, lon, lat));
  EXPECT_NEAR(lat, 19.0, 1e-12);  // the top row
  ASSERT_TRUE(wcs.pixel_to_sky(2.5, 19.5, lon, lat));
  EXPECT_NEAR(lon, 358.0, 1e-12);  // RA grows to the left
  EXPECT_EQ(wcs.frame(), "RA");
  EXPECT_EQ(wcs.projection(), "CAR");
}

TEST(SkyWcs, PointsOutsideTheProjectionHaveNoPosition) {
  const Wcs wcs(cards({{"CTYPE1", "'RA---SIN'"}, {"CTYPE2", "'DEC--SIN'"}, {"CRVAL1", "0.0"}, {"CRVAL2", "0.0"},
                       {"CRPIX1", "50.5"}, {"CRPIX2", "50.5"}, {"CDELT1", "-2.0"}, {"CDELT2", "2.0"}}),
                100, 100, "sin");
  double lon = 0, lat = 0, x = 0, y = 0;
  EXPECT_FALSE(wcs.pixel_to_sky(0.0, 0.0, lon, lat)) << "a corner beyond the SIN disc";
  EXPECT_FALSE(wcs.sky_to_pixel(180.0, 0.0, x, y)) << "the far hemisphere";
  EXPECT_TRUE(wcs.sky_to_pixel(10.0, 5.0, x, y));
}

std::string error_of(const std::string& header) {
  try {
    Wcs wcs(header, 100, 100, "plate.fits");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SkyWcs, BadHeadersAreInputErrorsNamingTheFileAndTheProblem) {
  const std::string none = error_of(cards({{"BITPIX", "-32"}, {"OBJECT", "'M31'"}}));
  EXPECT_EQ(none.rfind("plate.fits: ", 0), 0u) << none;
  EXPECT_NE(none.find("no celestial WCS"), std::string::npos) << none;
  const std::string linear = error_of(cards({{"CTYPE1", "'X'"}, {"CTYPE2", "'Y'"}, {"CDELT1", "1.0"}}));
  EXPECT_NE(linear.find("no celestial WCS"), std::string::npos) << linear;
  const std::string bad = error_of(cards(with(kTan, {{"CTYPE1", "'RA---XYZ'"}, {"CTYPE2", "'DEC--XYZ'"}})));
  EXPECT_EQ(bad.rfind("plate.fits: ", 0), 0u) << bad;
  EXPECT_NE(bad.find("CTYPE"), std::string::npos) << bad;
  std::vector<std::pair<std::string, std::string>> singular = kTan;
  for (auto& [k, v] : singular)
    if (k == "CD2_1" || k == "CD2_2") v = k == "CD2_1" ? "-2.1E-4" : "0.6E-4";
  const std::string sing = error_of(cards(singular));
  EXPECT_NE(sing.find("singular"), std::string::npos) << sing;
}

TEST(SkyHeader, MontageTemplatesBecomeCardsAndTargetsParse) {
  const std::string text =
      "SIMPLE = T\nNAXIS1 = 300\nNAXIS2  =  200\nCTYPE1 = 'RA---TAN'\nCTYPE2 = 'DEC--TAN'\n"
      "CRVAL1 = 83.6 / centre\nCRVAL2 = 22.0\nCRPIX1 = 150.5\nCRPIX2 = 100.5\nCDELT1 = -0.001\n"
      "CDELT2 = 0.001\nEND\n";
  const std::string c = cards_from_text(text, "t.hdr");
  ASSERT_EQ(c.size() % 80, 0u);
  EXPECT_EQ(header_number(c, "NAXIS1").value_or(0), 300);
  EXPECT_EQ(header_number(c, "NAXIS2").value_or(0), 200);
  EXPECT_DOUBLE_EQ(header_number(c, "CRVAL1").value_or(0), 83.6);
  const Wcs from_template(c, 300, 200, "t.hdr");
  const Wcs made(target_header({{}, 83.6, 22.0, 300, 200, 0.001, "TAN"}), 300, 200, "made");
  double a = 0, b = 0, c1 = 0, d = 0;
  ASSERT_TRUE(from_template.pixel_to_sky(17.25, 33.5, a, b));
  ASSERT_TRUE(made.pixel_to_sky(17.25, 33.5, c1, d));
  EXPECT_NEAR(a, c1, 1e-12);
  EXPECT_NEAR(b, d, 1e-12);
  EXPECT_THROW(cards_from_text("NAXIS1 300\n", "bad.hdr"), InputError);
}

}  // namespace
}  // namespace gdp::sky
