// gdp sky --hips: tile pixels are the HEALPix pixels the standard says, the pyramid averages, properties and Moc.fits.
#include <gtest/gtest.h>

#include <fitsio.h>
#include <healpix_base.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "cli_fixture.h"
#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "gdp/sphere.h"
#include "io/fits_image.h"
#include "sky/header.h"
#include "sky/hips_files.h"
#include "sky/hips_geometry.h"
#include "sky/hips_output.h"
#include "sky/reproject.h"
#include "sky/wcs.h"

namespace gdp {
namespace {

namespace fs = std::filesystem;

// A smooth sky: linear in the direction, so no two pixels of a tile (or of its mirror image) agree.
double sky_value(const sphere::Vec3& d) { return 0.3 * d.x + 0.5 * d.y + 0.7 * d.z; }

// The whole PQ sphere of height H with sky_value at every pixel centre; NaN where `keep` is false.
template <class Keep>
Image pq_sky(int H, Keep keep) {
  Image pq(4 * H, H, 1);
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < 4 * H; ++i) {
      const sphere::Vec3 d = sphere::pq_pixel_direction(sphere::SquareMap::Toast, H, i, j);
      pq.at(0, i, j) = keep(d) ? static_cast<float>(sky_value(d)) : std::numeric_limits<float>::quiet_NaN();
    }
  return pq;
}

// Nested sub-index of tile pixel (column c, row r from the top): r in the even bits, c in the odd.
std::int64_t interleave(int r, int c) {
  std::int64_t v = 0;
  for (int b = 0; b < 16; ++b) v |= (std::int64_t((r >> b) & 1) << (2 * b)) | (std::int64_t((c >> b) & 1) << (2 * b + 1));
  return v;
}

// Largest |tile value - sky_value| over a tile's finite pixels, the pixel directions from HEALPix
// (nested index npix * w^2 + interleave(r, c), or interleave(c, r) when `mirrored`).
double tile_error(const Image& tile, int order, std::int64_t npix, bool mirrored) {
  const int w = tile.width;
  const T_Healpix_Base<int64> pixels(order + static_cast<int>(std::log2(w)), NEST);
  double worst = 0.0;
  for (int r = 0; r < w; ++r)
    for (int c = 0; c < w; ++c) {
      const float v = tile.at(0, c, r);
      if (!std::isfinite(v)) continue;
      const vec3 d = pixels.pix2vec(npix * w * w + (mirrored ? interleave(c, r) : interleave(r, c)));
      worst = std::max(worst, std::abs(v - sky_value({d.x, d.y, d.z})));
    }
  return worst;
}

class SkyHips : public test::CliFixture {};

TEST_F(SkyHips, TilePixelsAreTheHealpixPixelsOfTheStandardAtEveryOrder) {
  // H = 64: HEALPix pixels of order 6 (hips_pixel_order), tiles of 16 -> deepest order 2.
  const int H = 64;
  ASSERT_EQ(sky::hips_pixel_order(H), 6);
  const Image pq = pq_sky(H, [](const sphere::Vec3&) { return true; });
  const auto s = sky::write_sky_hips(pq, sky::whole_pq(H), "RA", path("hips"), {16, "test"});
  EXPECT_EQ(s.order, 2);
  EXPECT_EQ(s.deepest_tiles, 192);          // the whole sky
  EXPECT_EQ(s.tiles, 192 + 48 + 12);
  for (int order = 0; order <= 2; ++order) {
    double worst = 0.0, worst_mirrored = 0.0;
    for (std::int64_t npix = 0; npix < (12 << (2 * order)); ++npix) {
      const Image tile = read_image(path("hips") / sky::hips_tile_stem(order, npix).concat(".fits")).image;
      ASSERT_EQ(tile.width, 16);
      worst = std::max(worst, tile_error(tile, order, npix, false));
      worst_mirrored = std::max(worst_mirrored, tile_error(tile, order, npix, true));
    }
    // Bilinear on the PQ grid (1.4 degree pixels = 0.025 rad; |gradient| <= 0.91) is within half a
    // PQ pixel's step (0.011); a parent pixel is the mean of the four child pixels around its centre.
    EXPECT_LT(worst, 0.012) << "order " << order;
    EXPECT_GT(worst_mirrored, 0.1) << "order " << order << ": the test must tell the mirrored tile";
    std::printf("order %d: worst %.4f, mirrored %.4f\n", order, worst, worst_mirrored);
  }
}

TEST_F(SkyHips, Tile0Of7MatchesTheStandardsHpxWcs) {
  // HiPS 1.0's example: the WCS of tile order 0, npix 7, 512 pixels is RA---HPX with CD = +-45/512
  // and CRPIX = -255.5; for width w, 45/w and (1 - w)/2.
  const int H = 16, w = 16;
  const Image pq = pq_sky(H, [](const sphere::Vec3&) { return true; });
  const auto s = sky::write_sky_hips(pq, sky::whole_pq(H), "RA", path("hips"), {w, "test"});
  ASSERT_EQ(s.order, 0);
  const Image tile = read_image(path("hips/Norder0/Dir0/Npix7.fits")).image;
  const double cd = 45.0 / w, crpix = (1.0 - w) / 2.0;
  std::string cards;
  for (const std::string& c : {fmt::format("CTYPE1  = 'RA---HPX'"), fmt::format("CTYPE2  = 'DEC--HPX'"),
                               fmt::format("CRPIX1  = {}", crpix), fmt::format("CRPIX2  = {}", crpix),
                               std::string("CRVAL1  = 0.0"), std::string("CRVAL2  = 0.0"),
                               fmt::format("CD1_1   = {}", -cd), fmt::format("CD1_2   = {}", -cd),
                               fmt::format("CD2_1   = {}", cd), fmt::format("CD2_2   = {}", -cd),
                               std::string("PV2_1   = 4"), std::string("PV2_2   = 3")})
    cards += fmt::format("{:<80}", c);
  const sky::Wcs hpx(cards, w, w, "the standard's tile 0/7");
  const sky::HipsGeometry geometry(0, w);
  std::vector<sphere::Vec3> dirs;
  geometry.tile_directions(7, dirs);
  double worst_angle = 0.0, worst_value = 0.0;
  for (int r = 0; r < w; ++r)
    for (int c = 0; c < w; ++c) {
      double lon = 0, lat = 0;
      ASSERT_TRUE(hpx.pixel_to_sky(c + 0.5, r + 0.5, lon, lat));
      const sphere::Vec3 d = sky::direction(lon, lat), g = dirs[static_cast<std::size_t>(r) * w + c];
      worst_angle = std::max(worst_angle, std::acos(std::min(1.0, d.x * g.x + d.y * g.y + d.z * g.z)));
      worst_value = std::max(worst_value, std::abs(tile.at(0, c, r) - sky_value(d)));
    }
  EXPECT_LT(worst_angle, 1e-6);  // radians; the pixels are 3.7 degrees
  EXPECT_LT(worst_value, 0.05);  // PQ pixels of 5.6 degrees (0.098 rad), half a step 0.045
  // The tile's own header carries that WCS (the enabler), CRPIX exactly the standard's.
  const std::string written = io::FitsImage(path("hips/Norder0/Dir0/Npix7.fits")).header();
  EXPECT_EQ(sky::header_number(written, "CRPIX1"), crpix);
  EXPECT_EQ(sky::header_number(written, "CRPIX2"), crpix);
  EXPECT_EQ(sky::header_number(written, "CD2_1"), cd);
  EXPECT_EQ(sky::header_number(written, "CD1_1"), -cd);
}

// Every FITS tile of every order, in both frames, carries an HPX WCS that puts each pixel centre at
// its HEALPix pixel's direction (1e-10 rad); base pixel 6 too (CRVAL1 180 there: HPX cuts it at 180 otherwise).
TEST_F(SkyHips, EveryFitsTileCarriesItsHpxWcs) {
  const int H = 64, w = 16;
  const Image pq = pq_sky(H, [](const sphere::Vec3&) { return true; });
  for (const char* frame : {"RA", "GLON"}) {
    const fs::path dir = path(std::string("hips-") + frame);
    const auto s = sky::write_sky_hips(pq, sky::whole_pq(H), frame, dir, {w, "test"});
    ASSERT_EQ(s.order, 2);
    std::vector<sphere::Vec3> dirs;
    double worst = 0.0;
    int tiles = 0;
    for (int order = 0; order <= 2; ++order) {
      const sky::HipsGeometry geometry(order, w);
      for (std::int64_t npix = 0; npix < (12 << (2 * order)); ++npix) {
        const fs::path file = dir / sky::hips_tile_stem(order, npix).concat(".fits");
        const sky::Wcs wcs(io::FitsImage(file).header(), w, w, file.string());
        EXPECT_EQ(wcs.frame(), frame);
        geometry.tile_directions(npix, dirs);
        for (int r = 0; r < w; ++r)
          for (int c = 0; c < w; ++c) {
            double lon = 0, lat = 0;
            ASSERT_TRUE(wcs.pixel_to_sky(c + 0.5, r + 0.5, lon, lat)) << file << " pixel " << c << ", " << r;
            const sphere::Vec3 d = sky::direction(lon, lat), g = dirs[static_cast<std::size_t>(r) * w + c];
            worst = std::max(worst, std::hypot(d.x - g.x, d.y - g.y, d.z - g.z));  // chord ~ angle
          }
        ++tiles;
      }
    }
    EXPECT_EQ(tiles, 252);
    EXPECT_LT(worst, 1e-10) << frame;  // radians
  }
}

// Reads Moc.fits with cfitsio: its keywords and NUNIQ cells.
std::vector<long long> read_moc(const fs::path& file, std::map<std::string, std::string>& keys) {
  fitsfile* f = nullptr;
  int status = 0, type = 0;
  fits_open_file(&f, file.c_str(), READONLY, &status);
  fits_movabs_hdu(f, 2, &type, &status);
  EXPECT_EQ(type, BINARY_TBL);
  for (const char* k : {"PIXTYPE", "ORDERING", "COORDSYS", "MOCORDER", "TTYPE1", "TFORM1", "MOCDIM"}) {
    char value[FLEN_VALUE] = "";
    int s = 0;
    fits_read_keyword(f, k, value, nullptr, &s);
    keys[k] = value;
  }
  long rows = 0;
  fits_get_num_rows(f, &rows, &status);
  std::vector<long long> uniq(rows);
  if (rows) fits_read_col(f, TLONGLONG, 1, 1, 1, rows, nullptr, uniq.data(), nullptr, &status);
  fits_close_file(f, &status);
  EXPECT_EQ(status, 0);
  return uniq;
}

TEST_F(SkyHips, OnlyTilesWithDataAreWrittenAndTheMocIsThem) {
  // Data on a cap around (RA 30, Dec 50) of 12 degrees radius.
  const int H = 64, w = 16;
  const sphere::Vec3 centre = sky::direction(30.0, 50.0);
  const auto keep = [&](const sphere::Vec3& d) { return d.x * centre.x + d.y * centre.y + d.z * centre.z > std::cos(0.21); };
  const Image pq = pq_sky(H, keep);
  const auto s = sky::write_sky_hips(pq, sky::whole_pq(H), "RA", path("hips"), {w, "cap"});
  ASSERT_EQ(s.order, 2);
  // Brute force: every tile of order 2 sampled as the writer samples (bilinear on the PQ).
  const sky::PqStore store(pq, sky::whole_pq(H));
  sky::PqSampler sampler(store);
  const sky::HipsGeometry geometry(2, w);
  std::set<long long> with_data, written;
  std::vector<sphere::Vec3> dirs;
  for (std::int64_t npix = 0; npix < 192; ++npix) {
    geometry.tile_directions(npix, dirs);
    for (const sphere::Vec3& d : dirs)
      if (std::isfinite(sampler.at(d))) with_data.insert(npix);
    if (fs::exists(path("hips") / sky::hips_tile_stem(2, npix).concat(".fits"))) written.insert(npix);
  }
  EXPECT_FALSE(with_data.empty());
  EXPECT_LT(with_data.size(), 30u);
  EXPECT_EQ(written, with_data);
  // PNG alpha is where the FITS tile has data.
  const std::int64_t some = *written.begin();
  const Image fits = read_image(path("hips") / sky::hips_tile_stem(2, some).concat(".fits")).image;
  const Image png = read_image(path("hips") / sky::hips_tile_stem(2, some).concat(".png")).image;
  ASSERT_EQ(png.channels, 2);
  for (std::size_t k = 0; k < fits.plane_size(); ++k)
    EXPECT_EQ(png.data[png.plane_size() + k] > 0.5f, std::isfinite(fits.data[k])) << k;
  // Moc.fits: a valid MOC whose cells, expanded to order 2, are exactly the tiles written.
  std::map<std::string, std::string> keys;
  const std::vector<long long> uniq = read_moc(path("hips/Moc.fits"), keys);
  EXPECT_EQ(keys["PIXTYPE"], "'HEALPIX '");
  EXPECT_EQ(keys["ORDERING"], "'NUNIQ   '");
  EXPECT_EQ(keys["COORDSYS"], "'C       '");
  EXPECT_EQ(keys["MOCORDER"], "2");
  EXPECT_EQ(keys["TTYPE1"], "'UNIQ    '");
  EXPECT_EQ(keys["TFORM1"], "'1J      '");
  std::set<long long> covered;
  for (const long long u : uniq) {
    int k = 0;
    while ((4LL << (2 * (k + 1))) <= u) ++k;
    const long long npix = u - (4LL << (2 * k));
    for (long long m = 0; m < (1LL << (2 * (2 - k))); ++m) covered.insert((npix << (2 * (2 - k))) + m);
  }
  EXPECT_EQ(covered, written);
  // Lower orders hold the parents of what is written, Allsky and properties are there.
  for (const long long t : written) EXPECT_TRUE(fs::exists(path("hips") / sky::hips_tile_stem(0, t >> 4).concat(".png")));
  EXPECT_TRUE(fs::exists(path("hips/Norder2/Allsky.fits")));
  EXPECT_TRUE(fs::exists(path("hips/Norder2/Allsky.png")));
  std::ifstream in(path("hips/properties"));
  std::map<std::string, std::string> props;
  for (std::string line; std::getline(in, line);) {
    const auto eq = line.find('=');
    if (line.empty() || line[0] == '#' || eq == std::string::npos) continue;
    const auto trim = [](std::string t) {
      t.erase(0, t.find_first_not_of(' '));
      return t.erase(t.find_last_not_of(' ') + 1);
    };
    props[trim(line.substr(0, eq))] = trim(line.substr(eq + 1));
  }
  for (const char* k : {"creator_did", "obs_title", "dataproduct_type", "hips_version", "hips_release_date", "hips_status",
                        "hips_tile_format", "hips_order", "hips_frame", "hips_tile_width",
                        "hips_pixel_bitpix", "data_pixel_bitpix", "hips_pixel_cut", "hips_data_range",
                        "hips_initial_ra", "hips_initial_dec", "hips_initial_fov", "moc_sky_fraction"})
    EXPECT_TRUE(props.count(k)) << k;
  // The data range is the PQ image's finite extremes, around the display cut.
  float lo = INFINITY, hi = -INFINITY;
  for (const float v : pq.data)
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  double range[2] = {0, 0}, cut[2] = {0, 0};
  std::istringstream(props["hips_data_range"]) >> range[0] >> range[1];
  std::istringstream(props["hips_pixel_cut"]) >> cut[0] >> cut[1];
  EXPECT_NEAR(range[0], lo, 1e-6);
  EXPECT_NEAR(range[1], hi, 1e-6);
  EXPECT_LE(range[0], cut[0]);
  EXPECT_LT(cut[0], cut[1]);
  EXPECT_LE(cut[1], range[1]);
  EXPECT_EQ(props["data_pixel_bitpix"], "-32");
  EXPECT_FALSE(props.count("hips_order_min")) << "not a HiPS 1.0 keyword (Aladin's LINT: unreferenced); orders start at 0";
  EXPECT_EQ(props["hips_order"], "2");
  EXPECT_EQ(props["hips_frame"], "equatorial");
  EXPECT_EQ(props["dataproduct_type"], "image");
  EXPECT_EQ(props["hips_version"], "1.4");
  EXPECT_NEAR(std::stod(props["hips_initial_ra"]), 30.0, 1.0);
  EXPECT_NEAR(std::stod(props["hips_initial_dec"]), 50.0, 2.0);  // the mean of PQ pixel directions
}

TEST_F(SkyHips, RefusesWhatItCannotWrite) {
  EXPECT_NO_THROW(sky::check_hips_output(path("new"), {512, ""}, "RA"));
  EXPECT_NO_THROW(sky::check_hips_output(path("new"), {16, ""}, "GLON"));
  EXPECT_THROW(sky::check_hips_output(path("new"), {512, ""}, "ELON"), UsageError);  // no MOC frame for it
  EXPECT_THROW(sky::check_hips_output(path("new"), {100, ""}, "RA"), UsageError);
  EXPECT_THROW(sky::check_hips_output(path("new"), {4, ""}, "RA"), UsageError);
  fs::create_directories(path("full"));
  std::ofstream(path("full/file")) << "x";
  EXPECT_THROW(sky::check_hips_output(path("full"), {512, ""}, "RA"), UsageError);
}

TEST_F(SkyHips, CommandLine) {
  Image image(24, 24, 1);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 24; ++x) image.at(0, x, y) = 1.0f + x / 24.0f;
  WriteOptions options;
  options.fits_header = sky::target_header({{}, 120.0, -30.0, 24, 24, 0.5, "TAN"});
  write_image(path("a.fits"), image, options);
  const std::string run = "sky " + path("a.fits") + " --center 120,-30 --size 20,20 --scale 0.5 -o " + path("out.fits");
  const test::CliRun r = gdp(run + " --hips " + path("hips") + " --hips-tile 16 --pq-height 64 --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(path("hips/properties")));
  EXPECT_TRUE(fs::exists(path("hips/Moc.fits")));
  EXPECT_TRUE(fs::exists(path("hips/Norder2/Allsky.png")));
  // The plate's centre is in a written tile of the deepest order, with about the plate's value there.
  const std::int64_t t = sky::HipsGeometry(2, 16).tile_of(sky::direction(120.0, -30.0));
  const Image tile = read_image(path("hips") / sky::hips_tile_stem(2, t).concat(".fits")).image;
  int finite = 0;
  for (const float v : tile.data) finite += std::isfinite(v);
  EXPECT_GT(finite, 0);
  fs::remove(path("out.fits"));
  expect_failure(run + " --hips " + path("h2") + " --hips-tile 100", "--hips-tile 100");
  expect_failure(run + " --hips " + path("a.fits"), "a.fits: exists and is not an empty directory");
}

}  // namespace
}  // namespace gdp
