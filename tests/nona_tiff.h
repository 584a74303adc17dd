// Writes TIFF layers as Hugin's nona does (cropped, XPOSITION/YPOSITION, PIXAR canvas size) with libtiff.
#pragma once

#include <tiffio.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "gdp/image.h"

namespace gdp::test {

struct NonaPage {
  const Image* image = nullptr;  // RGBA or grey + alpha, values in [0, 1]
  int x = 0, y = 0;              // offset on the canvas, pixels
  int bits = 8;                  // 8, 16 or 32 (float)
};

// One page per entry (a multi-page TIFF for more than one); positions in inches at 150 dpi.
inline void write_nona_tiff(const std::string& path, const std::vector<NonaPage>& pages, int canvas_w, int canvas_h) {
  TIFF* t = TIFFOpen(path.c_str(), "w");
  if (!t) throw std::runtime_error("cannot create " + path);
  for (const NonaPage& p : pages) {
    const Image& img = *p.image;
    const float dpi = 150.0f;
    const std::uint16_t extra[1] = {EXTRASAMPLE_UNASSALPHA};
    TIFFSetField(t, TIFFTAG_IMAGEWIDTH, img.width);
    TIFFSetField(t, TIFFTAG_IMAGELENGTH, img.height);
    TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, img.channels);
    TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, p.bits);
    TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, p.bits == 32 ? SAMPLEFORMAT_IEEEFP : SAMPLEFORMAT_UINT);
    TIFFSetField(t, TIFFTAG_PHOTOMETRIC, img.channels >= 3 ? PHOTOMETRIC_RGB : PHOTOMETRIC_MINISBLACK);
    TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
    TIFFSetField(t, TIFFTAG_EXTRASAMPLES, 1, extra);
    TIFFSetField(t, TIFFTAG_XRESOLUTION, dpi);
    TIFFSetField(t, TIFFTAG_YRESOLUTION, dpi);
    TIFFSetField(t, TIFFTAG_RESOLUTIONUNIT, RESUNIT_INCH);
    TIFFSetField(t, TIFFTAG_XPOSITION, p.x / dpi);
    TIFFSetField(t, TIFFTAG_YPOSITION, p.y / dpi);
    TIFFSetField(t, TIFFTAG_PIXAR_IMAGEFULLWIDTH, canvas_w);
    TIFFSetField(t, TIFFTAG_PIXAR_IMAGEFULLLENGTH, canvas_h);
    const std::size_t bytes = p.bits / 8;
    std::vector<unsigned char> row(static_cast<std::size_t>(img.width) * img.channels * bytes);
    for (int y = 0; y < img.height; ++y) {
      for (int x = 0; x < img.width; ++x)
        for (int c = 0; c < img.channels; ++c) {
          const float v = img.at(c, x, y);
          unsigned char* d = row.data() + (static_cast<std::size_t>(x) * img.channels + c) * bytes;
          if (p.bits == 8) *d = static_cast<unsigned char>(v * 255.0f + 0.5f);
          if (p.bits == 16) {
            const auto s = static_cast<std::uint16_t>(v * 65535.0f + 0.5f);
            std::memcpy(d, &s, 2);
          }
          if (p.bits == 32) std::memcpy(d, &v, 4);
        }
      if (TIFFWriteScanline(t, row.data(), y) < 0) throw std::runtime_error("cannot write " + path);
    }
    TIFFWriteDirectory(t);
  }
  TIFFClose(t);
}

}  // namespace gdp::test
