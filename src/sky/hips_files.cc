// HiPS files: tiles through gdp's FITS and PNG writers, the properties text, Moc.fits with cfitsio, Allsky.
#include "sky/hips_files.h"

#include <fitsio.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <limits>

#include <fmt/format.h>

#include "gdp/errors.h"
#include "gdp/image_io.h"
#include "io/fits_image.h"

namespace gdp::sky {

namespace fs = std::filesystem;

namespace {

// `stem`.fits (the values, `cards` in its header) and `stem`.png (grey + alpha).
void write_pair(const fs::path& stem, const Image& values, const HipsFormat& format, const std::string& cards = {}) {
  fs::create_directories(stem.parent_path());
  WriteOptions fits;
  fits.fits_header = cards;
  write_image(fs::path(stem).concat(".fits"), values, fits);
  Image png(values.width, values.height, 2);
  const float scale = 1.0f / (format.hi - format.lo);
  for (std::size_t k = 0; k < values.plane_size(); ++k) {
    const float v = values.data[k];
    const bool data = std::isfinite(v);
    png.data[k] = data ? std::clamp((v - format.lo) * scale, 0.0f, 1.0f) : 0.0f;
    png.data[values.plane_size() + k] = data ? 1.0f : 0.0f;
  }
  write_image(fs::path(stem).concat(".png"), png, WriteOptions{});
}

std::string utc_now() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%MZ", &tm);
  return text;
}

// Cells of a normalised MOC: every complete group of four merged into its parent, recursively.
std::vector<std::int64_t> moc_cells(int order, std::vector<std::int64_t> level) {
  std::vector<std::int64_t> uniq;
  for (int k = order; k >= 0; --k) {
    std::vector<std::int64_t> parents;
    for (std::size_t i = 0; i < level.size();) {
      const std::int64_t parent = level[i] >> 2;
      std::size_t j = i;
      while (j < level.size() && (level[j] >> 2) == parent) ++j;
      if (j - i == 4 && k > 0) {
        parents.push_back(parent);
      } else {
        for (std::size_t m = i; m < j; ++m) uniq.push_back((std::int64_t{4} << (2 * k)) + level[m]);
      }
      i = j;
    }
    level = std::move(parents);
  }
  std::sort(uniq.begin(), uniq.end());
  return uniq;
}

}  // namespace

fs::path hips_tile_stem(int order, std::int64_t npix) {
  return fs::path(fmt::format("Norder{}", order)) / fmt::format("Dir{}", npix / 10000 * 10000) /
         fmt::format("Npix{}", npix);
}

void write_hips_tile(const fs::path& root, const HipsFormat& format, int order, std::int64_t npix, const Image& tile,
                     const std::string& cards) {
  write_pair(root / hips_tile_stem(order, npix), tile, format, cards);
}

void write_hips_properties(const fs::path& file, const HipsFormat& f, const HipsProperties& p) {
  const std::string now = utc_now();
  std::ofstream out(file);
  out << "# HiPS made by gdp sky (docs/sky.md)\n"
      << "creator_did          = ivo://gdp/P/sky/" << f.frame << "\n"
      << "obs_title            = " << p.title << "\n";
  if (!p.description.empty()) out << "obs_description      = " << p.description << "\n";
  if (!p.progenitor.empty()) out << "prov_progenitor      = " << p.progenitor << "\n";
  out << "dataproduct_type     = image\n"
      << "hips_version         = 1.4\n"
      << "hips_builder         = gdp sky\n"
      << "hips_creation_date   = " << now << "\n"
      << "hips_release_date    = " << now << "\n"
      << "hips_status          = private master unclonable\n"
      << "hips_frame           = " << f.frame << "\n"
      << "hips_order           = " << f.order << "\n"
      << "hips_tile_width      = " << f.width << "\n"
      << "hips_tile_format     = png fits\n"
      << "hips_pixel_bitpix    = -32\n"
      << "data_pixel_bitpix    = -32\n"  // gdp reads every plate as floats (physical values after BSCALE/BZERO)
      << fmt::format("hips_pixel_cut       = {:.9g} {:.9g}\n", f.lo, f.hi)
      << fmt::format("hips_data_range      = {:.9g} {:.9g}\n", f.min, f.max)
      << fmt::format("hips_pixel_scale     = {:.9g}\n", 180.0 / M_PI * std::sqrt(M_PI / 3.0) / f.width / std::ldexp(1.0, f.order))
      << "hips_sampling        = bilinear\n"
      << fmt::format("hips_initial_ra      = {:.9g}\n", p.ra)
      << fmt::format("hips_initial_dec     = {:.9g}\n", p.dec)
      << fmt::format("hips_initial_fov     = {:.9g}\n", p.fov)
      << "hips_nb_tiles        = " << p.tiles << "\n"
      << fmt::format("moc_sky_fraction     = {:.9g}\n", p.sky_fraction);
  if (!out.flush()) throw OutputError(file.string() + ": cannot write the HiPS properties");
}

std::vector<std::int64_t> write_moc(const fs::path& file, int order, const std::vector<std::int64_t>& tiles) {
  std::vector<std::int64_t> uniq = moc_cells(order, tiles);
  std::vector<long long> column(uniq.begin(), uniq.end());
  fitsfile* f = nullptr;
  int status = 0;
  const std::string name = fmt::format("!{}", file.string());  // "!": CFITSIO overwrites the file
  char ttype[] = "UNIQ", tform_j[] = "1J", tform_k[] = "1K";
  char* types[] = {ttype};
  char* forms[] = {order <= 13 ? tform_j : tform_k};
  fits_create_file(&f, name.c_str(), &status);
  fits_create_tbl(f, BINARY_TBL, static_cast<LONGLONG>(column.size()), 1, types, forms, nullptr, "COVERAGE", &status);
  const auto key = [&](const char* k, const char* v, const char* comment) {
    fits_write_key_str(f, k, v, comment, &status);
  };
  key("PIXTYPE", "HEALPIX", "HEALPix tessellation");
  key("ORDERING", "NUNIQ", "NUNIQ coding: 4 * 4^order + npix");
  key("COORDSYS", "C", "ICRS (MOC 1.1 and 2.0 space MOCs)");
  int moc_order = order;
  fits_write_key_lng(f, "MOCORDER", moc_order, "MOC resolution (best order)", &status);
  key("MOCVERS", "2.0", "MOC version");
  key("MOCDIM", "SPACE", "spatial MOC");
  fits_write_key_lng(f, "MOCORD_S", moc_order, "MOC resolution (best order)", &status);
  key("MOCTOOL", "gdp sky", "");
  key("MOCTYPE", "IMAGE", "coverage of an image HiPS");
  if (!column.empty()) fits_write_col(f, TLONGLONG, 1, 1, 1, static_cast<LONGLONG>(column.size()), column.data(), &status);
  if (f) fits_close_file(f, &status);
  if (status) throw OutputError(file.string() + ": cannot write the MOC: " + io::fits_error(status));
  return uniq;
}

HipsAllsky::HipsAllsky(int order, int width)
    : order_(order),
      width_(width),
      small_(std::min(64, width)),
      cols_(static_cast<int>(std::sqrt(12.0 * std::ldexp(1.0, 2 * order)))) {
  const int tiles = 12 << (2 * order), rows = (tiles + cols_ - 1) / cols_;
  image_ = Image(cols_ * small_, rows * small_, 1, std::numeric_limits<float>::quiet_NaN());
}

void HipsAllsky::add(std::int64_t npix, const Image& tile) {
  const int f = width_ / small_;
  const int x0 = static_cast<int>(npix % cols_) * small_, y0 = static_cast<int>(npix / cols_) * small_;
  for (int r = 0; r < small_; ++r)
    for (int c = 0; c < small_; ++c) {
      double sum = 0.0;
      int n = 0;
      for (int dr = 0; dr < f; ++dr)
        for (int dc = 0; dc < f; ++dc) {
          const float v = tile.at(0, c * f + dc, r * f + dr);
          if (std::isfinite(v)) sum += v, ++n;
        }
      if (n > 0) image_.at(0, x0 + c, y0 + r) = static_cast<float>(sum / n);
    }
}

void HipsAllsky::write(const fs::path& root, const HipsFormat& format) const {
  write_pair(root / fmt::format("Norder{}", order_) / "Allsky", image_, format);
}

}  // namespace gdp::sky
